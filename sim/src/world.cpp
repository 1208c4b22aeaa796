// The synthetic world renderer: see world.h.
//
// Structure. A uniform grid of kCell-metre cells over the map lists, per cell, (1) the paved
// polygons (road areas, intersection shapes) that touch it, each flagged when it covers the whole
// cell, (2) the centre-line segments near enough to decide a point's shoulder side and its
// position along a road, (3) the tree-canopy discs whose shadow touches it. A ground point's
// paved test is then a lookup plus, in boundary cells only, an exact crossing-number test against
// the polygon's edges in a 1 m band of y. Texture is value noise of the world point, its octaves
// faded out where they are finer than the pixel's footprint on the ground (no aliasing far away).
#include "mapnav/sim/world.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>

#include "mapnav/core/options.h"
#include "mapnav/map/predict.h"  // intersectionSurface

namespace mapnav {

namespace {

constexpr double kCell = 3.0;   // grid cell, m
constexpr double kBand = 1.0;   // y-band of a polygon's edge index, m

// ---------------------------------------------------------------------------------------------
// Hashing and noise.

inline std::uint64_t mix64(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}
inline std::uint64_t hash2(std::uint64_t salt, std::int64_t a, std::int64_t b) {
  return mix64(salt ^ (static_cast<std::uint64_t>(a) * 0x9E3779B97F4A7C15ULL) ^
               (static_cast<std::uint64_t>(b) * 0xC2B2AE3D27D4EB4FULL));
}
/// [0, 1)
inline float unit01(std::uint64_t h) { return static_cast<float>(h >> 40) * (1.0f / 16777216.0f); }
/// [-1, 1)
inline float unitSigned(std::uint64_t h) { return unit01(h) * 2.0f - 1.0f; }

/// Smooth value noise in [-1, 1], unit lattice.
float valueNoise(std::uint64_t salt, double x, double y) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  const float tx = static_cast<float>(x - fx), ty = static_cast<float>(y - fy);
  const float ux = tx * tx * (3.0f - 2.0f * tx), uy = ty * ty * (3.0f - 2.0f * ty);
  const float a = unitSigned(hash2(salt, ix, iy)), b = unitSigned(hash2(salt, ix + 1, iy));
  const float c = unitSigned(hash2(salt, ix, iy + 1)), d = unitSigned(hash2(salt, ix + 1, iy + 1));
  const float ab = a + (b - a) * ux, cd = c + (d - c) * ux;
  return ab + (cd - ab) * uy;
}

/// How much of a pattern of `freq` cycles/m survives a pixel `footprint` m wide.
inline float filterWeight(double freq, double footprint) {
  return static_cast<float>(std::clamp(2.0 - 4.0 * freq * footprint, 0.0, 1.0));
}

/// Fractal value noise, octaves from base_freq doubling; octaves finer than the footprint fade out
/// (the result keeps its normalisation, so far away it tends to 0 = the mean colour).
float fbm(std::uint64_t salt, const Vec2& p, double base_freq, int octaves, double footprint) {
  float sum = 0, norm = 0, amp = 1;
  double f = base_freq;
  for (int o = 0; o < octaves; ++o) {
    const float w = filterWeight(f, footprint);
    if (w > 0) sum += amp * w * valueNoise(salt + static_cast<std::uint64_t>(o) * 0x51ED27ULL, p.x() * f, p.y() * f);
    norm += amp;
    amp *= 0.5f;
    f *= 2.0;
  }
  return sum / norm;
}

inline float smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

/// Coverage (0..1) of a dark line of `width` at distance `d` from the pixel centre, for a pixel
/// `footprint` wide (box-filtered).
inline float lineCoverage(double d, double width, double footprint) {
  const double fp = std::max(footprint, 1e-4);
  const double overlap = std::min(d + fp / 2, width / 2) - std::max(d - fp / 2, -width / 2);
  return static_cast<float>(std::clamp(overlap / fp, 0.0, 1.0));
}

/// Thin wandering crack lines: where ridged noise is near zero. Returns coverage 0..1.
float crackCoverage(std::uint64_t salt, const Vec2& p, double footprint, double width) {
  constexpr double kFreq = 0.9;
  if (footprint > 0.08) return 0.0f;
  const double n = valueNoise(salt, p.x() * kFreq, p.y() * kFreq) +
                   0.22 * valueNoise(salt + 7, p.x() * kFreq * 5, p.y() * kFreq * 5) +
                   0.08 * valueNoise(salt + 9, p.x() * kFreq * 23, p.y() * kFreq * 23);
  // |grad| of the noise is ~2.4 × freq per unit: distance to the zero line in metres.
  const double d = std::abs(n) / (2.4 * kFreq);
  return lineCoverage(d, width, footprint) * (1.0f - static_cast<float>(footprint / 0.08));
}

struct C3 {
  float r = 0, g = 0, b = 0;
};
inline C3 operator+(C3 a, C3 b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
inline C3 operator*(C3 a, float k) { return {a.r * k, a.g * k, a.b * k}; }
inline C3 operator*(C3 a, C3 b) { return {a.r * b.r, a.g * b.g, a.b * b.b}; }
inline C3 lerp(C3 a, C3 b, float t) { return a + (b + a * -1.0f) * t; }
inline C3 fromVec(const Vec3& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

// ---------------------------------------------------------------------------------------------
// The map, prepared for lookups.

enum class Material { Concrete, Asphalt, Grass, Dirt, Gravel, Brick, Other };

Material materialOf(const std::string& name) {
  if (name == "concrete") return Material::Concrete;
  if (name == "asphalt") return Material::Asphalt;
  if (name == "grass") return Material::Grass;
  if (name == "dirt") return Material::Dirt;
  if (name == "gravel") return Material::Gravel;
  if (name == "brick") return Material::Brick;
  return Material::Other;
}

struct Surface {
  Material material = Material::Other;
  C3 rgb;
  C3 spread;
};

struct PavedPolygon {
  Polygon2 ring;
  Box2 box;
  double band_y0 = 0;
  std::vector<std::vector<std::uint32_t>> bands;  // per y-band, the edges (start vertex) meeting it
  int surface = 0;
  int road = -1;  // index into roads; -1 for an intersection
};

struct RoadInfo {
  double width = 2;
  int surface = 0, left = 0, right = 0;
};

struct Segment {
  Vec2 a, dir;
  double len = 0, s0 = 0;
  int road = 0;
};

struct Disc {
  Vec2 c;
  double r = 1;
};

struct PolyRef {
  std::uint32_t poly;
  bool whole;
};

bool crossingContains(const PavedPolygon& poly, const Vec2& p) {
  if (!poly.box.contains(p)) return false;
  const auto band = static_cast<std::size_t>(
      std::clamp((p.y() - poly.band_y0) / kBand, 0.0, static_cast<double>(poly.bands.size() - 1)));
  bool inside = false;
  const std::size_t n = poly.ring.size();
  for (std::uint32_t i : poly.bands[band]) {
    const Vec2& a = poly.ring[i];
    const Vec2& b = poly.ring[(i + 1) % n];
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (p.x() < x) inside = !inside;
    }
  }
  return inside;
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

}  // namespace

// ---------------------------------------------------------------------------------------------

void WorldOptions::validate() const {
  constexpr std::string_view kOwner = "WorldOptions";
  auto finiteIn = [](double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; };
  requireOption(finiteIn(pavement_noise, 0, 1e3), kOwner, "pavement_noise", pavement_noise, "finite and >= 0");
  requireOption(finiteIn(slab_spacing_m, 0, 1e3), kOwner, "slab_spacing_m", slab_spacing_m, "finite and >= 0");
  requireOption(finiteIn(slab_gap_width_m, 0, 1e3) && slab_gap_width_m > 0, kOwner, "slab_gap_width_m",
                slab_gap_width_m, "finite and > 0");
  requireOption(finiteIn(slab_gap_darkness, 0, 1), kOwner, "slab_gap_darkness", slab_gap_darkness, "in [0, 1]");
  requireOption(finiteIn(crack_density, 0, 1), kOwner, "crack_density", crack_density, "in [0, 1]");
  requireOption(finiteIn(dust, 0, 1), kOwner, "dust", dust, "in [0, 1]");
  requireOption(finiteIn(ground_noise, 0, 1e3), kOwner, "ground_noise", ground_noise, "finite and >= 0");
  requireOption(finiteIn(shoulder_width_m, 0, 1e3), kOwner, "shoulder_width_m", shoulder_width_m, "finite and >= 0");
  requireOption(finiteIn(shadow_density, 0, 1), kOwner, "shadow_density", shadow_density, "in [0, 1]");
  requireOption(finiteIn(shadow_k, 0, 1) && shadow_k > 0, kOwner, "shadow_k", shadow_k, "in (0, 1]");
  requireOption(finiteIn(shadow_blue_shift, 0, 1) && shadow_blue_shift < 1, kOwner, "shadow_blue_shift",
                shadow_blue_shift, "in [0, 1)");
  requireOption(finiteIn(leaf_density, 0, 1), kOwner, "leaf_density", leaf_density, "in [0, 1]");
  requireOption(finiteIn(illumination_drift, 0, 1) && illumination_drift < 1, kOwner, "illumination_drift",
                illumination_drift, "in [0, 1)");
  requireOption(finiteIn(white_balance_drift, 0, 1) && white_balance_drift < 1, kOwner, "white_balance_drift",
                white_balance_drift, "in [0, 1)");
  requireOption(std::isfinite(illumination_period_s) && illumination_period_s > 0, kOwner, "illumination_period_s",
                illumination_period_s, "finite and > 0");
  requireOption(finiteIn(haze_distance_m, 0, 1e9), kOwner, "haze_distance_m", haze_distance_m, "finite and >= 0");
  requireOption(finiteIn(noise_sigma, 0, 1e3), kOwner, "noise_sigma", noise_sigma, "finite and >= 0");
  requireOption(std::isfinite(tv_hue_shift_rad), kOwner, "tv_hue_shift_rad", tv_hue_shift_rad, "finite");
  requireOption(finiteIn(tv_chroma_gain, 0, 2), kOwner, "tv_chroma_gain", tv_chroma_gain, "in [0, 2]");
  requireOption(paved_edge_samples >= 1 && paved_edge_samples <= 16, kOwner, "paved_edge_samples",
                paved_edge_samples, "in [1, 16]");
  requireOption(tv_chroma_blur_px >= 0 && tv_chroma_blur_px <= 16, kOwner, "tv_chroma_blur_px", tv_chroma_blur_px,
                "in [0, 16]");
}

// ---------------------------------------------------------------------------------------------
// RayTable

RayTable::RayTable(const Camera& camera)
    : model_(camera.model()), intrinsics_(camera.intrinsics()), mount_(camera.mount()),
      width_(camera.width()), height_(camera.height()),
      rays_(static_cast<std::size_t>(width_) * height_) {
  const Vec3 center = camera.center();
  for (int v = 0; v < height_; ++v) {
    for (int u = 0; u < width_; ++u) {
      Ray& r = rays_[static_cast<std::size_t>(v) * width_ + u];
      const Vec2 pixel(u, v);
      const auto dir = camera.ray(pixel);
      if (!dir) continue;
      const auto ground = (dir->z() < 0) ? camera.backproject(pixel) : std::nullopt;
      if (ground) {
        r.kind = Kind::Ground;
        r.x = static_cast<float>(ground->x());
        r.y = static_cast<float>(ground->y());
        r.range = static_cast<float>((Vec3(ground->x(), ground->y(), 0.0) - center).norm());
      } else {
        r.kind = Kind::Sky;
        r.elevation = static_cast<float>(std::asin(std::clamp(dir->z(), -1.0, 1.0)));
      }
    }
  }
  // Footprint: the largest distance to a neighbouring pixel's ground point.
  for (int v = 0; v < height_; ++v) {
    for (int u = 0; u < width_; ++u) {
      Ray& r = rays_[static_cast<std::size_t>(v) * width_ + u];
      if (r.kind != Kind::Ground) continue;
      float fp = 0;
      const std::array<std::pair<int, int>, 4> nb{{{u - 1, v}, {u + 1, v}, {u, v - 1}, {u, v + 1}}};
      for (const auto& [nu, nv] : nb) {
        if (nu < 0 || nv < 0 || nu >= width_ || nv >= height_) continue;
        const Ray& o = rays_[static_cast<std::size_t>(nv) * width_ + nu];
        if (o.kind == Kind::Ground) fp = std::max(fp, std::hypot(o.x - r.x, o.y - r.y));
        else fp = std::max(fp, r.range * 0.05f);  // next to the horizon: very oblique
      }
      r.footprint = fp > 0 ? fp : r.range * 0.01f;
    }
  }
}

bool RayTable::matches(const Camera& camera) const {
  return camera.model() == model_ && camera.intrinsics() == intrinsics_ && camera.mount() == mount_;
}

// ---------------------------------------------------------------------------------------------
// World

struct World::Impl {
  WorldOptions options;
  std::vector<Surface> surfaces;
  int lawn = -1;  // the background surface
  std::vector<RoadInfo> roads;
  std::vector<PavedPolygon> polys;
  std::vector<Segment> segments;
  std::vector<Disc> discs;
  bool shadow_everywhere = false;

  // Grid.
  Vec2 origin = Vec2::Zero();
  int nx = 0, ny = 0;
  std::vector<std::uint32_t> poly_start, seg_start, disc_start;  // CSR offsets, size nx*ny+1
  std::vector<PolyRef> cell_polys;
  std::vector<std::uint32_t> cell_segs, cell_discs;

  mutable std::mutex cache_mutex;
  mutable std::vector<std::shared_ptr<const RayTable>> cache;

  int cellIndex(const Vec2& p) const {
    const double fx = (p.x() - origin.x()) / kCell, fy = (p.y() - origin.y()) / kCell;
    if (!(fx >= 0 && fy >= 0 && fx < nx && fy < ny)) return -1;
    return static_cast<int>(fy) * nx + static_cast<int>(fx);
  }

  Impl(const Map& map, const WorldOptions& opts);
  int surfaceIndex(const Map& map, const std::string& name);
  void buildGrid(const Box2& box);
  void placeTrees(const Map& map);

  /// Index of the paved polygon holding p (roads before intersections), or -1.
  int pavedAt(const Vec2& p, int cell) const;
  double shadowAt(const Vec2& p, int cell, bool with_flecks, double footprint = 0.0) const;
  C3 shade(const Vec2& p, double footprint, double range, bool& paved) const;
  C3 texture(int surface, const Vec2& p, double footprint, double along, double lateral, int road) const;
  C3 sky(double elevation) const;
};

int World::Impl::surfaceIndex(const Map& map, const std::string& name) {
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

World::Impl::Impl(const Map& map, const WorldOptions& opts) : options(opts) {
  options.validate();
  shadow_everywhere = options.shadow_density >= 0.999;
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
  for (PavedPolygon& poly : polys) {
    poly.box = Box2();
    for (const Vec2& v : poly.ring) poly.box.extend(v);
    poly.band_y0 = poly.box.min().y();
    const auto nb = static_cast<std::size_t>(std::floor(poly.box.sizes().y() / kBand)) + 1;
    poly.bands.assign(nb, {});
    const std::size_t n = poly.ring.size();
    for (std::size_t i = 0; i < n; ++i) {
      const double y0 = std::min(poly.ring[i].y(), poly.ring[(i + 1) % n].y());
      const double y1 = std::max(poly.ring[i].y(), poly.ring[(i + 1) % n].y());
      const auto b0 = static_cast<std::size_t>(std::clamp((y0 - poly.band_y0) / kBand, 0.0, double(nb - 1)));
      const auto b1 = static_cast<std::size_t>(std::clamp((y1 - poly.band_y0) / kBand, 0.0, double(nb - 1)));
      for (std::size_t b = b0; b <= b1; ++b) poly.bands[b].push_back(static_cast<std::uint32_t>(i));
    }
  }

  Box2 box = map.bounds();
  const double margin = 2 * max_width + options.shoulder_width_m + 12.0;
  box.extend(box.min() - Vec2(margin, margin));
  box.extend(box.max() + Vec2(margin, margin));
  placeTrees(map);
  buildGrid(box);
}

void World::Impl::placeTrees(const Map& map) {
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
      }
    }
  }
}

void World::Impl::buildGrid(const Box2& box) {
  origin = box.min();
  nx = std::max(1, static_cast<int>(std::ceil(box.sizes().x() / kCell)));
  ny = std::max(1, static_cast<int>(std::ceil(box.sizes().y() / kCell)));
  const std::size_t cells = static_cast<std::size_t>(nx) * ny;
  auto cellRange = [&](const Box2& b, int& x0, int& y0, int& x1, int& y1) {
    x0 = std::clamp(static_cast<int>(std::floor((b.min().x() - origin.x()) / kCell)), 0, nx - 1);
    y0 = std::clamp(static_cast<int>(std::floor((b.min().y() - origin.y()) / kCell)), 0, ny - 1);
    x1 = std::clamp(static_cast<int>(std::floor((b.max().x() - origin.x()) / kCell)), 0, nx - 1);
    y1 = std::clamp(static_cast<int>(std::floor((b.max().y() - origin.y()) / kCell)), 0, ny - 1);
  };
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
  // Discs.
  std::vector<std::vector<std::uint32_t>> dc(cells);
  for (std::size_t di = 0; di < discs.size(); ++di) {
    Box2 b;
    const double r = discs[di].r + 0.2;
    b.extend(discs[di].c - Vec2(r, r));
    b.extend(discs[di].c + Vec2(r, r));
    if (!b.intersects(Box2(origin, origin + Vec2(nx * kCell, ny * kCell)))) continue;
    int x0, y0, x1, y1;
    cellRange(b, x0, y0, x1, y1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) dc[static_cast<std::size_t>(y) * nx + x].push_back(static_cast<std::uint32_t>(di));
  }
  poly_start.assign(cells + 1, 0);
  seg_start.assign(cells + 1, 0);
  disc_start.assign(cells + 1, 0);
  for (std::size_t c = 0; c < cells; ++c) {
    poly_start[c] = static_cast<std::uint32_t>(cell_polys.size());
    cell_polys.insert(cell_polys.end(), pc[c].begin(), pc[c].end());
    seg_start[c] = static_cast<std::uint32_t>(cell_segs.size());
    cell_segs.insert(cell_segs.end(), sc[c].begin(), sc[c].end());
    disc_start[c] = static_cast<std::uint32_t>(cell_discs.size());
    cell_discs.insert(cell_discs.end(), dc[c].begin(), dc[c].end());
  }
  poly_start[cells] = static_cast<std::uint32_t>(cell_polys.size());
  seg_start[cells] = static_cast<std::uint32_t>(cell_segs.size());
  disc_start[cells] = static_cast<std::uint32_t>(cell_discs.size());
}

int World::Impl::pavedAt(const Vec2& p, int cell) const {
  if (cell < 0) return -1;
  int found = -1;
  for (std::uint32_t i = poly_start[static_cast<std::size_t>(cell)]; i < poly_start[static_cast<std::size_t>(cell) + 1]; ++i) {
    const PolyRef ref = cell_polys[i];
    const PavedPolygon& poly = polys[ref.poly];
    if (ref.whole || crossingContains(poly, p)) {
      if (poly.road >= 0) return static_cast<int>(ref.poly);
      if (found < 0) found = static_cast<int>(ref.poly);
    }
  }
  return found;
}

double World::Impl::shadowAt(const Vec2& p, int cell, bool with_flecks, double footprint) const {
  if (shadow_everywhere) return 1.0;
  if (cell < 0) return 0.0;
  float s = 0;
  double wobble = std::numeric_limits<double>::quiet_NaN();
  for (std::uint32_t i = disc_start[static_cast<std::size_t>(cell)]; i < disc_start[static_cast<std::size_t>(cell) + 1]; ++i) {
    const Disc& d = discs[cell_discs[i]];
    double dist = (p - d.c).norm();
    if (dist > d.r + 0.45) continue;
    if (std::isnan(wobble)) {  // ragged, leafy canopy outlines
      wobble = 0.3 * valueNoise(options.seed ^ 0xC4A0ULL, p.x() * 1.3, p.y() * 1.3) +
               0.15 * valueNoise(options.seed ^ 0xC4A1ULL, p.x() * 4.0, p.y() * 4.0);
    }
    dist += wobble;
    s = std::max(s, smoothstep(0.0f, static_cast<float>(std::max(0.25, footprint)), static_cast<float>(d.r - dist)));
    if (s >= 1) break;
  }
  if (s > 0 && with_flecks) {
    // Sun flecks through gaps in the canopy.
    const float n = valueNoise(options.seed ^ 0xF1ECULL, p.x() * 1.7, p.y() * 1.7) +
                    0.5f * valueNoise(options.seed ^ 0xF1EDULL, p.x() * 4.1, p.y() * 4.1);
    s *= 1.0f - 0.9f * smoothstep(0.55f, 0.75f, n) * filterWeight(2.0, footprint);
  }
  return s;
}

C3 World::Impl::sky(double elevation) const {
  const C3 horizon{206, 216, 228}, zenith{92, 138, 204};
  const float t = static_cast<float>(std::pow(std::clamp(std::sin(elevation), 0.0, 1.0), 0.55));
  return lerp(horizon, zenith, t);
}

C3 World::Impl::texture(int surface_index, const Vec2& p, double fp, double along, double lateral, int road) const {
  const Surface& sf = surfaces[static_cast<std::size_t>(surface_index)];
  const std::uint64_t seed = options.seed;
  const auto salt = [&](std::uint64_t k) { return mix64(seed * 0x100000001B3ULL + k); };
  C3 c = sf.rgb;
  switch (sf.material) {
    case Material::Concrete: {
      const auto pn = static_cast<float>(options.pavement_noise);
      // Slabs: along the road (or a world grid in intersections and off-road concrete).
      double slab_u = p.x(), slab_v = p.y();
      bool along_road = road >= 0;
      if (along_road) {
        slab_u = along;
        slab_v = lateral;
      }
      std::int64_t slab_i = 0, slab_j = 0;
      float gap = 0;
      if (options.slab_spacing_m > 0) {
        const double sp = options.slab_spacing_m;
        const double qu = slab_u / sp;
        slab_i = static_cast<std::int64_t>(std::floor(qu));
        const double du = std::abs(qu - std::round(qu)) * sp;
        gap = lineCoverage(du, options.slab_gap_width_m, fp);
        if (!along_road) {
          const double qv = slab_v / sp;
          slab_j = static_cast<std::int64_t>(std::floor(qv));
          const double dv = std::abs(qv - std::round(qv)) * sp;
          gap = std::max(gap, lineCoverage(dv, options.slab_gap_width_m, fp));
        }
      }
      const std::uint64_t slab_hash = hash2(salt(1) + static_cast<std::uint64_t>(road + 1), slab_i, slab_j);
      const float tone = 1.0f + 0.035f * unitSigned(slab_hash) * pn;  // each slab poured apart
      c = c * tone;
      const float mottle = fbm(salt(2), p, 0.7, 4, fp);
      const float grain = fbm(salt(3), p, 30.0, 3, fp);
      c = c + sf.spread * (pn * (1.3f * mottle + 1.4f * grain));
      // Dust and stains, heavier toward the edges.
      if (options.dust > 0) {
        float edge = 0;
        if (along_road) {
          const double half = roads[static_cast<std::size_t>(road)].width / 2;
          edge = smoothstep(0.35f, 0.0f, static_cast<float>(half - std::abs(lateral)));
        }
        const float stain = std::clamp(0.5f + 1.6f * fbm(salt(4), p, 0.35, 3, fp), 0.0f, 1.0f);
        const float amount = static_cast<float>(options.dust) * std::clamp(0.35f * stain * stain + 0.5f * edge, 0.0f, 1.0f);
        c = lerp(c, C3{138, 124, 100}, amount);
      }
      if (options.crack_density > 0 && unit01(mix64(slab_hash)) < options.crack_density) {
        const float cr = crackCoverage(salt(5) + static_cast<std::uint64_t>(slab_i * 31 + slab_j), p, fp, 0.004);
        c = c * (1.0f - 0.45f * cr);
      }
      c = c * (1.0f - static_cast<float>(options.slab_gap_darkness) * gap);
      break;
    }
    case Material::Asphalt: {
      const auto pn = static_cast<float>(options.pavement_noise);
      // Blue-grey to black (the paper's park path): large patches of different wear.
      const float wear = fbm(salt(10), p, 0.12, 3, fp);
      c = c * (1.0f + 0.22f * wear * pn) + C3{-2, 0, 4} * (wear * pn);
      const float mottle = fbm(salt(11), p, 1.5, 3, fp);
      const float grain = fbm(salt(12), p, 40.0, 3, fp);
      c = c + sf.spread * (pn * (0.9f * mottle + 2.2f * grain));
      // Bright aggregate stones.
      if (fp < 0.02) {
        const std::uint64_t h = hash2(salt(13), static_cast<std::int64_t>(std::floor(p.x() * 60)),
                                      static_cast<std::int64_t>(std::floor(p.y() * 60)));
        if (unit01(h) < 0.04f) c = c + C3{16, 16, 15} * (pn * (1.0f - static_cast<float>(fp / 0.02)));
      }
      if (options.crack_density > 0) {
        const float zone = fbm(salt(14), p, 0.08, 2, fp);
        if (zone < static_cast<float>(options.crack_density) * 0.6f - 0.3f) {
          c = c * (1.0f - 0.5f * crackCoverage(salt(15), p, fp, 0.007));
        }
      }
      if (options.dust > 0) {
        const float stain = std::clamp(fbm(salt(16), p, 0.25, 3, fp) * 2.0f, 0.0f, 1.0f);
        c = lerp(c, C3{120, 112, 98}, 0.25f * static_cast<float>(options.dust) * stain);
      }
      break;
    }
    case Material::Grass: {
      const auto gn = static_cast<float>(options.ground_noise);
      const float patch = fbm(salt(20), p, 0.15, 3, fp);
      const float dry = std::clamp(fbm(salt(21), p, 0.3, 3, fp) * 2.5f, 0.0f, 1.0f);
      c = c * (1.0f + 0.3f * patch * gn);
      c = lerp(c, C3{118, 122, 72}, std::min(1.0f, 0.3f + 0.5f * dry) * gn);  // not a golf course
      const float clump = fbm(salt(22), p, 2.5, 3, fp);
      const float tuft = fbm(salt(24), p, 9.0, 2, fp);
      const float blade = fbm(salt(23), p, 40.0, 3, fp);
      c = c * (1.0f + gn * (0.22f * clump + 0.35f * tuft + 0.6f * blade)) + sf.spread * (0.3f * gn * blade);
      break;
    }
    case Material::Dirt: {
      const auto gn = static_cast<float>(options.ground_noise);
      const float m = fbm(salt(30), p, 0.8, 4, fp);
      const float g = fbm(salt(31), p, 25.0, 3, fp);
      c = c + sf.spread * (gn * (1.3f * m + 1.5f * g));
      const float wet = std::clamp(fbm(salt(32), p, 0.2, 2, fp) * 2.0f, 0.0f, 1.0f);
      c = c * (1.0f - 0.25f * wet * gn);
      break;
    }
    case Material::Gravel: {
      const auto gn = static_cast<float>(options.ground_noise);
      const float m = fbm(salt(40), p, 0.5, 3, fp);
      const float g = fbm(salt(41), p, 45.0, 2, fp);
      c = c + sf.spread * (gn * (0.8f * m + 2.2f * g));
      break;
    }
    case Material::Brick: {
      const auto gn = static_cast<float>(options.ground_noise);
      constexpr double kL = 0.2, kH = 0.1, kMortar = 0.012;
      const double row = std::floor(p.y() / kH);
      const double xs = p.x() / kL + 0.5 * std::fmod(std::abs(row), 2.0);
      const double col = std::floor(xs);
      const std::uint64_t h = hash2(salt(50), static_cast<std::int64_t>(col), static_cast<std::int64_t>(row));
      c = c * (1.0f + 0.12f * unitSigned(h) * gn * filterWeight(1 / kL, fp));
      const double dv = std::abs(p.y() / kH - std::round(p.y() / kH)) * kH;
      const double du = std::abs(xs - std::round(xs)) * kL;
      const float mortar = std::max(lineCoverage(dv, kMortar, fp), lineCoverage(du, kMortar, fp));
      c = lerp(c, C3{150, 145, 135}, 0.7f * mortar);
      c = c + sf.spread * (gn * 0.8f * fbm(salt(51), p, 20.0, 2, fp));
      break;
    }
    case Material::Other: {
      const float m = fbm(salt(60), p, 1.0, 5, fp);
      c = c + sf.spread * (2.0f * m * static_cast<float>(options.ground_noise));
      break;
    }
  }
  return c;
}

C3 World::Impl::shade(const Vec2& p, double fp, double range, bool& paved) const {
  const int cell = cellIndex(p);
  const int poly = pavedAt(p, cell);
  paved = poly >= 0;
  // Nearest centre-line segment within reach: the road a point belongs to, its side, arc length.
  double best = std::numeric_limits<double>::infinity(), along = 0, lateral = 0;
  int best_road = -1;
  const int want_road = paved ? polys[static_cast<std::size_t>(poly)].road : -2;
  if (cell >= 0 && !(paved && want_road < 0)) {
    for (std::uint32_t i = seg_start[static_cast<std::size_t>(cell)]; i < seg_start[static_cast<std::size_t>(cell) + 1]; ++i) {
      const Segment& s = segments[cell_segs[i]];
      if (want_road >= 0 && s.road != want_road) continue;
      const Vec2 d = p - s.a;
      const double t = std::clamp(d.dot(s.dir), 0.0, s.len);
      const double dist = (d - s.dir * t).norm();
      if (dist < best) {
        best = dist;
        along = s.s0 + t;
        lateral = cross2(s.dir, d);
        best_road = s.road;
      }
    }
  }
  C3 c;
  if (paved) {
    const PavedPolygon& pp = polys[static_cast<std::size_t>(poly)];
    c = texture(pp.surface, p, fp, along, lateral, pp.road >= 0 && best_road >= 0 ? pp.road : -1);
  } else {
    int surface = lawn;
    if (best_road >= 0) {
      const RoadInfo& r = roads[static_cast<std::size_t>(best_road)];
      const double edge = best - r.width / 2;
      const double wobble = 0.4 * valueNoise(options.seed ^ 0x5B0ULL, p.x() * 0.8, p.y() * 0.8);
      if (edge < options.shoulder_width_m + wobble) surface = lateral > 0 ? r.left : r.right;
    }
    c = texture(surface, p, fp, along, lateral, -1);
    if (best_road >= 0 && surfaces[static_cast<std::size_t>(surface)].material == Material::Grass) {
      // Worn, dusty strip where the lawn meets the pavement.
      const double edge = best - roads[static_cast<std::size_t>(best_road)].width / 2;
      const float worn = smoothstep(0.25f, 0.0f, static_cast<float>(edge)) *
                         (0.5f + 0.5f * valueNoise(options.seed ^ 0xED6EULL, p.x() * 3, p.y() * 3));
      c = lerp(c, C3{112, 108, 78}, 0.5f * worn);
    }
  }
  // Fallen leaves: jittered cells of 0.12 m, more of them under the trees.
  const double tree = shadowAt(p, cell, false);
  if (options.leaf_density > 0) {
    constexpr double kLeafCell = 0.12;
    const double density = std::min(1.0, options.leaf_density * (0.5 + 2.5 * (shadow_everywhere ? 0.2 : tree)));
    static constexpr std::array<C3, 4> kLeaf{{{186, 104, 38}, {196, 156, 58}, {112, 68, 34}, {150, 58, 32}}};
    constexpr double kRadius = 0.04;
    if (fp > kRadius) {
      const float cover = static_cast<float>(density * kPi * kRadius * kRadius * 1.6 / (kLeafCell * kLeafCell));
      c = lerp(c, C3{150, 96, 42}, std::min(cover, 1.0f));
    } else {
      const auto ix = static_cast<std::int64_t>(std::floor(p.x() / kLeafCell));
      const auto iy = static_cast<std::int64_t>(std::floor(p.y() / kLeafCell));
      const std::uint64_t h = hash2(mix64(options.seed ^ 0x1EAFULL), ix, iy);
      if (unit01(h) < density) {
        const std::uint64_t h2 = mix64(h);
        const Vec2 centre((ix + 0.3 + 0.4 * unit01(h2)) * kLeafCell, (iy + 0.3 + 0.4 * unit01(mix64(h2))) * kLeafCell);
        const double ang = unit01(h2 >> 7) * kPi;
        const Vec2 d = p - centre;
        const double a = d.dot(unitVector(ang)), b = cross2(unitVector(ang), d);
        const double e = std::sqrt(a * a / (kRadius * kRadius) + b * b / (0.45 * 0.45 * kRadius * kRadius));
        const float inside = smoothstep(1.0f + static_cast<float>(fp / kRadius), 1.0f, static_cast<float>(e));
        const C3 leaf = kLeaf[(h2 >> 20) % 4] * (0.8f + 0.3f * unit01(h2 >> 3));
        c = lerp(c, leaf, inside);
      }
    }
  }
  // Tree shadow: k·C, tinted toward the skylight.
  const double s = shadow_everywhere ? 1.0 : shadowAt(p, cell, true, fp);
  if (s > 0) {
    const auto k = static_cast<float>(options.shadow_k), b = static_cast<float>(options.shadow_blue_shift);
    const C3 lit{1, 1, 1}, shadow{k * (1 - b), k, k * (1 + b)};
    c = c * lerp(lit, shadow, static_cast<float>(s));
  }
  // Aerial perspective: far ground fades toward the haze of the horizon.
  if (options.haze_distance_m <= 0) return c;
  const float haze = static_cast<float>(1.0 - std::exp(-range / options.haze_distance_m));
  return lerp(c, C3{196, 206, 218}, haze);
}

World::World(const Map& map, const WorldOptions& options) : impl_(std::make_unique<Impl>(map, options)) {}
World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

const WorldOptions& World::options() const { return impl_->options; }

bool World::isPaved(const Vec2& p) const { return impl_->pavedAt(p, impl_->cellIndex(p)) >= 0; }

double World::shadowAt(const Vec2& p) const { return impl_->shadowAt(p, impl_->cellIndex(p), true); }

Frame World::render(const Camera& camera, const Pose2& pose, double t) const {
  std::shared_ptr<const RayTable> table;
  {
    std::lock_guard lock(impl_->cache_mutex);
    auto& cache = impl_->cache;
    for (std::size_t i = 0; i < cache.size(); ++i) {
      if (cache[i]->matches(camera)) {
        table = cache[i];
        std::rotate(cache.begin(), cache.begin() + static_cast<std::ptrdiff_t>(i), cache.begin() + static_cast<std::ptrdiff_t>(i) + 1);
        break;
      }
    }
  }
  if (!table) {
    table = std::make_shared<const RayTable>(camera);
    std::lock_guard lock(impl_->cache_mutex);
    impl_->cache.insert(impl_->cache.begin(), table);
    if (impl_->cache.size() > 4) impl_->cache.pop_back();
  }
  return render(*table, pose, t);
}

Frame World::render(const RayTable& rays, const Pose2& pose, double t) const {
  const Impl& im = *impl_;
  const WorldOptions& o = im.options;
  const int w = rays.width(), h = rays.height();
  const std::size_t n = static_cast<std::size_t>(w) * h;
  Frame frame{Image(w, h, 3), Image(w, h, 1)};
  std::vector<float> buf(n * 3);

  const double ch = std::cos(pose.heading()), sh = std::sin(pose.heading());
  const double tx = pose.x(), ty = pose.y();
  for (std::size_t i = 0; i < n; ++i) {
    const RayTable::Ray& r = rays.rays()[i];
    C3 c;
    if (r.kind == RayTable::Kind::Ground) {
      const Vec2 p(ch * r.x - sh * r.y + tx, sh * r.x + ch * r.y + ty);
      bool paved = false;
      c = im.shade(p, r.footprint, r.range, paved);
      frame.mask.data[i] = paved ? 255 : 0;
    } else if (r.kind == RayTable::Kind::Sky) {
      c = im.sky(r.elevation);
    }
    buf[3 * i] = c.r;
    buf[3 * i + 1] = c.g;
    buf[3 * i + 2] = c.b;
  }
  if (o.paved_edge_samples > 1) {
    // The pixels the paved area's edge crosses: the mean of n × n samples spread over the pixel's
    // ground footprint, its sides taken from the neighbouring pixels' rays (locally affine).
    const int ns = o.paved_edge_samples;
    const auto ground = [&](int u, int v) {
      return u >= 0 && u < w && v >= 0 && v < h && rays.at(u, v).kind == RayTable::Kind::Ground;
    };
    const auto point = [&](int u, int v) { return Vec2(rays.at(u, v).x, rays.at(u, v).y); };
    // Half the step to the next pixel along u (dv = 0) or v, from the neighbours that are ground.
    const auto halfStep = [&](int u, int v, int du, int dv) {
      const bool fwd = ground(u + du, v + dv), back = ground(u - du, v - dv);
      if (fwd && back) return Vec2(0.25 * (point(u + du, v + dv) - point(u - du, v - dv)));
      if (fwd) return Vec2(0.5 * (point(u + du, v + dv) - point(u, v)));
      if (back) return Vec2(0.5 * (point(u, v) - point(u - du, v - dv)));
      return Vec2(0, 0);
    };
    const std::vector<std::uint8_t>& mask = frame.mask.data;  // the centres' classes (mixing leaves them)
    const auto differs = [&](int u, int v, std::uint8_t m) {
      return ground(u, v) && mask[static_cast<std::size_t>(v) * w + u] != m;
    };
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * w + u;
        const std::uint8_t m = mask[i];
        if (!ground(u, v) || !(differs(u - 1, v, m) || differs(u + 1, v, m) || differs(u, v - 1, m) || differs(u, v + 1, m)))
          continue;
        const RayTable::Ray& r = rays.at(u, v);
        const Vec2 su = halfStep(u, v, 1, 0), sv = halfStep(u, v, 0, 1);
        C3 sum{0, 0, 0};
        for (int a = 0; a < ns; ++a)
          for (int b = 0; b < ns; ++b) {
            const double fa = (2.0 * a + 1.0) / ns - 1.0, fb = (2.0 * b + 1.0) / ns - 1.0;  // in (−1, 1)
            const Vec2 q = Vec2(r.x, r.y) + fa * su + fb * sv;
            const Vec2 p(ch * q.x() - sh * q.y() + tx, sh * q.x() + ch * q.y() + ty);
            bool paved = false;
            sum = sum + im.shade(p, r.footprint, r.range, paved);
          }
        const float k = 1.0f / static_cast<float>(ns * ns);
        buf[3 * i] = sum.r * k;
        buf[3 * i + 1] = sum.g * k;
        buf[3 * i + 2] = sum.b * k;
      }
  }

  // Slow drifts of brightness and white balance along the mission.
  const double phase = 2 * kPi * t / o.illumination_period_s;
  const auto gain = static_cast<float>(1.0 + o.illumination_drift * std::sin(phase));
  const auto wb = static_cast<float>(o.white_balance_drift * std::sin(phase / 1.618));
  const std::array<float, 3> g{gain * (1 + wb), gain, gain * (1 - wb)};
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) buf[3 * i + static_cast<std::size_t>(k)] *= g[static_cast<std::size_t>(k)];

  if (o.tv_color_shift) {
    // Chroma (B − Y, R − Y) turned, scaled and smeared along rows, as by the TV link.
    const double theta = o.tv_hue_shift_rad + 0.05 * std::sin(2 * kPi * t / 37.0);
    const auto cs = static_cast<float>(std::cos(theta) * o.tv_chroma_gain);
    const auto sn = static_cast<float>(std::sin(theta) * o.tv_chroma_gain);
    std::vector<float> y(static_cast<std::size_t>(w)), cb(static_cast<std::size_t>(w)), cr(static_cast<std::size_t>(w));
    const int rad = o.tv_chroma_blur_px;
    for (int v = 0; v < h; ++v) {
      float* row = buf.data() + static_cast<std::size_t>(v) * w * 3;
      for (int u = 0; u < w; ++u) {
        const float R = row[3 * u], G = row[3 * u + 1], B = row[3 * u + 2];
        const float Y = 0.299f * R + 0.587f * G + 0.114f * B;
        const float b = B - Y, r = R - Y;
        y[static_cast<std::size_t>(u)] = Y;
        cb[static_cast<std::size_t>(u)] = cs * b - sn * r;
        cr[static_cast<std::size_t>(u)] = sn * b + cs * r;
      }
      for (int u = 0; u < w; ++u) {
        float sb = 0, sr = 0;
        int cnt = 0;
        for (int d = -rad; d <= rad; ++d) {
          const int uu = std::clamp(u + d, 0, w - 1);
          sb += cb[static_cast<std::size_t>(uu)];
          sr += cr[static_cast<std::size_t>(uu)];
          ++cnt;
        }
        const float b = sb / static_cast<float>(cnt), r = sr / static_cast<float>(cnt), Y = y[static_cast<std::size_t>(u)];
        const float R = Y + r, B = Y + b;
        const float G = (Y - 0.299f * R - 0.114f * B) / 0.587f;
        row[3 * u] = R;
        row[3 * u + 1] = G;
        row[3 * u + 2] = B;
      }
    }
  }

  // Sensor noise: seeded per frame (seed, pose, time), ≈ Gaussian (a sum of four uniforms).
  std::uint64_t frame_seed = mix64(o.seed ^ 0x5E45ULL);
  for (double v : {pose.x(), pose.y(), pose.heading(), t}) frame_seed = mix64(frame_seed ^ std::bit_cast<std::uint64_t>(v));
  const auto sigma = static_cast<float>(o.noise_sigma * 1.7320508);  // sum of 4 U(-.5,.5) has sd 1/√3
  const float lo = o.low_dynamic_range ? 37.0f : 0.0f;
  for (std::size_t i = 0; i < n; ++i) {
    const bool lit = rays.rays()[i].kind != RayTable::Kind::None;
    for (std::size_t k = 0; k < 3; ++k) {
      float v = buf[3 * i + k];
      if (sigma > 0 && lit) {
        const std::uint64_t hsh = mix64(frame_seed + (3 * i + k) * 0x9E3779B97F4A7C15ULL);
        const float s = static_cast<float>(hsh & 0xFFFF) + static_cast<float>((hsh >> 16) & 0xFFFF) +
                        static_cast<float>((hsh >> 32) & 0xFFFF) + static_cast<float>(hsh >> 48);
        v += sigma * (s / 65536.0f - 2.0f);
      }
      v = std::clamp(std::round(v), lo, 255.0f);
      frame.rgb.data[3 * i + k] = static_cast<std::uint8_t>(v);
    }
  }
  return frame;
}

}  // namespace mapnav
