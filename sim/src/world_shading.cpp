// The synthetic world's shading (world_detail::Shading, world_scene.h): the colour of a ground point
// (its surface's procedural texture, the shoulder beside a road, fallen leaves, tree shadow, haze)
// and of the sky; and the same for a row of located ground points at once, the textures' fractal
// sums evaluated channel by channel (textureSums, addPoint, shadeLocated), as the renderer's rows and
// the texel tiles shade them. Texture is value noise of the world point, its octaves faded out where
// they are finer than the pixel's footprint on the ground (no aliasing far away).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "world_scene.h"

namespace mapnav {

using namespace world_detail;

C3 Shading::sky(double elevation) const {
  const C3 horizon{206, 216, 228}, zenith{92, 138, 204};
  const float t = static_cast<float>(std::pow(std::clamp(std::sin(elevation), 0.0, 1.0), 0.55));
  return lerp(horizon, zenith, t);
}

template <class Noise>
C3 Shading::concreteTexture(const Surface& sf, const Vec2& p, double fp, double along, double lateral, int road,
                            const Noise& noise, NoiseCache* nc) const {
  const auto salt = [&](int k) { return salts[static_cast<std::size_t>(k)]; };
  C3 c = sf.rgb;
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
    slab_i = static_cast<std::int64_t>(floorInline(qu));
    const double du = distanceToWhole(qu) * sp;
    gap = lineCoverage(du, options.slab_gap_width_m, fp);
    if (!along_road) {
      const double qv = slab_v / sp;
      slab_j = static_cast<std::int64_t>(floorInline(qv));
      const double dv = distanceToWhole(qv) * sp;
      gap = std::max(gap, lineCoverage(dv, options.slab_gap_width_m, fp));
    }
  }
  const std::uint64_t slab_hash =
      hash2(salt(1) + static_cast<std::uint64_t>(road + 1), slab_i, slab_j, nc != nullptr ? &nc->slab : nullptr);
  const float tone = 1.0f + 0.035f * unitSigned(slab_hash) * pn;  // each slab poured apart
  c = c * tone;
  const float mottle = noise(2);
  const float grain = noise(3);
  c = c + sf.spread * (pn * (1.3f * mottle + 1.4f * grain));
  // Dust and stains, heavier toward the edges.
  if (options.dust > 0) {
    float edge = 0;
    if (along_road) {
      const double half = roads[static_cast<std::size_t>(road)].width / 2;
      edge = smoothstep(0.35f, 0.0f, static_cast<float>(half - std::abs(lateral)));
    }
    const float stain = std::clamp(0.5f + 1.6f * noise(4), 0.0f, 1.0f);
    const float amount = static_cast<float>(options.dust) * std::clamp(0.35f * stain * stain + 0.5f * edge, 0.0f, 1.0f);
    c = lerp(c, C3{138, 124, 100}, amount);
  }
  if (options.crack_density > 0 && unit01(mix64(slab_hash)) < options.crack_density) {
    const float cr = crackCoverage(salt(5) + static_cast<std::uint64_t>(slab_i * 31 + slab_j), p, fp, 0.004, channelOf(nc, 5));
    c = c * (1.0f - 0.45f * cr);
  }
  c = c * (1.0f - static_cast<float>(options.slab_gap_darkness) * gap);
  return c;
}

template <class Noise>
C3 Shading::asphaltTexture(const Surface& sf, const Vec2& p, double fp, const Noise& noise, NoiseCache* nc) const {
  const auto salt = [&](int k) { return salts[static_cast<std::size_t>(k)]; };
  C3 c = sf.rgb;
  const auto pn = static_cast<float>(options.pavement_noise);
  // Blue-grey to black (the paper's park path): large patches of different wear.
  const float wear = noise(10);
  c = c * (1.0f + 0.22f * wear * pn) + C3{-2, 0, 4} * (wear * pn);
  const float mottle = noise(11);
  const float grain = noise(12);
  c = c + sf.spread * (pn * (0.9f * mottle + 2.2f * grain));
  // Bright aggregate stones.
  if (fp < 0.02) {
    const std::uint64_t h = hash2(salt(13), static_cast<std::int64_t>(std::floor(p.x() * 60)),
                                  static_cast<std::int64_t>(std::floor(p.y() * 60)));
    if (unit01(h) < 0.04f) c = c + C3{16, 16, 15} * (pn * (1.0f - static_cast<float>(fp / 0.02)));
  }
  if (options.crack_density > 0) {
    const float zone = noise(14);
    if (zone < static_cast<float>(options.crack_density) * 0.6f - 0.3f) {
      c = c * (1.0f - 0.5f * crackCoverage(salt(15), p, fp, 0.007, channelOf(nc, 15)));
    }
  }
  if (options.dust > 0) {
    const float stain = std::clamp(noise(16) * 2.0f, 0.0f, 1.0f);
    c = lerp(c, C3{120, 112, 98}, 0.25f * static_cast<float>(options.dust) * stain);
  }
  return c;
}

template <class Noise>
C3 Shading::texture(int surface_index, const Vec2& p, double fp, double along, double lateral, int road,
                    const Noise& noise, NoiseCache* nc) const {
  const Surface& sf = surfaces[static_cast<std::size_t>(surface_index)];
  const auto salt = [&](int k) { return salts[static_cast<std::size_t>(k)]; };
  C3 c = sf.rgb;
  switch (sf.material) {
    case Material::Concrete:
      c = concreteTexture(sf, p, fp, along, lateral, road, noise, nc);
      break;
    case Material::Asphalt:
      c = asphaltTexture(sf, p, fp, noise, nc);
      break;
    case Material::Grass: {
      const auto gn = static_cast<float>(options.ground_noise);
      const float patch = noise(20);
      const float dry = std::clamp(noise(21) * 2.5f, 0.0f, 1.0f);
      c = c * (1.0f + 0.3f * patch * gn);
      c = lerp(c, C3{118, 122, 72}, std::min(1.0f, 0.3f + 0.5f * dry) * gn);  // not a golf course
      const float clump = noise(22);
      const float tuft = noise(24);
      const float blade = noise(23);
      c = c * (1.0f + gn * (0.22f * clump + 0.35f * tuft + 0.6f * blade)) + sf.spread * (0.3f * gn * blade);
      break;
    }
    case Material::Dirt: {
      const auto gn = static_cast<float>(options.ground_noise);
      const float m = noise(30);
      const float g = noise(31);
      c = c + sf.spread * (gn * (1.3f * m + 1.5f * g));
      const float wet = std::clamp(noise(32) * 2.0f, 0.0f, 1.0f);
      c = c * (1.0f - 0.25f * wet * gn);
      break;
    }
    case Material::Gravel: {
      const auto gn = static_cast<float>(options.ground_noise);
      const float m = noise(40);
      const float g = noise(41);
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
      c = c + sf.spread * (gn * 0.8f * noise(51));
      break;
    }
    case Material::Other: {
      const float m = noise(60);
      c = c + sf.spread * (2.0f * m * static_cast<float>(options.ground_noise));
      break;
    }
  }
  return c;
}

void Shading::locate(const Vec2& p, const CellLists& lists, NoiseCache* nc, GroundPoint& g) const {
  const int poly = pavedAt(p, lists);
  g.lists = lists;
  g.paved = poly >= 0;
  // Nearest centre-line segment within reach: the road a point belongs to, its side, arc length.
  double best = std::numeric_limits<double>::infinity(), along = 0, lateral = 0;
  double best2 = best;  // best², the root taken only of a nearer square (the root is monotone)
  int best_road = -1;
  const int want_road = g.paved ? polys[static_cast<std::size_t>(poly)].road : -2;
  if (!(g.paved && want_road < 0)) {
    for (std::uint32_t i = 0; i < lists.n_segs; ++i) {
      const Segment& s = segments[lists.segs[i]];
      if (want_road >= 0 && s.road != want_road) continue;
      const Vec2 d = p - s.a;
      const double t = std::clamp(d.dot(s.dir), 0.0, s.len);
      const double d2 = (d - s.dir * t).squaredNorm();
      if (!(d2 < best2)) continue;  // then its norm is not below best
      const double dist = std::sqrt(d2);
      if (dist < best) {
        best = dist;
        best2 = d2;
        along = s.s0 + t;
        lateral = cross2(s.dir, d);
        best_road = s.road;
      }
    }
  }
  g.along = along;
  g.lateral = lateral;
  g.best = best;
  g.best_road = best_road;
  if (g.paved) {
    const PavedPolygon& pp = polys[static_cast<std::size_t>(poly)];
    g.surface = pp.surface;
    g.texture_road = pp.road >= 0 && best_road >= 0 ? pp.road : -1;
    return;
  }
  g.surface = lawn;
  g.texture_road = -1;
  if (best_road >= 0) {
    const RoadInfo& r = roads[static_cast<std::size_t>(best_road)];
    const double edge = best - r.width / 2;
    // The ragged edge moves the shoulder's end by 0.4 m at most: its noise only where that decides.
    const double reach = options.shoulder_width_m;
    bool shoulder = edge < reach - 0.4 - 1e-6;
    if (!shoulder && edge < reach + 0.4 + 1e-6) {
      const double wobble = 0.4 * valueNoise(options.seed ^ 0x5B0ULL, p.x() * 0.8, p.y() * 0.8, channelOf(nc, kWobbleChannel));
      shoulder = edge < reach + wobble;
    }
    if (shoulder) g.surface = lateral > 0 ? r.left : r.right;
  }
}

C3 Shading::shade(const Vec2& p, double fp, double range, bool& paved, NoiseCache* nc) const {
  GroundPoint g;
  locate(p, cellLists(cellIndex(p)), nc, g);
  paved = g.paved;
  C3 c = texture(g.surface, p, fp, g.along, g.lateral, g.texture_road, PointNoise{salts.data(), p, fp, nc}, nc);
  float tree = 0, flecked = 0;  // tree shadow: at the point (leaves fall there), and as seen
  canopy(p, g.lists, fp, nc, tree, flecked);
  if (g.lists.n_marks > 0)  // the landmarks' shadows and covers
    flecked = std::max(flecked, landmarks.marksAt(p, g.lists.marks, g.lists.n_marks, fp, &c, nullptr));
  return finish(p, g, c, fp, options.haze_distance_m > 0 ? hazeAt(range) : 0.0f, tree, flecked, nc);
}

float Shading::hazeAt(double range) const {
  return static_cast<float>(1.0 - std::exp(-range / options.haze_distance_m));
}

C3 Shading::finish(const Vec2& p, const GroundPoint& g, C3 c, double fp, float haze, float tree, float flecked,
                   NoiseCache* nc) const {
  return hazed(shadowed(surfaceFinish(p, g, c, fp, tree, nc), flecked), haze);
}

C3 Shading::surfaceFinish(const Vec2& p, const GroundPoint& g, C3 c, double fp, float tree, NoiseCache* nc) const {
  if (!g.paved && g.best_road >= 0 && surfaces[static_cast<std::size_t>(g.surface)].material == Material::Grass) {
    // Worn, dusty strip where the lawn meets the pavement.
    // (Beyond 0.25 m the smoothstep is 0 and the colour stays: no noise there.)
    const auto edge = static_cast<float>(g.best - roads[static_cast<std::size_t>(g.best_road)].width / 2);
    if (edge < 0.25f) {
      const float worn = smoothstep(0.25f, 0.0f, edge) *
                         (0.5f + 0.5f * valueNoise(options.seed ^ 0xED6EULL, p.x() * 3, p.y() * 3, channelOf(nc, kWornChannel)));
      c = lerp(c, C3{112, 108, 78}, 0.5f * worn);
    }
  }
  // Fallen leaves: jittered cells of 0.12 m, more of them under the trees.
  if (options.leaf_density > 0) {
    constexpr double kLeafCell = 0.12;
    const double density = std::min(1.0, options.leaf_density * (0.5 + 2.5 * (shadow_everywhere ? 0.2 : tree)));
    static constexpr std::array<C3, 4> kLeaf{{{186, 104, 38}, {196, 156, 58}, {112, 68, 34}, {150, 58, 32}}};
    constexpr double kRadius = 0.04;
    if (fp > kRadius) {
      const float cover = static_cast<float>(density * kPi * kRadius * kRadius * 1.6 / (kLeafCell * kLeafCell));
      c = lerp(c, C3{150, 96, 42}, std::min(cover, 1.0f));
    } else {
      const auto ix = static_cast<std::int64_t>(floorInline(p.x() / kLeafCell));
      const auto iy = static_cast<std::int64_t>(floorInline(p.y() / kLeafCell));
      const std::uint64_t h = hash2(leaf_salt, ix, iy, nc != nullptr ? &nc->leaf : nullptr);
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
  return c;
}

void Shading::textureSums(std::size_t w, RowScratch& rs) const {
  for (int m = 0; m < kMaterials; ++m) {
    const std::vector<std::uint32_t>& group = rs.group[static_cast<std::size_t>(m)];
    if (group.empty()) continue;
    const std::size_t n = group.size();
    rs.xs.resize(n);
    rs.ys.resize(n);
    rs.footprints.resize(n);
    rs.sums.resize(n);
    for (std::size_t j = 0; j < n; ++j) {
      rs.xs[j] = rs.points[group[j]].x();
      rs.ys[j] = rs.points[group[j]].y();
      rs.footprints[j] = rs.fp[group[j]];
    }
    for (int k : materialChannels(static_cast<Material>(m))) {
      if (k == 0) break;
      const FbmSpec spec = fbmSpec(k);
      fbmRow(salts[static_cast<std::size_t>(k)], rs.xs.data(), rs.ys.data(), rs.footprints.data(), n, spec.base_freq,
             spec.octaves, rs.sums.data());
      float* values = rs.values.data() + static_cast<std::size_t>(k) * w;
      for (std::size_t j = 0; j < n; ++j) values[group[j]] = rs.sums[j];
    }
  }
}

void Shading::addPoint(RowScratch& rs, std::size_t u, const Vec2& p, float footprint, const CellLists& lists,
                       NoiseCache& nc) const {
  rs.points[u] = p;
  rs.fp[u] = footprint;
  locate(p, lists, &nc, rs.ground[u]);
  const Material m = surfaces[static_cast<std::size_t>(rs.ground[u].surface)].material;
  rs.group[static_cast<std::size_t>(m)].push_back(static_cast<std::uint32_t>(u));
}

void Shading::shadeLocated(std::size_t w, RowScratch& rs, NoiseCache& nc, const float* haze, float* rgb,
                           float* shadows, const LandmarkView* view, std::uint8_t* lmask) const {
  rs.values.resize(static_cast<std::size_t>(NoiseCache::kChannels) * w);
  canopyRow(w, rs);
  textureSums(w, rs);
  // Each ground point's texture from those sums, then its edge, leaves, shadow and haze.
  for (const auto& group : rs.group)
    for (std::uint32_t u : group) {
      const GroundPoint& g = rs.ground[u];
      const Vec2& p = rs.points[u];
      const float fp = rs.fp[u];
      C3 c = texture(g.surface, p, fp, g.along, g.lateral, g.texture_road, RowNoise{rs.values.data(), w, u}, &nc);
      float shadow = rs.flecked[u];
      if (g.lists.n_marks > 0) {  // the landmarks' shadows and covers
        int cover = -1;
        shadow = std::max(shadow, landmarks.marksAt(p, g.lists.marks, g.lists.n_marks, fp, &c, &cover));
        if (cover >= 0 && lmask != nullptr) {
          lmask[u] = kShowsCover;
          if (const int slot = view != nullptr ? view->slot(static_cast<std::uint32_t>(cover)) : -1; slot >= 0)
            ++rs.shown[static_cast<std::size_t>(slot)];
        }
      }
      if (shadows != nullptr) {
        c = surfaceFinish(p, g, c, fp, rs.tree[u], &nc);
        shadows[u] = shadow;
      } else {
        c = finish(p, g, c, fp, haze != nullptr ? haze[u] : 0.0f, rs.tree[u], shadow, &nc);
      }
      rgb[3 * u] = c.r;
      rgb[3 * u + 1] = c.g;
      rgb[3 * u + 2] = c.b;
    }
}

template C3 Shading::texture<PointNoise>(int, const Vec2&, double, double, double, int, const PointNoise&,
                                         NoiseCache*) const;
template C3 Shading::texture<RowNoise>(int, const Vec2&, double, double, double, int, const RowNoise&,
                                       NoiseCache*) const;

}  // namespace mapnav
