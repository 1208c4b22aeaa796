#include "mapnav/osm/osm_import.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <numeric>
#include <set>
#include <unordered_map>
#include <utility>

#include <osmium/handler.hpp>
#include <osmium/io/any_compression.hpp>
#include <osmium/io/pbf_input.hpp>
#include <osmium/io/xml_input.hpp>
#include <osmium/visitor.hpp>

#include "mapnav/core/error.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/geometry/polyline2.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/map/geodesy.h"
#include "mapnav/map/geojson.h"
#include "osm_internal.h"

namespace mapnav {

IntersectionKind inferIntersectionKind(const std::vector<double>& headings) {
  constexpr double kStraight = 30.0 * std::numbers::pi / 180.0;
  // How far the pair (a, b) is from running straight through: 0 when b = a + pi.
  auto bend = [](double a, double b) { return std::abs(std::remainder(b - a - std::numbers::pi, 2 * std::numbers::pi)); };
  const std::size_t n = headings.size();
  if (n <= 1) return IntersectionKind::End;
  if (n == 2) return bend(headings[0], headings[1]) > kStraight ? IntersectionKind::L : IntersectionKind::Other;
  std::size_t straight_pairs = 0;
  std::vector<bool> used(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      if (!used[i] && !used[j] && bend(headings[i], headings[j]) <= kStraight) {
        used[i] = used[j] = true;
        ++straight_pairs;
      }
    }
  }
  if (n == 3) return straight_pairs >= 1 ? IntersectionKind::T : IntersectionKind::Y;
  if (n == 4 && straight_pairs == 2) return IntersectionKind::Cross;
  return IntersectionKind::Plaza;
}

namespace {

using osm_internal::Cell;
using osm_internal::CellHash;
using osm_internal::cellOf;
using osm_internal::forEachCell;
using osm_internal::LandmarkTags;
using osm_internal::NodeId;
using osm_internal::nodeRef;

struct RawWay {
  NodeId id = 0;
  std::string highway, width, surface, name, oneway, area;
  int layer = 0;
  RoadStructure structure = RoadStructure::None;
  std::vector<NodeId> refs;
};

/// The level a way is on, so that ways on different levels (a bridge over a path) cross without
/// meeting: the `layer` tag when it is an integer, else 1 for a bridge, -1 for a tunnel, 0.
int layerOf(const std::string& layer, const std::string& bridge, const std::string& tunnel) {
  char* end = nullptr;
  const long parsed = std::strtol(layer.c_str(), &end, 10);
  if (!layer.empty() && *end == '\0') return static_cast<int>(parsed);
  if (!bridge.empty() && bridge != "no") return 1;
  if (!tunnel.empty() && tunnel != "no") return -1;
  return 0;
}

/// What carries the way: a bridge (`bridge` other than "no"), a tunnel (`tunnel` other than "no",
/// building passages included, or `covered=yes`: a roof over it hides it from above as a tunnel
/// does), or nothing.
RoadStructure structureOf(const std::string& bridge, const std::string& tunnel, const std::string& covered) {
  if (!bridge.empty() && bridge != "no") return RoadStructure::Bridge;
  if ((!tunnel.empty() && tunnel != "no") || covered == "yes") return RoadStructure::Tunnel;
  return RoadStructure::None;
}

/// A node tagged as a landmark, as read.
struct RawLandmark {
  NodeId id = 0;
  LatLon position;
  LandmarkKind kind = LandmarkKind::Pole;
  LandmarkTags tags;  // those mapnav reads
};

/// Collects the nodes, the landmarks among them and the kept ways of the file.
class Collector : public osmium::handler::Handler {
 public:
  explicit Collector(const std::set<std::string, std::less<>>& highways) : highways_(highways) {}

  void node(const osmium::Node& node) {
    ++nodes_read;
    if (!node.location().valid()) return;
    const LatLon position{node.location().lat(), node.location().lon()};
    nodes.emplace(node.id(), position);
    LandmarkTags tags;
    for (const osmium::Tag& tag : node.tags()) {
      if (osm_internal::isLandmarkKey(tag.key())) tags.emplace_back(tag.key(), tag.value());
    }
    if (const auto kind = osm_internal::landmarkKindOf(tags)) landmarks.push_back({node.id(), position, *kind, std::move(tags)});
  }

  void way(const osmium::Way& way) {
    ++ways_read;
    const char* highway = way.tags()["highway"];
    if (highway == nullptr || !highways_.contains(std::string_view(highway))) return;
    auto tag = [&](const char* key) {
      const char* v = way.tags()[key];
      return std::string(v == nullptr ? "" : v);
    };
    RawWay w;
    w.id = way.id();
    w.highway = highway;
    w.width = tag("width");
    w.surface = tag("surface");
    w.name = tag("name");
    w.oneway = tag("oneway");
    w.area = tag("area");
    w.layer = layerOf(tag("layer"), tag("bridge"), tag("tunnel"));
    w.structure = structureOf(tag("bridge"), tag("tunnel"), tag("covered"));
    for (const osmium::NodeRef& ref : way.nodes()) w.refs.push_back(ref.ref());
    ways.push_back(std::move(w));
  }

  std::size_t nodes_read = 0, ways_read = 0;
  std::unordered_map<NodeId, LatLon> nodes;
  std::vector<RawLandmark> landmarks;
  std::vector<RawWay> ways;

 private:
  const std::set<std::string, std::less<>>& highways_;
};

/// A stretch of a kept way: consecutive nodes present in the file (and inside the bbox).
struct Run {
  std::size_t way = 0;  // index into Collector::ways
  std::vector<NodeId> nodes;
};

/// A road to be: a run cut at the nodes other runs share.
struct Piece {
  std::size_t way = 0;
  std::vector<NodeId> nodes;
  std::string id;  // w<way> or w<way>-<k>
};

std::string wayRef(NodeId id) { return "way/" + std::to_string(id); }

std::string fixed(double v, int decimals = 2) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, v);
  return text;
}

/// Union-find over node ids.
class NodeSets {
 public:
  NodeId find(NodeId id) {
    auto it = parent_.find(id);
    if (it == parent_.end() || it->second == id) return id;
    const NodeId root = find(it->second);
    parent_[id] = root;
    return root;
  }
  /// Joins the sets; the smaller id becomes the representative. False when already joined.
  bool join(NodeId a, NodeId b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (b < a) std::swap(a, b);
    parent_[b] = a;
    return true;
  }

 private:
  std::unordered_map<NodeId, NodeId> parent_;
};

class Importer {
 public:
  Importer(const std::filesystem::path& file, const OsmImportOptions& options) : file_(file), options_(options) {}

  OsmImport run() {
    read();
    makeRuns();
    project();
    mergeCloseNodes();
    joinCrossings();
    makePieces();
    dropDegeneratePieces();
    build();
    addLandmarks();
    return std::move(result_);
  }

 private:
  void read() {
    const std::set<std::string, std::less<>> highways(options_.highways.begin(), options_.highways.end());
    Collector collector(highways);
    try {
      osmium::io::Reader reader(osmium::io::File(file_.string()), osmium::osm_entity_bits::node | osmium::osm_entity_bits::way);
      osmium::apply(reader, collector);
      reader.close();
    } catch (const osmium::xml_error& e) {
      throw IoError(file_.string() + ":" + std::to_string(e.line) + ":" + std::to_string(e.column) +
                    ": malformed OSM XML: " + e.error_string);
    } catch (const std::exception& e) {
      throw IoError(file_.string() + ": cannot read as OpenStreetMap data: " + e.what());
    }
    result_.report.nodes_read = collector.nodes_read;
    result_.report.ways_read = collector.ways_read;
    nodes_ = std::move(collector.nodes);
    landmarks_ = std::move(collector.landmarks);
    ways_ = std::move(collector.ways);
  }

  void warn(std::string check, std::string where, std::string message) {
    addIssue(result_.report.issues, Severity::Warning, std::move(check), std::move(where), std::move(message));
  }

  bool inside(const LatLon& p) const {
    if (!options_.bbox) return true;
    const auto& b = *options_.bbox;
    return p.lon >= b[0] && p.lat >= b[1] && p.lon <= b[2] && p.lat <= b[3];
  }

  void makeRuns() {
    std::set<std::size_t> kept;
    for (std::size_t w = 0; w < ways_.size(); ++w) {
      const RawWay& way = ways_[w];
      if (way.area == "yes") {
        warn("osm.area", wayRef(way.id), "highway=" + way.highway + " area=yes is a paved area, not a way: left out");
        continue;
      }
      Run run{w, {}};
      auto flush = [&] {
        if (run.nodes.size() >= 2) {
          runs_.push_back(run);
          kept.insert(w);
        }
        run.nodes.clear();
      };
      for (const NodeId id : way.refs) {
        const auto it = nodes_.find(id);
        if (it == nodes_.end()) {
          warn("osm.missing_node", wayRef(way.id), "refers to node " + std::to_string(id) + ", which the file does not have: the way is cut there");
          flush();
        } else if (!inside(it->second)) {
          flush();
        } else {
          run.nodes.push_back(id);
        }
      }
      flush();
    }
    result_.report.ways_kept = kept.size();
    if (runs_.empty()) {
      throw InvalidInput(file_.string() + ": no way with highway=" + joinNames(options_.highways) +
                         (options_.bbox ? " inside the bbox" : "") + ": nothing to import");
    }
  }

  static std::string joinNames(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ",") + n;
    return out;
  }

  void project() {
    GeoOrigin origin;
    if (options_.origin) {
      origin = *options_.origin;
    } else {
      double lat_lo = 90, lat_hi = -90, lon_lo = 180, lon_hi = -180;
      for (const Run& run : runs_) {
        for (const NodeId id : run.nodes) {
          const LatLon& p = nodes_.at(id);
          lat_lo = std::min(lat_lo, p.lat);
          lat_hi = std::max(lat_hi, p.lat);
          lon_lo = std::min(lon_lo, p.lon);
          lon_hi = std::max(lon_hi, p.lon);
        }
      }
      // Rounded to 1e-6 degrees (0.1 m) so the origin reads well in the file.
      origin.lat = std::round((lat_lo + lat_hi) / 2 * 1e6) / 1e6;
      origin.lon = std::round((lon_lo + lon_hi) / 2 * 1e6) / 1e6;
    }
    result_.map.origin = origin;
    const LocalFrame frame(origin);
    for (const Run& run : runs_) {
      for (const NodeId id : run.nodes) {
        if (!xy_.contains(id)) xy_.emplace(id, frame.toLocal(nodes_.at(id)));
      }
    }
  }

  /// Distinct nodes closer than merge_distance_m: reported, and with repair made one.
  void mergeCloseNodes() {
    const double d = options_.merge_distance_m;
    if (!(d > 0)) return;
    std::vector<NodeId> ids;
    ids.reserve(xy_.size());
    for (const auto& [id, p] : xy_) ids.push_back(id);
    std::sort(ids.begin(), ids.end());
    std::unordered_map<Cell, std::vector<NodeId>, CellHash> grid;
    for (const NodeId id : ids) grid[cellOf(xy_.at(id), d)].push_back(id);
    NodeSets sets;
    for (const NodeId id : ids) {
      const Vec2& p = xy_.at(id);
      const auto [cx, cy] = cellOf(p, d);
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          const auto it = grid.find({cx + dx, cy + dy});
          if (it == grid.end()) continue;
          for (const NodeId other : it->second) {
            if (other <= id) continue;
            const double distance = (xy_.at(other) - p).norm();
            if (distance >= d) continue;
            if (!options_.repair) {
              warn("osm.duplicate_node", nodeRef(other),
                   "lies " + fixed(distance) + " m from node " + std::to_string(id) +
                       " without being the same node (the import's repair merges them)");
            } else if (sets.join(id, other)) {
              result_.report.repairs.push_back("merged node " + std::to_string(other) + " with node " + std::to_string(id) +
                                               " (" + fixed(distance) + " m apart)");
            }
          }
        }
      }
    }
    if (!options_.repair) return;
    for (Run& run : runs_) {
      std::vector<NodeId> merged;
      for (const NodeId id : run.nodes) {
        const NodeId root = sets.find(id);
        if (merged.empty() || merged.back() != root) merged.push_back(root);
      }
      run.nodes = std::move(merged);
    }
    std::erase_if(runs_, [](const Run& r) { return r.nodes.size() < 2; });
  }

  /// Segments of kept ways on the same layer that cross where neither has a node: reported, and
  /// with repair a new node is put into both.
  void joinCrossings() {
    struct SegmentRef {
      std::size_t run, index;  // nodes[index] → nodes[index + 1]
    };
    constexpr double kCell = 25.0;
    std::unordered_map<Cell, std::vector<SegmentRef>, CellHash> grid;
    auto segment = [&](const SegmentRef& s) {
      const Run& run = runs_[s.run];
      return Segment2{xy_.at(run.nodes[s.index]), xy_.at(run.nodes[s.index + 1])};
    };
    for (std::size_t r = 0; r < runs_.size(); ++r) {
      for (std::size_t i = 0; i + 1 < runs_[r].nodes.size(); ++i) {
        forEachCell(segment({r, i}).bounds(), kCell, [&](const Cell& c) { grid[c].push_back({r, i}); });
      }
    }
    Cuts cuts;
    std::set<std::pair<std::pair<std::size_t, std::size_t>, std::pair<std::size_t, std::size_t>>> seen;
    NodeId next_id = -1;
    for (const auto& [cell, list] : grid) {
      for (std::size_t a = 0; a < list.size(); ++a) {
        for (std::size_t b = a + 1; b < list.size(); ++b) {
          SegmentRef s = list[a], t = list[b];
          if (std::make_pair(t.run, t.index) < std::make_pair(s.run, s.index)) std::swap(s, t);
          if (!seen.insert({{s.run, s.index}, {t.run, t.index}}).second) continue;
          const Run& rs = runs_[s.run];
          const Run& rt = runs_[t.run];
          if (ways_[rs.way].layer != ways_[rt.way].layer) continue;
          // Segments that share a node meet there, as they should.
          const NodeId sa = rs.nodes[s.index], sb = rs.nodes[s.index + 1];
          const NodeId ta = rt.nodes[t.index], tb = rt.nodes[t.index + 1];
          if (sa == ta || sa == tb || sb == ta || sb == tb) continue;
          const Segment2 gs = segment(s), gt = segment(t);
          const auto p = segmentIntersection(gs, gt);
          if (!p) continue;
          const double len_s = gs.length(), len_t = gt.length();
          if (!(len_s > 0) || !(len_t > 0)) continue;
          const double ts = (*p - gs.a).norm() / len_s, tt = (*p - gt.a).norm() / len_t;
          const Vec2 where = *p;
          const NodeId wa = ways_[rs.way].id, wb = ways_[rt.way].id;
          if (!options_.repair) {
            warn("osm.crossing_without_node", wayRef(wa),
                 "crosses way " + std::to_string(wb) + " at (" + fixed(where.x(), 1) + ", " + fixed(where.y(), 1) +
                     ") m where neither has a node (the import's repair adds an intersection)");
            continue;
          }
          const NodeId id = next_id--;
          xy_.emplace(id, where);
          cuts[{s.run, s.index}].push_back({ts, id});
          cuts[{t.run, t.index}].push_back({tt, id});
          result_.report.repairs.push_back("added intersection x" + std::to_string(-id) + " where way " + std::to_string(wa) +
                                           " crosses way " + std::to_string(wb) + " at (" + fixed(where.x(), 1) + ", " +
                                           fixed(where.y(), 1) + ") m");
        }
      }
    }
    insertCuts(cuts);
  }

  /// A node put into a run's segment where another crosses it, at fraction t along the segment.
  struct Cut {
    double t;
    NodeId node;
  };
  using Cuts = std::map<std::pair<std::size_t, std::size_t>, std::vector<Cut>>;  // (run, segment) → new nodes

  void insertCuts(const Cuts& cuts) {
    if (cuts.empty()) return;
    for (std::size_t r = 0; r < runs_.size(); ++r) {
      std::vector<NodeId> nodes;
      for (std::size_t i = 0; i < runs_[r].nodes.size(); ++i) {
        nodes.push_back(runs_[r].nodes[i]);
        const auto it = cuts.find({r, i});
        if (it == cuts.end()) continue;
        std::vector<Cut> list = it->second;
        std::sort(list.begin(), list.end(), [](const Cut& x, const Cut& y) { return x.t < y.t; });
        for (const Cut& c : list) nodes.push_back(c.node);
      }
      runs_[r].nodes = std::move(nodes);
    }
  }

  /// Each run split at every node that another run (or the run itself, again) also uses.
  void makePieces() {
    std::unordered_map<NodeId, int> uses;
    for (const Run& run : runs_) {
      for (const NodeId id : run.nodes) ++uses[id];
    }
    std::map<std::size_t, std::size_t> pieces_of_way;
    for (const Run& run : runs_) {
      Piece piece{run.way, {run.nodes.front()}, ""};
      for (std::size_t i = 1; i < run.nodes.size(); ++i) {
        piece.nodes.push_back(run.nodes[i]);
        if (i + 1 == run.nodes.size() || uses.at(run.nodes[i]) >= 2) {
          pieces_.push_back(piece);
          ++pieces_of_way[run.way];
          piece.nodes = {run.nodes[i]};
        }
      }
    }
    // Ids: w<way> when the way is one piece, else w<way>-1, w<way>-2, ... along it.
    std::map<std::size_t, std::size_t> numbered;
    for (Piece& piece : pieces_) {
      const std::string base = "w" + std::to_string(ways_[piece.way].id);
      piece.id = pieces_of_way.at(piece.way) == 1 ? base : base + "-" + std::to_string(++numbered[piece.way]);
    }
  }

  double pieceLength(const Piece& piece) const {
    double length = 0;
    for (std::size_t i = 1; i < piece.nodes.size(); ++i) length += (xy_.at(piece.nodes[i]) - xy_.at(piece.nodes[i - 1])).norm();
    return length;
  }

  /// Tiny pieces: reported; with repair, stubs and loops among them dropped (a tiny piece between
  /// two junctions stays: dropping it would cut the network; merging its ends is merge_distance_m's).
  void dropDegeneratePieces() {
    std::unordered_map<NodeId, int> degree;
    for (const Piece& p : pieces_) {
      ++degree[p.nodes.front()];
      ++degree[p.nodes.back()];
    }
    std::vector<Piece> kept;
    for (const Piece& p : pieces_) {
      const double length = pieceLength(p);
      if (length >= options_.min_piece_m) {
        kept.push_back(p);
        continue;
      }
      const bool loop = p.nodes.front() == p.nodes.back();
      const bool stub = degree.at(p.nodes.front()) == 1 || degree.at(p.nodes.back()) == 1;
      const NodeId way = ways_[p.way].id;
      if (options_.repair && (loop || stub)) {
        result_.report.repairs.push_back("dropped " + p.id + " (way " + std::to_string(way) + "): " + fixed(length) +
                                         " m " + (loop ? "loop" : "stub"));
        continue;
      }
      const auto [meters, least] = comparedText(length, options_.min_piece_m);
      warn("osm.tiny_piece", wayRef(way),
           "piece " + p.id + " is only " + meters + " m long (< " + least + " m)" +
               (loop || stub ? std::string(" (the import's repair drops it)") : std::string()));
      kept.push_back(p);
    }
    pieces_ = std::move(kept);
  }

  /// The road's surface name among standardSurfaces() from OSM's `surface` (or the highway).
  std::string surfaceOf(const RawWay& way) {
    static const std::map<std::string, std::string, std::less<>> kSurface = {
        {"asphalt", "asphalt"},       {"concrete", "concrete"},     {"concrete:plates", "concrete"},
        {"concrete:lanes", "concrete"}, {"paved", "concrete"},      {"cement", "concrete"},
        {"paving_stones", "brick"},   {"brick", "brick"},           {"sett", "brick"},
        {"cobblestone", "brick"},     {"unhewn_cobblestone", "brick"}, {"gravel", "gravel"},
        {"fine_gravel", "gravel"},    {"compacted", "gravel"},      {"pebblestone", "gravel"},
        {"dirt", "dirt"},             {"ground", "dirt"},           {"earth", "dirt"},
        {"sand", "dirt"},             {"mud", "dirt"},              {"unpaved", "dirt"},
        {"wood", "dirt"},             {"grass", "grass"}};
    if (!way.surface.empty()) {
      const auto it = kSurface.find(way.surface);
      if (it != kSurface.end()) return it->second;
      warn("osm.unknown_surface", wayRef(way.id), "surface=" + way.surface + " is not one mapnav knows: concrete assumed");
      return "concrete";
    }
    if (way.highway == "path") return "gravel";
    if (way.highway == "cycleway") return "asphalt";
    return "concrete";
  }

  double widthOf(const RawWay& way) {
    if (!way.width.empty()) {
      const auto w = osm_internal::parseMetres(way.width);
      if (w && *w > 0 && *w < 100) return *w;
      warn("osm.bad_width", wayRef(way.id), "width=" + way.width + " is not a width in metres: the highway's default used");
    }
    const auto it = options_.widths.find(way.highway);
    return it != options_.widths.end() ? it->second : options_.default_width_m;
  }

  static std::string intersectionId(NodeId id) {
    return id >= 0 ? "n" + std::to_string(id) : "x" + std::to_string(-id);
  }

  void build() {
    MapData& map = result_.map;
    map.name = options_.name.empty() ? "imported from " + file_.filename().string() : options_.name;
    map.surfaces = standardSurfaces();
    map.position_sigma_m = options_.position_sigma_m;
    // Headings leaving each end node, measured 2 m along (short first segments make noisy angles).
    std::map<NodeId, std::vector<double>> headings;
    std::vector<Polyline2> lines;
    for (const Piece& p : pieces_) {
      std::vector<Vec2> points;
      for (const NodeId id : p.nodes) {
        const Vec2& q = xy_.at(id);
        if (points.empty() || (q - points.back()).norm() > 1e-6) points.push_back(q);
      }
      if (points.size() < 2) points.push_back(points.back());  // validation reports the degenerate road
      Polyline2 line(points);
      const double length = line.length();
      if (length > 0) {
        headings[p.nodes.front()].push_back(line.headingAt(std::min(2.0, length / 2)));
        const Vec2 back = line.pointAt(std::max(0.0, length - std::min(2.0, length / 2)));
        const Vec2 d = back - points.back();
        headings[p.nodes.back()].push_back(std::atan2(d.y(), d.x()));
      }
      lines.push_back(std::move(line));
    }
    for (const auto& [id, list] : headings) {
      Intersection x;
      x.id = intersectionId(id);
      x.kind = inferIntersectionKind(list);
      x.position = xy_.at(id);
      if (id >= 0) x.properties["osm_node"] = std::to_string(id);
      map.intersections.push_back(std::move(x));
    }
    std::set<NodeId> steps_reported;
    for (std::size_t i = 0; i < pieces_.size(); ++i) {
      const Piece& p = pieces_[i];
      const RawWay& way = ways_[p.way];
      Road road;
      road.id = p.id;
      road.from = intersectionId(p.nodes.front());
      road.to = intersectionId(p.nodes.back());
      road.centerline = lines[i];
      road.width = widthOf(way);
      road.surface = surfaceOf(way);
      road.left = road.right = options_.shoulder;
      if (way.oneway == "yes" || way.oneway == "true" || way.oneway == "1") road.oneway = true;
      if (way.oneway == "-1") {
        road.oneway = true;
        std::swap(road.from, road.to);
        std::vector<Vec2> reversed = road.centerline.points();
        std::reverse(reversed.begin(), reversed.end());
        road.centerline = Polyline2(reversed);
      }
      if (way.highway == "steps") {
        road.cost_factor = options_.steps_cost_factor;
        if (steps_reported.insert(way.id).second) {
          warn("osm.steps", wayRef(way.id), "steps: kept, with route cost factor " + fixed(options_.steps_cost_factor, 0) +
                                                " so that routes avoid them where they can");
        }
      }
      road.layer = way.layer;
      road.structure = way.structure;
      road.properties["osm_way"] = std::to_string(way.id);
      road.properties["highway"] = way.highway;
      if (!way.name.empty()) road.properties["name"] = way.name;
      if (!way.surface.empty()) road.properties["surface"] = way.surface;
      map.roads.push_back(std::move(road));
    }
  }

  /// The landmark nodes inside the bbox, projected like the rest; those farther than
  /// max_landmark_distance_m from every road's paved area dropped unless keep_far_landmarks.
  void addLandmarks() {
    const LocalFrame frame(*result_.map.origin);
    std::vector<Landmark> found;
    std::vector<Vec2> positions;
    for (const RawLandmark& raw : landmarks_) {
      if (!inside(raw.position)) continue;
      found.push_back(osm_internal::landmarkFromNode(raw.id, raw.kind, frame.toLocal(raw.position), raw.tags,
                                                     result_.report.issues));
      positions.push_back(found.back().position);
    }
    const double reach = options_.max_landmark_distance_m;
    const std::vector<double> distance = osm_internal::distancesToPavedArea(result_.map.roads, positions, reach);
    OsmImportReport& report = result_.report;
    report.landmarks_found = found.size();
    for (std::size_t i = 0; i < found.size(); ++i) {
      const bool far = !(distance[i] <= reach);
      report.landmarks_far += far;
      if (!far || options_.keep_far_landmarks) result_.map.landmarks.push_back(std::move(found[i]));
    }
  }

  std::filesystem::path file_;
  OsmImportOptions options_;
  OsmImport result_;
  std::unordered_map<NodeId, LatLon> nodes_;
  std::vector<RawLandmark> landmarks_;
  std::vector<RawWay> ways_;
  std::vector<Run> runs_;
  std::unordered_map<NodeId, Vec2> xy_;
  std::vector<Piece> pieces_;
};

}  // namespace

bool osmRepairCanFix(std::string_view check) {
  // A same-layer crossing gets an intersection; merged nodes and dropped tiny pieces take away
  // repeated points and degenerate centre lines.
  return check == "roads.crossing_without_intersection" || check == "roads.repeated_point" ||
         check == "roads.too_few_points";
}

OsmImport importOsm(const std::filesystem::path& file, const OsmImportOptions& options) {
  options.validate();
  if (!std::filesystem::is_regular_file(file)) throw IoError(file.string() + ": no such file");
  return Importer(file, options).run();
}

}  // namespace mapnav
