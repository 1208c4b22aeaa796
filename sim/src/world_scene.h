#pragma once
// The synthetic world's scene (internal to sim/src): the map prepared for lookups, and World::Impl,
// which the scene (world_scene.cpp), the shading (world_shading.cpp) and the renderer
// (world_render.cpp) share.
//
// Structure. A uniform grid of kCell-metre cells over the map lists, per cell, (1) the paved
// polygons (road areas, intersection shapes) that touch it, each flagged when it covers the whole
// cell, (2) the centre-line segments near enough to decide a point's shoulder side and its
// position along a road, (3) the tree-canopy discs whose shadow touches it. A ground point's
// paved test is then a lookup plus, in boundary cells only, an exact crossing-number test against
// the polygon's edges in a 1 m band of y.
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "mapnav/geometry/polygon.h"
#include "mapnav/sim/world.h"
#include "world_noise.h"

namespace mapnav {
namespace world_detail {

constexpr double kCell = 3.0;   // grid cell, m

// NoiseCache channels of the noise that is not a texture's (a texture's fractal sum k uses
// channel k, its salt's key in World::Impl::texture).
constexpr int kWobbleChannel = 0;  // the shoulder's ragged edge
constexpr int kWornChannel = 1;    // the worn strip of lawn beside the pavement
constexpr int kCanopyChannel = 6;  // the canopies' ragged outlines (two octaves)
constexpr int kFleckChannel = 7;   // sun flecks (two octaves)

enum class Material { Concrete, Asphalt, Grass, Dirt, Gravel, Brick, Other };

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

}  // namespace world_detail

struct [[gnu::visibility("hidden")]] World::Impl {
  using C3 = world_detail::C3;
  using Surface = world_detail::Surface;
  using RoadInfo = world_detail::RoadInfo;
  using PavedPolygon = world_detail::PavedPolygon;
  using Segment = world_detail::Segment;
  using Disc = world_detail::Disc;
  using PolyRef = world_detail::PolyRef;
  using NoiseCache = world_detail::NoiseCache;
  using NoiseMemo = world_detail::NoiseMemo;

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
    const double fx = (p.x() - origin.x()) / world_detail::kCell, fy = (p.y() - origin.y()) / world_detail::kCell;
    if (!(fx >= 0 && fy >= 0 && fx < nx && fy < ny)) return -1;
    return static_cast<int>(fy) * nx + static_cast<int>(fx);
  }

  Impl(const Map& map, const WorldOptions& opts);
  int surfaceIndex(const Map& map, const std::string& name);
  void buildGrid(const Box2& box);
  void placeTrees(const Map& map);

  /// Index of the paved polygon holding p (roads before intersections), or -1.
  int pavedAt(const Vec2& p, int cell) const;
  /// Tree shadow at p, 0 sunlit … 1 full: `bare` at the point without the sun flecks (where the
  /// leaves fall), `flecked` over a pixel `footprint` wide with the flecks. `nc` may be nullptr.
  void canopy(const Vec2& p, int cell, double footprint, NoiseCache* nc, float& bare, float& flecked) const;
  /// The colour of ground point p seen by a pixel `footprint` wide at `range`; `paved` its class.
  /// `nc` (may be nullptr) memoizes the noise lattice between calls (the same colour either way).
  C3 shade(const Vec2& p, double footprint, double range, bool& paved, NoiseCache* nc) const;
  C3 texture(int surface, const Vec2& p, double footprint, double along, double lateral, int road,
             NoiseCache* nc) const;
  C3 sky(double elevation) const;
};

}  // namespace mapnav
