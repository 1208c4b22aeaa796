// The ground's colour kept in world space across frames (world_texels.h): the cache, a tile's
// shading and a pixel's samples of two levels.
#include "world_texels.h"

#include <algorithm>
#include <cmath>

#include "world_scene.h"

namespace mapnav {

using namespace world_detail;

namespace world_detail {

std::shared_ptr<const TexelTile> TexelCache::find(std::uint64_t key) {
  const std::lock_guard lock(mutex_);
  const auto it = tiles_.find(key);
  if (it == tiles_.end()) return nullptr;
  it->second.used = frame_;
  return it->second.tile;
}

std::shared_ptr<const TexelTile> TexelCache::insert(std::uint64_t key, std::shared_ptr<const TexelTile> tile) {
  const std::lock_guard lock(mutex_);
  Entry& e = tiles_[key];
  if (!e.tile) e.tile = std::move(tile);
  e.used = frame_;
  return e.tile;
}

void TexelCache::endFrame() {
  const std::lock_guard lock(mutex_);
  ++frame_;
  if (tiles_.size() <= max_tiles_) return;
  // The least recently used go first; among tiles of one frame, by key (the same every run).
  std::vector<std::pair<std::uint64_t, std::uint64_t>> order;  // (used, key)
  order.reserve(tiles_.size());
  for (const auto& [key, e] : tiles_) order.emplace_back(e.used, key);
  const std::size_t drop = tiles_.size() - max_tiles_;
  std::nth_element(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(drop), order.end());
  for (std::size_t k = 0; k < drop; ++k) tiles_.erase(order[k].second);
}

std::size_t TexelCache::size() const {
  const std::lock_guard lock(mutex_);
  return tiles_.size();
}

}  // namespace world_detail

namespace {

/// Level L's texel spacing s_L, m.
double texelSpacing(int level) { return std::ldexp(kTexel0, level); }

/// 1 / s_L per level.
const std::array<double, kTexelLevels> kInvSpacing = [] {
  std::array<double, kTexelLevels> a{};
  for (int l = 0; l < kTexelLevels; ++l) a[static_cast<std::size_t>(l)] = 1.0 / texelSpacing(l);
  return a;
}();

/// Texel coordinates are offset by 2^31 so that truncation is floor (|x| / s_0 < 2^31: 2000 km).
constexpr double kTexelOffset = 2147483648.0;

}  // namespace

const TexelTile* Shading::texelTile(int level, std::int64_t tx, std::int64_t ty, TexelReader& rd,
                                    NoiseCache& nc) const {
  const std::uint64_t key = texelKey(level, tx, ty);
  std::shared_ptr<const TexelTile> tile = rd.cache->find(key);
  if (!tile) {
    // The tile's grid points as one row of located points (row by row, so that neighbours follow
    // each other), shaded as a pixel s_L wide sees them, without the landmarks' marks and haze.
    auto fresh = std::make_shared<TexelTile>();
    RowScratch& rs = rd.scratch;
    const double s = texelSpacing(level);
    constexpr std::size_t n = static_cast<std::size_t>(kTexelSide) * kTexelSide;
    rs.begin(n);
    clearTiles(rd.lists);
    addTile(Box2(Vec2(static_cast<double>(tx * kTexelTile) * s, static_cast<double>(ty * kTexelTile) * s),
                 Vec2(static_cast<double>((tx + 1) * kTexelTile) * s, static_cast<double>((ty + 1) * kTexelTile) * s)),
            rd.lists);
    for (std::size_t k = 0; k < n; ++k) {
      const auto i = static_cast<std::int64_t>(k % kTexelSide), j = static_cast<std::int64_t>(k / kTexelSide);
      const Vec2 p(static_cast<double>(tx * kTexelTile + i) * s, static_cast<double>(ty * kTexelTile + j) * s);
      addPoint(rs, k, p, static_cast<float>(s), tileLists(rd.lists, 0, p), nc);
      rs.ground[k].lists.n_marks = 0;  // the pixels add the landmarks' marks
    }
    rs.rgb.resize(3 * n);
    rs.shadows.resize(n);
    shadeLocated(n, rs, nc, nullptr, rs.rgb.data(), rs.shadows.data(), nullptr, nullptr);
    for (std::size_t k = 0; k < n; ++k) {
      const float* c = rs.rgb.data() + 3 * k;
      fresh->texel[k] = Texel{c[0], c[1], c[2], rs.shadows[k] + (rs.ground[k].paved ? kTexelPaved : 0)};
    }
    tile = rd.cache->insert(key, std::move(fresh));
  }
  const std::size_t l = TexelReader::slot(key);
  rd.key[l] = key;
  rd.tile[l] = tile.get();
  rd.held.push_back(std::move(tile));
  return rd.tile[l];
}

TexelLod world_detail::texelLod(double footprint) {
  int e = 0;
  const double m = std::frexp(footprint / kTexel0, &e);  // footprint = m · 2^e · kTexel0, m in [0.5, 1)
  // (footprint − s_L) / s_L = 2m − 1 in [0, 1); the two levels mixed over its middle quarter.
  TexelLod lod{std::clamp(static_cast<float>(4 * (2 * m - 1) - 1.5), 0.0f, 1.0f), e - 1};
  if (lod.level < 0) lod = {0, 0};
  if (lod.level >= kTexelLevels - 1) lod = {1, kTexelLevels - 2};
  return lod;
}

bool Shading::texelColour(const Vec2& p, TexelLod lod, bool paved, TexelReader& rd, NoiseCache& nc, C3& colour,
                          float& shadow) const {
  // Level L's and L + 1's bilinear samples at p, weighted 1 − mix and mix, summed as one; false
  // where the paved area's edge passes between the texels read.
  Texel sum{};
  const auto same = [paved](const Texel& t) { return (t[3] >= kTexelPaved) == paved; };
  double gx = p.x() * kInvSpacing[static_cast<std::size_t>(lod.level)] + kTexelOffset;
  double gy = p.y() * kInvSpacing[static_cast<std::size_t>(lod.level)] + kTexelOffset;
  for (int k = 0; k < 2; ++k) {
    const float wk = k == 0 ? 1 - lod.mix : lod.mix;
    if (wk != 0) {  // else the other level alone
      const int level = lod.level + k;
      const auto i = static_cast<std::int64_t>(gx), j = static_cast<std::int64_t>(gy);  // ≥ 0: the floor
      const auto ax = static_cast<float>(gx - static_cast<double>(i)), ay = static_cast<float>(gy - static_cast<double>(j));
      // floor(texel / kTexelTile) less the offset's tiles
      const std::int64_t tx = (i >> kTexelTileBits) - (std::int64_t{1} << (31 - kTexelTileBits));
      const std::int64_t ty = (j >> kTexelTileBits) - (std::int64_t{1} << (31 - kTexelTileBits));
      const std::uint64_t key = texelKey(level, tx, ty);
      const std::size_t l = TexelReader::slot(key);
      const TexelTile* tile = rd.key[l] == key ? rd.tile[l] : texelTile(level, tx, ty, rd, nc);
      const Texel* a = tile->texel.data() + (j & (kTexelTile - 1)) * kTexelSide + (i & (kTexelTile - 1));
      const Texel* c = a + kTexelSide;
      if (!(same(a[0]) && same(a[1]) && same(c[0]) && same(c[1]))) return false;
      const float w00 = wk * (1 - ax) * (1 - ay), w10 = wk * ax * (1 - ay), w01 = wk * (1 - ax) * ay, w11 = wk * ax * ay;
      sum += (a[0] * w00 + a[1] * w10) + (c[0] * w01 + c[1] * w11);
    }
    gx = 0.5 * gx + 0.5 * kTexelOffset;  // the next level's coordinates: half, offset kept
    gy = 0.5 * gy + 0.5 * kTexelOffset;
  }
  colour = {sum[0], sum[1], sum[2]};
  shadow = std::clamp(sum[3] - (paved ? kTexelPaved : 0), 0.0f, 1.0f);
  return true;
}

}  // namespace mapnav
