// OpenStreetMap nodes → landmarks: trees, street lamps, benches, bollards, manholes.
#include <algorithm>
#include <array>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <unordered_map>

#include "mapnav/core/strprintf.h"
#include "mapnav/geometry/polyline2.h"
#include "mapnav/geometry/segment2.h"
#include "osm_internal.h"

namespace mapnav::osm_internal {

namespace {

struct KindTag {
  std::string_view key, value;  // value "" : any value but "no"
  LandmarkKind kind;
};
constexpr std::array<KindTag, 6> kKindTags{{{"natural", "tree", LandmarkKind::Tree},
                                            {"highway", "street_lamp", LandmarkKind::Pole},
                                            {"amenity", "bench", LandmarkKind::Bench},
                                            {"barrier", "bollard", LandmarkKind::Bollard},
                                            {"man_made", "manhole", LandmarkKind::Manhole},
                                            {"manhole", "", LandmarkKind::Manhole}}};

// The largest trunk circumference (m) taken from a tag: thicker is a typing slip (centimetres) more
// often than a tree. Heights follow the map's own limit (validation: <= 100 m).
constexpr double kMaxCircumferenceM = 20.0;
constexpr double kMaxHeightM = 100.0;

const std::string* tagValue(const LandmarkTags& tags, std::string_view key) {
  const auto it = std::find_if(tags.begin(), tags.end(), [&](const auto& t) { return t.first == key; });
  return it == tags.end() ? nullptr : &it->second;
}

// A size tag's metres when they lie in (0, max]; else nothing, and an osm.bad_size warning.
std::optional<double> sizeTag(const LandmarkTags& tags, std::string_view key, double max, NodeId node, Issues& issues) {
  const std::string* text = tagValue(tags, key);
  if (text == nullptr) return std::nullopt;
  const auto metres = parseMetres(*text);
  if (metres && *metres > 0 && *metres <= max) return metres;
  addIssue(issues, Severity::Warning, "osm.bad_size", nodeRef(node),
           std::string(key) + "=" + *text + " is not a length in (0, " + strprintf("%g", max) +
               "] m: the landmark's default size used");
  return std::nullopt;
}

}  // namespace

std::optional<double> parseMetres(std::string text) {
  if (text.size() > 1 && text.ends_with("m")) text.pop_back();
  while (!text.empty() && text.back() == ' ') text.pop_back();
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end == nullptr || *end != '\0' || !std::isfinite(value)) return std::nullopt;
  return value;
}

bool isLandmarkKey(std::string_view key) {
  return key == "circumference" || key == "height" ||
         std::any_of(kKindTags.begin(), kKindTags.end(), [&](const KindTag& t) { return t.key == key; });
}

std::optional<LandmarkKind> landmarkKindOf(const LandmarkTags& tags) {
  for (const KindTag& t : kKindTags) {
    const std::string* value = tagValue(tags, t.key);
    if (value != nullptr && (t.value.empty() ? *value != "no" : *value == t.value)) return t.kind;
  }
  return std::nullopt;
}

Landmark landmarkFromNode(NodeId node, LandmarkKind kind, const Vec2& position, const LandmarkTags& tags, Issues& issues) {
  const LandmarkSize size = defaultLandmarkSize(kind);
  Landmark l;
  l.id = std::string(toString(kind)) + std::to_string(node);
  l.kind = kind;
  l.position = position;
  l.radius = size.radius_m;
  l.height = size.height_m;
  if (kind == LandmarkKind::Tree) {
    if (const auto c = sizeTag(tags, "circumference", kMaxCircumferenceM, node, issues)) l.radius = *c / (2 * std::numbers::pi);
  }
  if (isUpright(kind)) {
    if (const auto h = sizeTag(tags, "height", kMaxHeightM, node, issues)) l.height = *h;
  }
  l.properties["osm_node"] = std::to_string(node);
  for (const auto& [key, value] : tags) l.properties[key] = value;
  return l;
}

std::vector<double> distancesToPavedArea(const std::vector<Road>& roads, const std::vector<Vec2>& points, double reach) {
  double widest = 0;
  for (const Road& r : roads) widest = std::max(widest, r.width);
  // A segment whose paved area is within `reach` of a point lies in the cells the box of half side
  // `cell` about the point meets.
  const double cell = std::max(reach + widest / 2, 10.0);
  std::unordered_map<Cell, std::vector<std::pair<std::size_t, std::size_t>>, CellHash> grid;  // → (road, segment)
  for (std::size_t r = 0; r < roads.size(); ++r) {
    const Polyline2& line = roads[r].centerline;
    for (std::size_t s = 0; s < line.segmentCount(); ++s) {
      forEachCell(line.segment(s).bounds(), cell, [&](const Cell& c) { grid[c].emplace_back(r, s); });
    }
  }
  std::vector<double> out;
  out.reserve(points.size());
  for (const Vec2& p : points) {
    double best = std::numeric_limits<double>::infinity();
    forEachCell(Box2(p - Vec2::Constant(cell), p + Vec2::Constant(cell)), cell, [&](const Cell& c) {
      const auto it = grid.find(c);
      if (it == grid.end()) return;
      for (const auto& [r, s] : it->second) {
        best = std::min(best, roads[r].centerline.segment(s).distanceTo(p) - roads[r].width / 2);
      }
    });
    out.push_back(best <= reach ? best : std::numeric_limits<double>::infinity());
  }
  return out;
}

}  // namespace mapnav::osm_internal
