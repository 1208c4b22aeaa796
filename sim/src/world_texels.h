#pragma once
// The ground's colour kept in world space across frames (internal to sim/src; World::Impl's
// texels). Frames a short step apart see mostly the same ground, so the renderer shades the
// ground once per texel rather than once per pixel and frame (WorldOptions::texel_cache_mib).
//
// Levels. Level L's texels lie on the world grid of spacing s_L = kTexel0 · 2^L (world frame, m;
// texel (i, j) at (i · s_L, j · s_L)), each shaded as Shading::shade shades a point for a
// pixel s_L wide, but kept before a shadow darkens it, with the canopies' shadow beside it, and
// without the marks of the map's landmarks. A pixel of footprint f (RayTable::Ray::footprint) in
// [s_L, 2 s_L) takes the bilinear sample of level L and of level L + 1 around its ground point,
// mixed by where f lies in the octave (TexelLod): the texture's detail fades with the footprint as
// the per-pixel renderer's does, without a step at a level's end, and a pixel outside the middle
// quarter of an octave reads one level only. The pixel then adds the landmarks' shadows at its
// own point, the shadow (Shading::shadowed) and its haze (that depends on the range), so
// that the marks change a frame where they lie and nowhere else, as in the per-pixel renderer.
//
// Where the texels would blur what the masks say exactly, the pixel is shaded on its own (with
// the others of its row, as the per-pixel renderer shades it): where a texel it reads is paved
// and the pixel is not, or the other way round, and on a manhole cover. So the colours change
// class where the mask does, at the pixel.
//
// Tiles. Texels are shaded kTexelTile × kTexelTile at a time; a tile holds its next tile's first
// row and column too (kTexelSide a side), so that a bilinear sample reads one tile. A tile is a
// pure function of the world, its level and its place: the frames do not depend on what the cache
// held before, on the order of the tiles' shading or on the threads.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

namespace mapnav::world_detail {

constexpr int kTexelTileBits = 4;
constexpr int kTexelTile = 1 << kTexelTileBits;  // texels a side of a tile
constexpr int kTexelSide = kTexelTile + 1;  // grid points a side of a tile (with the next tile's first)
constexpr double kTexel0 = 1.0 / 1024;      // level 0's texel spacing, m
constexpr int kTexelLevels = 24;            // levels 0 … 23 (level 23: 8 km texels)

/// A texel: the colour before a shadow darkens it (r, g, b, before the camera) and the canopies'
/// shadow (0 … 1) plus kTexelPaved where the point is paved.
using Texel = float __attribute__((vector_size(16)));
constexpr float kTexelPaved = 2;

/// A tile's texels: grid point (i, j) (i along x) at j · kTexelSide + i.
struct TexelTile {
  std::array<Texel, kTexelSide * kTexelSide> texel;
};

/// Level `level`'s tile (tx, ty) as one key (tx, ty within ±2^27 tiles: far beyond any map).
constexpr std::uint64_t texelKey(int level, std::int64_t tx, std::int64_t ty) {
  constexpr std::int64_t kOff = std::int64_t{1} << 27;
  return (static_cast<std::uint64_t>(level) << 56) | (static_cast<std::uint64_t>(tx + kOff) << 28) |
         static_cast<std::uint64_t>(ty + kOff);
}

/// The tiles shaded so far, the least recently used dropped beyond a budget (thread-safe).
class TexelCache {
 public:
  explicit TexelCache(std::size_t max_tiles) : max_tiles_(max_tiles) {}
  /// The tile of `key`, or nullptr; marks it used by the current frame.
  std::shared_ptr<const TexelTile> find(std::uint64_t key);
  /// Keeps `tile` for `key` and returns it (or the tile another thread stored first: the same values).
  std::shared_ptr<const TexelTile> insert(std::uint64_t key, std::shared_ptr<const TexelTile> tile);
  /// Ends a frame: drops the tiles least recently used beyond the budget.
  void endFrame();
  std::size_t size() const;

 private:
  struct Entry {
    std::shared_ptr<const TexelTile> tile;
    std::uint64_t used = 0;  // the frame that last asked for it
  };
  mutable std::mutex mutex_;
  std::unordered_map<std::uint64_t, Entry> tiles_;
  std::uint64_t frame_ = 0;
  std::size_t max_tiles_;
};

/// The two levels a pixel of footprint f samples: level L with f in [s_L, 2 s_L) and level L + 1,
/// mixed by `mix` (0: level L alone, 1: level L + 1 alone), which rises from 0 to 1 over the
/// middle quarter of the octave, (f − s_L) / s_L in [3/8, 5/8] (levels clamped to 0 … kTexelLevels − 1).
struct TexelLod {
  float mix = 0;
  int level = 0;
};
TexelLod texelLod(double footprint);

}  // namespace mapnav::world_detail
