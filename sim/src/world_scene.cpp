// The synthetic world's scene: the map's surfaces, paved polygons, centre-line segments and tree
// canopies gathered into the lookup grid (see world_scene.h), and the lookups a ground point needs:
// which paved polygon holds it, how deep in tree shadow it lies.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "mapnav/map/predict.h"  // intersectionSurface
#include "world_scene.h"

namespace mapnav {

using namespace world_detail;

namespace {

Material materialOf(const std::string& name) {
  if (name == "concrete") return Material::Concrete;
  if (name == "asphalt") return Material::Asphalt;
  if (name == "grass") return Material::Grass;
  if (name == "dirt") return Material::Dirt;
  if (name == "gravel") return Material::Gravel;
  if (name == "brick") return Material::Brick;
  return Material::Other;
}

/// A splitmix64 stream for placement (portable, unlike std distributions).
class Stream {
 public:
  explicit Stream(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() { return mix64(state_ += 0x9E3779B97F4A7C15ULL); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * static_cast<double>(next() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t state_;
};

/// The polygon's box and its edges by bands of y (crossingContains).
void indexEdges(PavedPolygon& poly) {
  poly.box = Box2();
  for (const Vec2& v : poly.ring) poly.box.extend(v);
  poly.band_y0 = poly.box.min().y();
  const auto nb = static_cast<std::size_t>(std::floor(poly.box.sizes().y() / kEdgeBand)) + 1;
  std::vector<std::vector<Edge>> bands(nb);
  const std::size_t n = poly.ring.size();
  for (std::size_t i = 0; i < n; ++i) {
    Edge e{poly.ring[i], poly.ring[(i + 1) % n]};
    const double lo = std::min(e.a.x(), e.b.x()), hi = std::max(e.a.x(), e.b.x());
    const double margin = 1e-9 * (std::abs(lo) + std::abs(hi) + 1.0);
    e.x_lo = lo - margin;
    e.x_hi = hi + margin;
    const double y0 = std::min(e.a.y(), e.b.y()), y1 = std::max(e.a.y(), e.b.y());
    const auto b0 = static_cast<std::size_t>(std::clamp((y0 - poly.band_y0) / kEdgeBand, 0.0, double(nb - 1)));
    const auto b1 = static_cast<std::size_t>(std::clamp((y1 - poly.band_y0) / kEdgeBand, 0.0, double(nb - 1)));
    for (std::size_t b = b0; b <= b1; ++b) bands[b].push_back(e);
  }
  poly.band_start.assign(1, 0);
  for (const auto& band : bands) {
    poly.band_edges.insert(poly.band_edges.end(), band.begin(), band.end());
    poly.band_start.push_back(static_cast<std::uint32_t>(poly.band_edges.size()));
  }
}

}  // namespace

bool world_detail::crossingContains(const PavedPolygon& poly, const Vec2& p) {
  if (!poly.box.contains(p)) return false;
  const auto band = static_cast<std::size_t>(
      std::clamp((p.y() - poly.band_y0) / kEdgeBand, 0.0, static_cast<double>(poly.band_start.size() - 2)));
  bool inside = false;
  for (std::uint32_t i = poly.band_start[band]; i < poly.band_start[band + 1]; ++i) {
    const Vec2& a = poly.band_edges[i].a;
    const Vec2& b = poly.band_edges[i].b;
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      // The crossing x lies between a.x and b.x (to a few ulps): beyond its margin the side is plain.
      const Edge& e = poly.band_edges[i];
      if (p.x() < e.x_lo) {
        inside = !inside;
      } else if (p.x() <= e.x_hi) {
        const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
        if (p.x() < x) inside = !inside;
      }
    }
  }
  return inside;
}

int Scene::surfaceIndex(const Map& map, const std::string& name) {
  const Appearance* a = map.findSurface(name);
  Surface s;
  s.material = materialOf(name);
  if (a != nullptr) {
    s.rgb = fromVec(a->rgb);
    s.spread = fromVec(a->spread);
  } else {  // a name the map does not describe: a neutral grey
    s.rgb = {128, 128, 128};
    s.spread = {8, 8, 8};
  }
  surfaces.push_back(s);
  return static_cast<int>(surfaces.size() - 1);
}

Scene::Scene(const Map& map, const WorldOptions& opts) : options(opts) {
  options.validate();
  for (std::size_t k = 0; k < salts.size(); ++k) salts[k] = mix64(options.seed * 0x100000001B3ULL + k);
  shadow_everywhere = options.shadow_density >= 0.999;
  leaf_salt = mix64(options.seed ^ 0x1EAFULL);
  lawn = surfaceIndex(map, map.findSurface("grass") ? "grass" : "");
  if (!map.findSurface("grass")) surfaces[static_cast<std::size_t>(lawn)] = {Material::Grass, {70, 120, 50}, {14, 18, 12}};

  double max_width = 0;
  for (const Road& road : map.roads()) {
    RoadInfo info;
    info.width = road.width;
    info.surface = surfaceIndex(map, road.surface);
    info.left = road.left.empty() ? lawn : surfaceIndex(map, road.left);
    info.right = road.right.empty() ? lawn : surfaceIndex(map, road.right);
    const int r = static_cast<int>(roads.size());
    roads.push_back(info);
    max_width = std::max(max_width, road.width);
    PavedPolygon poly;
    poly.ring = map.roadPolygon(road);
    poly.surface = info.surface;
    poly.road = r;
    polys.push_back(std::move(poly));
    const Polyline2& line = road.centerline;
    for (std::size_t i = 0; i + 1 < line.size(); ++i) {
      Segment s;
      s.a = line.points()[i];
      const Vec2 d = line.points()[i + 1] - s.a;
      s.len = d.norm();
      if (s.len <= 0) continue;
      s.dir = d / s.len;
      s.s0 = line.arcLengthAt(i);
      s.road = r;
      segments.push_back(s);
    }
  }
  for (const Intersection& in : map.intersections()) {
    // Paved as the prediction expects it (the widest road meeting here decides the look).
    const std::string surface = intersectionSurface(map, in);
    const Polygon2& shape = map.intersectionShape(in);
    if (shape.size() < 3) continue;
    PavedPolygon poly;
    poly.ring = shape;
    poly.surface = surface.empty() ? lawn : surfaceIndex(map, surface);
    polys.push_back(std::move(poly));
  }
  for (PavedPolygon& poly : polys) indexEdges(poly);

  Box2 box = map.bounds();
  const double margin = 2 * max_width + options.shoulder_width_m + 12.0;
  box.extend(box.min() - Vec2(margin, margin));
  box.extend(box.max() + Vec2(margin, margin));
  landmarks = Landmarks(map, options);
  for (const GroundMark& m : landmarks.marks) box.extend(m.box);  // the grid holds their shadows too
  placeTrees(map);
  buildGrid(box);
}

void Scene::placeTrees(const Map& map) {
  if (options.shadow_density <= 0 || shadow_everywhere) return;
  Stream rng(mix64(options.seed ^ 0x7EE5ULL));
  constexpr double kClusterArea = 22.0;  // mean area of one canopy, m² (measured for the sizes below)
  const double per_m2 = -std::log(1.0 - options.shadow_density) / kClusterArea;
  for (const Road& road : map.roads()) {
    const double half = road.width / 2 + 6.0;  // the band beside the road where trees stand
    const double length = road.centerline.length();
    const double expected = per_m2 * 2 * half * length;
    auto count = static_cast<long>(expected);
    if (rng.uniform(0, 1) < expected - static_cast<double>(count)) ++count;
    count = std::min(count, 100000L);
    for (long i = 0; i < count; ++i) {
      const double s = rng.uniform(0, length);
      const double lateral = rng.uniform(-half, half);
      const Vec2 centre = road.centerline.pointAt(s) + leftNormal(road.centerline.tangentAt(s)) * lateral;
      const int discs_in_cluster = 3 + static_cast<int>(rng.next() % 4);
      for (int k = 0; k < discs_in_cluster; ++k) {
        const double a = rng.uniform(0, 2 * kPi), d = rng.uniform(0, 1.8);
        discs.push_back({centre + unitVector(a) * d, rng.uniform(1.0, 2.4)});
        const double reach = discs.back().r + 0.45;
        discs.back().reach2 = reach * reach * (1 + 1e-9);
      }
    }
  }
}

void Scene::cellRange(const Box2& b, int& x0, int& y0, int& x1, int& y1) const {
  x0 = std::clamp(static_cast<int>(std::floor((b.min().x() - origin.x()) / kCell)), 0, nx - 1);
  y0 = std::clamp(static_cast<int>(std::floor((b.min().y() - origin.y()) / kCell)), 0, ny - 1);
  x1 = std::clamp(static_cast<int>(std::floor((b.max().x() - origin.x()) / kCell)), 0, nx - 1);
  y1 = std::clamp(static_cast<int>(std::floor((b.max().y() - origin.y()) / kCell)), 0, ny - 1);
}

std::vector<std::vector<PolyRef>> Scene::polygonCells() const {
  const std::size_t cells = static_cast<std::size_t>(nx) * ny;
  // Polygons: cells an edge's box touches are boundary cells; other cells inside are whole.
  std::vector<std::vector<PolyRef>> pc(cells);
  std::vector<int> mark(cells, -1);
  for (std::size_t pi = 0; pi < polys.size(); ++pi) {
    const PavedPolygon& poly = polys[pi];
    const std::size_t n = poly.ring.size();
    for (std::size_t i = 0; i < n; ++i) {
      Box2 eb;
      eb.extend(poly.ring[i]);
      eb.extend(poly.ring[(i + 1) % n]);
      eb.extend(eb.min() - Vec2(1e-6, 1e-6));
      eb.extend(eb.max() + Vec2(1e-6, 1e-6));
      int x0, y0, x1, y1;
      cellRange(eb, x0, y0, x1, y1);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const std::size_t c = static_cast<std::size_t>(y) * nx + x;
          if (mark[c] == static_cast<int>(pi)) continue;
          mark[c] = static_cast<int>(pi);
          pc[c].push_back({static_cast<std::uint32_t>(pi), false});
        }
    }
    int x0, y0, x1, y1;
    cellRange(poly.box, x0, y0, x1, y1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const std::size_t c = static_cast<std::size_t>(y) * nx + x;
        if (mark[c] == static_cast<int>(pi)) continue;
        const Vec2 centre = origin + Vec2((x + 0.5) * kCell, (y + 0.5) * kCell);
        if (crossingContains(poly, centre)) {
          // A whole cell first, so a lookup stops at once.
          pc[c].insert(pc[c].begin(), {static_cast<std::uint32_t>(pi), true});
        }
      }
  }
  return pc;
}

void Scene::buildGrid(const Box2& box) {
  origin = box.min();
  nx = std::max(1, static_cast<int>(std::ceil(box.sizes().x() / kCell)));
  ny = std::max(1, static_cast<int>(std::ceil(box.sizes().y() / kCell)));
  const std::size_t cells = static_cast<std::size_t>(nx) * ny;
  const std::vector<std::vector<PolyRef>> pc = polygonCells();
  // Segments within reach of a cell.
  std::vector<std::vector<std::uint32_t>> sc(cells);
  for (std::size_t si = 0; si < segments.size(); ++si) {
    const Segment& s = segments[si];
    const double reach = 2 * roads[static_cast<std::size_t>(s.road)].width + options.shoulder_width_m + 1.5;
    Box2 b;
    b.extend(s.a);
    b.extend(s.a + s.dir * s.len);
    b.extend(b.min() - Vec2(reach, reach));
    b.extend(b.max() + Vec2(reach, reach));
    int x0, y0, x1, y1;
    cellRange(b, x0, y0, x1, y1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) sc[static_cast<std::size_t>(y) * nx + x].push_back(static_cast<std::uint32_t>(si));
  }
  // Discs and the landmarks' ground marks: the cells their boxes touch.
  const Box2 grid(origin, origin + Vec2(nx * kCell, ny * kCell));
  const auto boxCells = [&](std::size_t n, const auto& boxOf) {
    std::vector<std::vector<std::uint32_t>> lists(cells);
    for (std::size_t i = 0; i < n; ++i) {
      const Box2 b = boxOf(i);
      if (!b.intersects(grid)) continue;
      int x0, y0, x1, y1;
      cellRange(b, x0, y0, x1, y1);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) lists[static_cast<std::size_t>(y) * nx + x].push_back(static_cast<std::uint32_t>(i));
    }
    return lists;
  };
  const auto dc = boxCells(discs.size(), [&](std::size_t di) {
    const double r = discs[di].r + 0.2;
    return Box2(discs[di].c - Vec2(r, r), discs[di].c + Vec2(r, r));
  });
  const auto mc = boxCells(landmarks.marks.size(), [&](std::size_t mi) { return landmarks.marks[mi].box; });
  // Compressed rows: a list's start offset per cell, the lists one after the other.
  const auto compress = [&](const auto& lists, auto& start, auto& flat) {
    start.assign(cells + 1, 0);
    for (std::size_t c = 0; c < cells; ++c) {
      start[c] = static_cast<std::uint32_t>(flat.size());
      flat.insert(flat.end(), lists[c].begin(), lists[c].end());
    }
    start[cells] = static_cast<std::uint32_t>(flat.size());
  };
  compress(pc, poly_start, cell_polys);
  compress(sc, seg_start, cell_segs);
  compress(dc, disc_start, cell_discs);
  compress(mc, mark_start, cell_marks);
}

int Scene::pavedAt(const Vec2& p, const CellLists& lists) const {
  int found = -1;
  for (std::uint32_t i = 0; i < lists.n_polys; ++i) {
    const PolyRef ref = lists.polys[i];
    const PavedPolygon& poly = polys[ref.poly];
    if (ref.whole || crossingContains(poly, p)) {
      if (poly.road >= 0) return static_cast<int>(ref.poly);
      if (found < 0) found = static_cast<int>(ref.poly);
    }
  }
  return found;
}

template <class Wobble>
void Scene::discShadow(const Vec2& p, const CellLists& lists, double footprint, const Wobble& wobbleAt, float& s,
                       float& s_bare) const {
  // The disc edges are smoothed over max(0.25 m, footprint): the same for both unless wide.
  const auto edge = static_cast<float>(std::max(0.25, footprint));
  const bool wide = footprint > 0.25;
  s = s_bare = 0;
  double wobble = std::numeric_limits<double>::quiet_NaN();
  for (std::uint32_t i = 0; i < lists.n_discs; ++i) {
    const Disc& d = discs[lists.discs[i]];
    // Far discs by the squared distance (no root): beyond reach2 the distance exceeds r + 0.45.
    const double d2 = (p - d.c).squaredNorm();
    if (d2 > d.reach2) continue;
    double dist = std::sqrt(d2);  // (p - d.c).norm()
    if (dist > d.r + 0.45) continue;
    if (std::isnan(wobble)) wobble = wobbleAt();  // ragged, leafy canopy outlines
    dist += wobble;
    const auto inside = static_cast<float>(d.r - dist);
    // Outside the disc both smoothsteps are 0 and s, s_bare ≥ 0 stay (s_bare = s unless wide).
    if (!(inside > 0.0f)) continue;
    s = std::max(s, smoothstep(0.0f, edge, inside));
    s_bare = wide ? std::max(s_bare, smoothstep(0.0f, 0.25f, inside)) : s;
    if (s >= 1) break;  // then s_bare >= s is 1 too
  }
}

namespace {

/// The canopy outline's wobble from its two octaves' value noise.
double canopyWobble(float n0, float n1) { return 0.3 * n0 + 0.15 * n1; }

/// Shadow s with the sun flecks of noise n (their two octaves' sum) through a pixel `footprint` wide.
float flecked(float s, float n, double footprint) {
  return s * (1.0f - 0.9f * smoothstep(0.55f, 0.75f, n) * filterWeight(2.0, footprint));
}

// The salts and frequencies of the outline's and the flecks' value noise.
constexpr std::uint64_t kOutlineSalt[2] = {0xC4A0ULL, 0xC4A1ULL}, kFleckSalt[2] = {0xF1ECULL, 0xF1EDULL};
constexpr double kOutlineFreq[2] = {1.3, 4.0}, kFleckFreq[2] = {1.7, 4.1};

}  // namespace

void Scene::canopy(const Vec2& p, const CellLists& lists, double footprint, NoiseCache* nc, float& bare,
                   float& flecked_out) const {
  bare = flecked_out = shadow_everywhere ? 1.0f : 0.0f;
  if (shadow_everywhere || lists.n_discs == 0) return;
  const auto noise = [&](std::uint64_t salt, double f, int channel, int octave) {
    NoiseMemo* memo = channelOf(nc, channel);
    return valueNoise(options.seed ^ salt, p.x() * f, p.y() * f, memo != nullptr ? memo + octave : nullptr);
  };
  float s = 0;
  discShadow(p, lists, footprint, [&] {
    return canopyWobble(noise(kOutlineSalt[0], kOutlineFreq[0], kCanopyChannel, 0),
                        noise(kOutlineSalt[1], kOutlineFreq[1], kCanopyChannel, 1));
  }, s, bare);
  // Sun flecks through gaps in the canopy.
  if (s > 0)
    s = flecked(s, noise(kFleckSalt[0], kFleckFreq[0], kFleckChannel, 0) +
                       0.5f * noise(kFleckSalt[1], kFleckFreq[1], kFleckChannel, 1), footprint);
  flecked_out = s;
}

void Scene::canopyRow(std::size_t w, RowScratch& rs) const {
  rs.tree.assign(w, shadow_everywhere ? 1.0f : 0.0f);
  rs.flecked.assign(w, shadow_everywhere ? 1.0f : 0.0f);
  if (shadow_everywhere) return;
  // The ground pixels with a disc in reach of their tile; their outlines' noise, a row at a time
  // (fbmRow of one octave at footprint 0 is the value noise itself, bit for bit).
  const auto gather = [&](const auto& keep) {
    rs.cand.clear();
    rs.cx.clear();
    rs.cy.clear();
    for (std::size_t u = 0; u < w; ++u)
      if (rs.fp[u] > 0 && keep(u)) {
        rs.cand.push_back(static_cast<std::uint32_t>(u));
        rs.cx.push_back(rs.points[u].x());
        rs.cy.push_back(rs.points[u].y());
      }
    rs.zeros.assign(rs.cand.size(), 0.0f);
    rs.n0.resize(rs.cand.size());
    rs.n1.resize(rs.cand.size());
  };
  const auto noiseRow = [&](const std::uint64_t (&salt)[2], const double (&f)[2]) {
    for (int k = 0; k < 2; ++k)
      fbmRow(options.seed ^ salt[k], rs.cx.data(), rs.cy.data(), rs.zeros.data(), rs.cand.size(), f[k], 1,
             (k == 0 ? rs.n0 : rs.n1).data());
  };
  gather([&](std::size_t u) { return rs.ground[u].lists.n_discs > 0; });
  if (rs.cand.empty()) return;
  noiseRow(kOutlineSalt, kOutlineFreq);
  for (std::size_t j = 0; j < rs.cand.size(); ++j) {
    const std::uint32_t u = rs.cand[j];
    const double fp = rs.fp[u];
    discShadow(rs.points[u], rs.ground[u].lists, fp, [&] { return canopyWobble(rs.n0[j], rs.n1[j]); },
               rs.flecked[u], rs.tree[u]);
  }
  // Sun flecks through gaps in the canopy, where there is shadow.
  gather([&](std::size_t u) { return rs.flecked[u] > 0; });
  if (rs.cand.empty()) return;
  noiseRow(kFleckSalt, kFleckFreq);
  for (std::size_t j = 0; j < rs.cand.size(); ++j) {
    const std::uint32_t u = rs.cand[j];
    rs.flecked[u] = flecked(rs.flecked[u], rs.n0[j] + 0.5f * rs.n1[j], rs.fp[u]);
  }
}

}  // namespace mapnav
