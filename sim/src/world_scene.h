#pragma once
// The synthetic world's scene (internal to sim/src): the map prepared for lookups, and World::Impl in
// three layers, each using only the one below it: world_detail::Scene (the lookups and the
// renderer's tiles of them: world_scene.cpp, world_tiles.cpp), world_detail::Shading (the ground's
// and the sky's colours, a point or a row at a time, and the texel tiles: world_shading.cpp,
// world_texels.cpp) and World::Impl (the frames: world_render.cpp, world_landmark_view.cpp).
//
// Structure. A uniform grid of kCell-metre cells over the map lists, per cell, (1) the paved
// polygons (road areas, intersection shapes) that touch it, each flagged when it covers the whole
// cell, (2) the centre-line segments near enough to decide a point's shoulder side and its
// position along a road, (3) the tree-canopy discs whose shadow touches it, (4) the ground marks
// of the map's landmarks (their shadows, manhole covers; world_landmarks.h) that touch it. A ground point's
// paved test is then a lookup plus, in boundary cells only, an exact crossing-number test against
// the polygon's edges in a 1 m band of y. The renderer narrows the lists further per frame: each
// kTileW × kTileH tile of the image keeps, per cell its ground points meet, only what a point of
// the tile can meet (RenderTiles, world_tiles.cpp), with the same answers for every pixel.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "mapnav/geometry/polygon.h"
#include "mapnav/sim/world.h"
#include "world_landmarks.h"
#include "world_noise.h"
#include "world_texels.h"

namespace mapnav {
namespace world_detail {

constexpr double kCell = 3.0;      // grid cell, m
constexpr double kEdgeBand = 1.0;  // y-band of a polygon's edge index, m
constexpr int kTileW = 32, kTileH = 8;  // the renderer's tiles (RenderTiles), pixels
constexpr C3 kHazeColour{196, 206, 218};  // far ground fades toward it (Shading::finish)

// NoiseCache channels of the noise that is not a texture's (a texture's fractal sum k uses
// channel k, its salt's key in Shading::texture).
constexpr int kWobbleChannel = 0;  // the shoulder's ragged edge
constexpr int kWornChannel = 1;    // the worn strip of lawn beside the pavement
constexpr int kCanopyChannel = 6;  // the canopies' ragged outlines (two octaves)
constexpr int kFleckChannel = 7;   // sun flecks (two octaves)

// A texture's fractal sums (Shading::texture): channel k is the key of its salt and its
// NoiseCache channel; the renderer evaluates a row's sums channel by channel (fbmBatch).
struct FbmSpec {
  double base_freq = 0;  // cycles/m of the coarsest octave
  int octaves = 0;
};
constexpr FbmSpec fbmSpec(int k) {
  switch (k) {
    case 2: return {0.7, 4};    // concrete: mottle
    case 3: return {30.0, 3};   //   grain
    case 4: return {0.35, 3};   //   stains
    case 10: return {0.12, 3};  // asphalt: wear
    case 11: return {1.5, 3};   //   mottle
    case 12: return {40.0, 3};  //   grain
    case 14: return {0.08, 2};  //   cracked zones
    case 16: return {0.25, 3};  //   stains
    case 20: return {0.15, 3};  // grass: patches
    case 21: return {0.3, 3};   //   dry
    case 22: return {2.5, 3};   //   clumps
    case 23: return {40.0, 3};  //   blades
    case 24: return {9.0, 2};   //   tufts
    case 30: return {0.8, 4};   // dirt: mottle
    case 31: return {25.0, 3};  //   grain
    case 32: return {0.2, 2};   //   wet
    case 40: return {0.5, 3};   // gravel: mottle
    case 41: return {45.0, 2};  //   stones
    case 51: return {20.0, 2};  // brick: grain
    case 60: return {1.0, 5};   // other
    default: return {};
  }
}

enum class Material { Concrete, Asphalt, Grass, Dirt, Gravel, Brick, Other };
constexpr int kMaterials = 7;

/// The texture channels a material's texture may read (0 ends the list).
constexpr std::array<int, 6> materialChannels(Material m) {
  switch (m) {
    case Material::Concrete: return {2, 3, 4, 0};
    case Material::Asphalt: return {10, 11, 12, 14, 16, 0};
    case Material::Grass: return {20, 21, 22, 23, 24, 0};
    case Material::Dirt: return {30, 31, 32, 0};
    case Material::Gravel: return {40, 41, 0};
    case Material::Brick: return {51, 0};
    case Material::Other: return {60, 0};
  }
  return {};
}

/// A texture's fractal sums evaluated at its point when asked.
struct PointNoise {
  const std::uint64_t* salts;
  Vec2 p;
  double footprint;
  NoiseCache* nc;
  float operator()(int k) const {
    const FbmSpec s = fbmSpec(k);
    return fbm(salts[k], p, s.base_freq, s.octaves, footprint, channelOf(nc, k));
  }
};

/// A texture's fractal sums evaluated beforehand for a row of pixels: channel k of pixel i is
/// values[k * stride + i].
struct RowNoise {
  const float* values;
  std::size_t stride, i;
  float operator()(int k) const { return values[static_cast<std::size_t>(k) * stride + i]; }
};

struct PolyRef {
  std::uint32_t poly;
  bool whole;
};

/// What a ground point's lookups consult: its grid cell's lists of paved polygons, centre-line
/// segments, canopy discs and landmarks' ground marks, or a tile's copy of them without the entries
/// that no point of the tile can meet (RenderTiles), in the cell's order. Empty for a point off the grid.
struct CellLists {
  const PolyRef* polys = nullptr;
  const std::uint32_t* segs = nullptr;
  const std::uint32_t* discs = nullptr;
  const std::uint32_t* marks = nullptr;
  std::uint32_t n_polys = 0, n_segs = 0, n_discs = 0, n_marks = 0;
};

/// Where a ground point lies: its paved area or shoulder, the road it belongs to.
struct GroundPoint {
  CellLists lists;       // the lookups' lists (the canopy's discs for finish)
  bool paved = false;
  int surface = 0;       // the surface whose texture it shows
  int texture_road = -1; // the road whose slabs it follows (-1: the world grid)
  double along = 0, lateral = 0;  // along and beside the nearest centre line
  double best = 0;       // distance to that centre line
  int best_road = -1;    // that road, -1 when none is within reach
};

/// A renderer's scratch for one row (World::Impl::shadeRow), kept between rows.
struct RowScratch {
  std::vector<GroundPoint> ground;
  std::vector<Vec2> points;
  std::vector<float> fp;                        // each ground point's footprint, m (0: no ground point)
  std::vector<float> values;                    // channel k of pixel u: values[k * width + u]
  std::vector<std::uint32_t> group[kMaterials];  // the row's ground pixels by their texture's material
  std::vector<double> xs, ys;                   // one group's points, gathered
  std::vector<float> footprints, sums;
  std::vector<float> tree, flecked;             // each pixel's canopy shadow (Scene::canopyRow)
  std::vector<std::uint32_t> cand;              // canopyRow's pixels, their points and noise
  std::vector<double> cx, cy;
  std::vector<float> zeros, n0, n1;
  std::vector<BodyHit> hits;                    // the row's nearest landmark bodies (World::Impl::bodyRow)
  std::vector<int> hit_slot;                    //   their slots in the frame's LandmarkView, -1: none
  std::vector<int> shown;                       // per LandmarkView slot, the pixels that show it
  std::vector<float> rgb, shadows;              // a texel tile's colours and shadows (Shading::texelTile)

  /// A row of w points begun: none located (footprint 0: addPoint's), no material groups.
  void begin(std::size_t w) {
    ground.resize(w);
    points.resize(w);
    fp.assign(w, 0.0f);
    for (auto& g : group) g.clear();
  }
};

struct Surface {
  Material material = Material::Other;
  C3 rgb;
  C3 spread;
};

struct Edge {
  Vec2 a, b;
  double x_lo = 0, x_hi = 0;  // the edge's x extent widened by far more than the rounding of its crossing
};

struct PavedPolygon {
  Polygon2 ring;
  Box2 box;
  double band_y0 = 0;
  std::vector<std::uint32_t> band_start;  // CSR offsets into band_edges, one per y-band + 1
  std::vector<Edge> band_edges;           // per y-band, the edges meeting it (in ring order)
  int surface = 0;
  int road = -1;  // index into roads; -1 for an intersection
};

/// The corners of a box, in order around it (counter-clockwise from its least corner).
inline std::array<Vec2, 4> corners(const Box2& b) {
  return {b.min(), Vec2(b.max().x(), b.min().y()), b.max(), Vec2(b.min().x(), b.max().y())};
}

/// Whether p is inside the polygon (crossing number over the edges of p's y-band).
bool crossingContains(const PavedPolygon& poly, const Vec2& p);

/// What a World derives from a ray table alone (World::Impl::rayExtras), kept for the last table.
struct RayExtras {
  /// The box of a tile's ground points (vehicle frame); `ground` false when it has none.
  struct TileBox {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool ground = false;
  };
  std::vector<float> haze;      // hazeAt of each ground pixel's range (empty without haze)
  std::vector<TexelLod> lod;    // each ground pixel's texel levels (empty without the texel cache)
  bool any_outside = false;     // whether some pixel lies outside the lens' field
  std::vector<TileBox> tiles;   // kTileW × kTileH pixels each, tiles_x per band of kTileH rows
  int tiles_x = 0;
  TileBox ground;               // the box of every ground point
  std::vector<float> dirs;      // each pixel's unit ray, vehicle frame, 3 floats (a world with landmarks)
};

/// One band of tiles of a frame (Scene::tileRow): for each tile, the grid cells its box
/// meets, each with the cell's lists less what no point of the tile meets (in `polys`, `segs`,
/// `discs`, `marks`; a polygon that holds the whole tile marked whole). A renderer's thread keeps one.
struct RenderTiles {
  struct Cell {
    int cell = -1;
    std::uint32_t polys = 0, segs = 0, discs = 0, marks = 0;  // offsets of its lists
    std::uint32_t n_polys = 0, n_segs = 0, n_discs = 0, n_marks = 0;
  };
  int band = -1;
  std::vector<Cell> cells;
  std::vector<std::uint32_t> first;  // tile t's cells: [first[t], first[t + 1])
  std::vector<int> sure;             // per tile, its one cell's entry when every pixel is in it, else -1
  std::vector<PolyRef> polys;
  std::vector<std::uint32_t> segs, discs, marks;
  std::vector<double> road_bound;    // per road, scratch of addTileCell (infinite between calls)
};

/// A renderer thread's reads of the cache during one frame: the tiles it read, held so that no
/// other frame's endFrame drops them, and a direct-mapped table of them by key.
struct TexelReader {
  static constexpr std::size_t kSlots = 1024;
  explicit TexelReader(TexelCache* c) : cache(c) { key.fill(~std::uint64_t{0}); }
  TexelCache* cache;
  std::vector<std::shared_ptr<const TexelTile>> held;
  std::array<std::uint64_t, kSlots> key{};
  std::array<const TexelTile*, kSlots> tile{};
  RowScratch scratch;      // for their shading, with the lists of the tile's points
  RenderTiles lists;
  /// The slot of a key: its level and tile coordinates' low bits.
  static std::size_t slot(std::uint64_t key) { return (key ^ (key >> 23) ^ (key >> 53)) & (kSlots - 1); }
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
  /// (r + 0.45)² widened by far more than its rounding: a point whose squared distance from c
  /// exceeds it is beyond the canopy's reach (r + 0.45, the outline's wobble included).
  double reach2 = 0;
};

/// The uniform grid of kCell-metre cells over the map (Scene::buildGrid): per cell, in CSR
/// form, the paved polygons, centre-line segments, canopy discs and landmarks' marks that touch it.
struct Grid {
  Vec2 origin = Vec2::Zero();
  int nx = 0, ny = 0;
  std::vector<std::uint32_t> poly_start, seg_start, disc_start, mark_start;  // CSR offsets, size nx*ny+1
  std::vector<PolyRef> cell_polys;
  std::vector<std::uint32_t> cell_segs, cell_discs, cell_marks;

  /// The grid's lists of a cell (cellIndex; empty for -1).
  CellLists cellLists(int cell) const {
    if (cell < 0) return {};
    const auto c = static_cast<std::size_t>(cell);
    return {cell_polys.data() + poly_start[c],      cell_segs.data() + seg_start[c],
            cell_discs.data() + disc_start[c],      cell_marks.data() + mark_start[c],
            poly_start[c + 1] - poly_start[c],      seg_start[c + 1] - seg_start[c],
            disc_start[c + 1] - disc_start[c],      mark_start[c + 1] - mark_start[c]};
  }

  /// The cell holding p, -1 off the grid.
  int cellIndex(const Vec2& p) const {
    const double fx = (p.x() - origin.x()) / kCell, fy = (p.y() - origin.y()) / kCell;
    if (!(fx >= 0 && fy >= 0 && fx < nx && fy < ny)) return -1;
    return static_cast<int>(fy) * nx + static_cast<int>(fx);
  }
};

/// The map prepared for lookups (world_scene.cpp, world_tiles.cpp): the surfaces, roads, paved
/// polygons, centre-line segments, canopy discs and landmarks, on the grid; which paved polygon holds
/// a point, the canopies' shadow there; and a frame's tiles of the grid's lists (RenderTiles). What
/// Shading colours and World::Impl renders; it needs neither.
struct [[gnu::visibility("hidden")]] Scene : Grid {
  WorldOptions options;
  std::array<std::uint64_t, NoiseCache::kChannels> salts{};  // texture salt k (Shading::texture)
  std::vector<Surface> surfaces;
  int lawn = -1;  // the background surface
  std::vector<RoadInfo> roads;
  std::vector<PavedPolygon> polys;
  std::vector<Segment> segments;
  std::vector<Disc> discs;
  bool shadow_everywhere = false;
  std::uint64_t leaf_salt = 0;  // the fallen leaves' cells' (Shading::surfaceFinish)
  Landmarks landmarks;  // the map's (world_landmarks.cpp)

  /// The options validated (InvalidInput otherwise), the map's surfaces, roads, intersections, trees
  /// and landmarks placed, and the grid built over them.
  Scene(const Map& map, const WorldOptions& opts);
  int surfaceIndex(const Map& map, const std::string& name);
  void buildGrid(const Box2& box);
  /// The grid cells [x0, x1] × [y0, y1] a box meets (clamped to the grid).
  void cellRange(const Box2& b, int& x0, int& y0, int& x1, int& y1) const;
  /// Per grid cell, the paved polygons that touch it (whole ones first).
  std::vector<std::vector<PolyRef>> polygonCells() const;
  void placeTrees(const Map& map);
  /// Index of the paved polygon holding p (roads before intersections), or -1.
  int pavedAt(const Vec2& p, const world_detail::CellLists& lists) const;
  /// Tree shadow at p, 0 sunlit … 1 full: `bare` at the point without the sun flecks (where the
  /// leaves fall), `flecked` over a pixel `footprint` wide with the flecks. `nc` may be nullptr.
  void canopy(const Vec2& p, const world_detail::CellLists& lists, double footprint, NoiseCache* nc, float& bare,
              float& flecked) const;
  /// The canopy's shadow at p, s (as seen over `footprint`, before the flecks) and s_bare (at
  /// the point), from the discs in `lists`; wobble() gives the outline's wobble at p (asked once,
  /// and only when a disc is within reach).
  template <class Wobble>
  void discShadow(const Vec2& p, const world_detail::CellLists& lists, double footprint, const Wobble& wobble, float& s,
                  float& s_bare) const;
  /// canopy of a row's w located ground points (rs.points, rs.ground, rs.fp) into rs.tree (bare)
  /// and rs.flecked, the outlines' and the flecks' noise evaluated a row at a time.
  void canopyRow(std::size_t w, world_detail::RowScratch& rs) const;
  /// Band `band` of the frame's tiles seen from pose (cos, sin of the heading, x, y) into rt.
  void tileRow(const world_detail::RayExtras& extras, int band, const std::array<double, 4>& pose,
               world_detail::RenderTiles& rt) const;
  /// rt emptied of tiles; tile rt.first.size() − 1 added: the lists of the points of a world box.
  void clearTiles(world_detail::RenderTiles& rt) const;
  void addTile(const Box2& points, world_detail::RenderTiles& rt) const;
  /// The lists of grid cell `cell` for the points of a tile (a world box) into rt.
  void addTileCell(int cell, const Box2& tile, world_detail::RenderTiles& rt) const;
  /// Whether every point of the box is inside the polygon as crossingContains sees it (false when unsure).
  bool polygonHoldsBox(const PavedPolygon& poly, const Box2& box) const;
  /// The lists of point p of tile `tile` in rt (its cell's own when the tile has none for it).
  world_detail::CellLists tileLists(const world_detail::RenderTiles& rt, int tile, const Vec2& p) const;
};

/// The colour of the scene's ground (world_shading.cpp, world_texels.cpp): where a point lies, its
/// surface's texture, its finish (worn edges, fallen leaves, shadows, haze) and the sky; a point at a
/// time (shade) or a row of located points at a time (addPoint, shadeLocated, with the textures'
/// fractal sums evaluated channel by channel), and the texel cache's tiles shaded the same way.
struct [[gnu::visibility("hidden")]] Shading : Scene {
  using Scene::Scene;

  /// The colour of ground point p seen by a pixel `footprint` wide at `range`; `paved` its class.
  /// `nc` (may be nullptr) memoizes the noise lattice between calls (the same colour either way).
  /// It is locate, texture and finish in turn.
  C3 shade(const Vec2& p, double footprint, double range, bool& paved, NoiseCache* nc) const;
  /// Where p lies (the shoulder's ragged edge from `nc`'s wobble channel), looked up in `lists`
  /// (p's cell's, or a tile's holding p).
  void locate(const Vec2& p, const world_detail::CellLists& lists, NoiseCache* nc, world_detail::GroundPoint& g) const;
  /// A surface's texture at p; `noise(k)` gives its fractal sum k (PointNoise or RowNoise).
  template <class Noise>
  C3 texture(int surface, const Vec2& p, double footprint, double along, double lateral, int road,
             const Noise& noise, NoiseCache* nc) const;
  /// texture's concrete (surface `sf`): slabs along road `road` (a world grid where it is -1), dust
  /// and stains, cracks, the gaps between the slabs. Inlined into texture, as it was written there.
  template <class Noise>
  [[gnu::always_inline]] inline C3 concreteTexture(const Surface& sf, const Vec2& p, double footprint, double along,
                                                   double lateral, int road, const Noise& noise, NoiseCache* nc) const;
  /// texture's asphalt (surface `sf`): patches of wear, mottle and grain, aggregate stones, cracked
  /// zones, stains. Inlined into texture, as it was written there.
  template <class Noise>
  [[gnu::always_inline]] inline C3 asphaltTexture(const Surface& sf, const Vec2& p, double footprint,
                                                  const Noise& noise, NoiseCache* nc) const;
  /// The fractal sums of each material group of a row's w ground points (rs.group, rs.points,
  /// rs.fp), channel by channel, into rs.values.
  void textureSums(std::size_t w, world_detail::RowScratch& rs) const;
  /// Point u of rs's row at p, `footprint` wide, located in `lists` and put in its material's group.
  void addPoint(world_detail::RowScratch& rs, std::size_t u, const Vec2& p, float footprint,
                const world_detail::CellLists& lists, NoiseCache& nc) const;
  /// A row's w located ground points (rs.points, rs.ground, rs.fp, rs.group) shaded: texture, marks,
  /// finish, `haze` per point (nullptr: none); with `shadows`, surfaceFinish and the shadow. Covers
  /// are marked in `lmask` (unless nullptr) and counted in rs.shown when the view lists them.
  void shadeLocated(std::size_t w, world_detail::RowScratch& rs, NoiseCache& nc, const float* haze, float* rgb,
                    float* shadows, const world_detail::LandmarkView* view, std::uint8_t* lmask) const;
  /// The texture `c` of located point p finished: surfaceFinish, shadowed by `flecked`, hazed.
  /// `haze`: hazeAt(the point's range).
  /// `tree`, `flecked`: canopy's shadow at p.
  C3 finish(const Vec2& p, const world_detail::GroundPoint& g, C3 c, double footprint, float haze, float tree,
            float flecked, NoiseCache* nc) const;
  /// The texture `c` of located point p with the lawn's worn edge and the fallen leaves (`tree`:
  /// the canopy's shadow at p, where leaves fall): what a shadow darkens.
  C3 surfaceFinish(const Vec2& p, const world_detail::GroundPoint& g, C3 c, double footprint, float tree,
                   NoiseCache* nc) const;
  /// c in shadow s (0 sunlit … 1 full); c at haze `haze` (hazeAt; unchanged without haze).
  C3 shadowed(C3 c, float s) const;
  C3 hazed(C3 c, float haze) const;
  /// Aerial perspective: how far ground at `range` m fades toward the horizon's haze (0 … 1; with
  /// haze_distance_m > 0).
  float hazeAt(double range) const;
  C3 sky(double elevation) const;
  /// Ground point p's colour before its shadow and the canopies' shadow for a pixel of texel levels
  /// `lod`, from the texels; false when a texel read is paved and p not, or the other way round.
  bool texelColour(const Vec2& p, world_detail::TexelLod lod, bool paved, world_detail::TexelReader& rd,
                   NoiseCache& nc, C3& colour, float& shadow) const;
  /// Level `level`'s tile (tx, ty) from rd's cache, shaded (without haze, shadows and marks) and
  /// kept when the cache lacks it; rd holds it.
  const world_detail::TexelTile* texelTile(int level, std::int64_t tx, std::int64_t ty, world_detail::TexelReader& rd,
                                           NoiseCache& nc) const;
};

}  // namespace world_detail

/// A world's frames (world_render.cpp, world_landmark_view.cpp): its rays' extras, each row shaded
/// (the landmarks' bodies, the ground from the texels or the Shading), the paved edge re-sampled, the
/// camera's drift and noise; and the caches the frames share (ray tables, extras, texels).
struct [[gnu::visibility("hidden")]] World::Impl : world_detail::Shading {
  using C3 = world_detail::C3;
  using NoiseCache = world_detail::NoiseCache;

  mutable std::mutex cache_mutex;
  mutable std::vector<std::shared_ptr<const RayTable>> cache;
  // What the last ray table gave (rayExtras), by the table's id.
  mutable std::uint64_t extras_id = 0;
  mutable std::shared_ptr<const world_detail::RayExtras> extras;
  std::unique_ptr<world_detail::TexelCache> texels;  // options' texel_cache_mib (null: none; world_texels.h)

  /// The scene, and the texel cache that options' texel_cache_mib asks for.
  Impl(const Map& map, const WorldOptions& opts);
  /// The landmarks that may show in a frame seen from pose (cos, sin of the heading, x, y).
  world_detail::LandmarkView landmarkView(const RayTable& rays, const world_detail::RayExtras& extras,
                                          const std::array<double, 4>& pose) const;
  /// Row v's pixels whose ray meets a landmark of the view before the ground: their colour (3
  /// floats, before the camera), mask 0 and landmark mask kShowsBody, counted in rs.shown. False
  /// when no body's box holds the row; else rs.hit_slot marks those pixels (-1 the others).
  bool bodyRow(const RayTable& rays, const world_detail::LandmarkView& view, int v, world_detail::RowScratch& rs,
               float* rgb, std::uint8_t* mask, std::uint8_t* lmask) const;
  /// The landmarks of the view that a frame lists (Frame::landmarks), from the pixels that show each.
  std::vector<LandmarkInView> landmarkTruth(const Camera& camera, const world_detail::LandmarkView& view,
                                            const std::array<double, 4>& pose, const std::vector<int>& shown) const;
  /// Shades row v of a frame seen from pose (cos, sin of the heading, x, y): its pixels' colours
  /// (3 floats each, before the camera's drift and noise) and mask. The same as `shade` per pixel,
  /// with the texture's fractal sums evaluated channel by channel over the row; with `texels`, the
  /// ground pixels texelPixel gives from them (`lod`: rayExtras' row v). `haze`: rayExtras' row v
  /// (unread without haze); `tiles`: row v's band (tileRow); `view`: the frame's landmarks
  /// (nullptr: none), `lmask` row v of the frame's landmark mask (kShowsBody, kShowsCover).
  void shadeRow(const RayTable& rays, int v, const std::array<double, 4>& pose, const world_detail::RenderTiles& tiles,
                world_detail::RowScratch& rs, NoiseCache& nc, world_detail::TexelReader* texels,
                const world_detail::TexelLod* lod, const float* haze, float* rgb, std::uint8_t* mask,
                const world_detail::LandmarkView* view, std::uint8_t* lmask) const;
  /// Ground pixel r's colour `c` (before the camera) and `mask` at p from the texels; false (c and
  /// mask unset) where it is to be shaded on its own: on a manhole cover, or where a texel read is
  /// paved and p not or the other way round.
  bool texelPixel(const Vec2& p, const RayTable::Ray& r, const world_detail::CellLists& lists, world_detail::TexelLod lod,
                  float haze, world_detail::TexelReader& texels, NoiseCache& nc, C3& c, std::uint8_t& mask) const;
  /// Rows [v0, v1) of the pixels the paved area's edge crosses re-sampled n × n (options'
  /// paved_edge_samples) from the finished mask into `buf` (3 floats a pixel). Pixels that show a
  /// landmark's body (kShowsBody in `lmask`, nullptr: none) are neither re-sampled nor an edge.
  void edgeSamples(const RayTable& rays, int v0, int v1, const std::array<double, 4>& pose, const std::uint8_t* mask,
                   const std::uint8_t* lmask, NoiseCache& nc, float* buf) const;
  /// Rows [v0, v1) through the camera: illumination drift, TV colour shift, sensor noise (none for
  /// a pixel outside the lens' field; `any_outside`: some is), bytes.
  void camera(const RayTable& rays, bool any_outside, int v0, int v1, const Pose2& pose, double t, float* buf,
              std::uint8_t* rgb) const;
  /// The haze of each ground pixel and the boxes of the tiles' ground points (kept for the last table).
  std::shared_ptr<const world_detail::RayExtras> rayExtras(const RayTable& rays) const;
};

inline world_detail::C3 world_detail::Shading::shadowed(C3 c, float s) const {
  // k·C, tinted toward the skylight.
  if (s > 0) {
    const auto k = static_cast<float>(options.shadow_k), b = static_cast<float>(options.shadow_blue_shift);
    const C3 lit{1, 1, 1}, shadow{k * (1 - b), k, k * (1 + b)};
    c = c * lerp(lit, shadow, s);
  }
  return c;
}

inline world_detail::C3 world_detail::Shading::hazed(C3 c, float haze) const {
  // Aerial perspective: far ground fades toward the haze of the horizon.
  if (options.haze_distance_m <= 0) return c;
  return lerp(c, world_detail::kHazeColour, haze);
}

}  // namespace mapnav
