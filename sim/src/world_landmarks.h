#pragma once
// The map's landmarks as the synthetic world draws them (internal to sim/src; see world.h for what
// they look like). A landmark is a Body (what stands: posts, a tree's trunk and crown, a bench's
// boxes; a manhole cover has none) and GroundMarks (what it leaves on the ground: its shadow, a
// cover's disc), which the lookup grid lists per cell beside the canopy discs, so a ground pixel
// tests only the marks of its tile. A frame keeps a LandmarkView: the landmarks that may show in
// it, each with the box of pixels its body may cover, so a pixel tests only the bodies whose box
// holds it. Everything is in the world frame, metres; heights above the ground plane.
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "mapnav/geometry/types.h"
#include "mapnav/map/map.h"
#include "mapnav/sim/world.h"
#include "world_noise.h"

namespace mapnav::world_detail {

// Where a ray meets a body (BodyHit::part).
enum class Part : std::uint8_t { Post, Cap, Crown, Seat, Back };

// A bench's box: its depth, its seat's height and the depth of its back (at the side away from
// its road), m.
constexpr double kBenchDepth = kBenchDepthM, kBenchSeat = 0.45, kBenchBack = 0.08;  // the depth: the map's
// A tree: its crown's radius and centre height, and the top of its trunk (inside the crown), as
// fractions of its height; the crown's outline is ragged inward by up to kCrownRag of its radius.
constexpr double kCrownRadius = 0.3, kCrownCentre = 0.7, kTrunkTop = 0.5, kCrownRag = 0.18;
// A ground mark's soft edge is at most this wide (m), so nothing of it lies beyond its box.
constexpr double kMarkEdgeMax = 1.0;

/// A map landmark's body, one per Map::landmarks() entry (a manhole cover's has no volume).
struct Body {
  LandmarkKind kind = LandmarkKind::Pole;
  Vec2 c = Vec2::Zero();          // where it meets the ground (Landmark::position)
  double r = 0, h = 0;            // Landmark::radius (a bench: half its length), height
  double post_top = 0;            // the cylinder's top: h (pole, bollard), kTrunkTop·h (a trunk)
  double crown_z = 0, crown_r = 0;  // a tree's crown: centre height, radius
  Vec2 axis = Vec2::UnitX();      // a bench: along its road
  Vec2 back = Vec2::UnitY();      // a bench: toward its back, away from its road
  Box2 box;                       // its extent on the ground
  std::uint32_t first_mark = 0, n_marks = 0;  // its ground marks in World::Impl::marks
  std::uint64_t salt = 0;         // its texture's and outline's noise
  bool upright() const { return kind != LandmarkKind::Manhole; }
};

/// Where a ray first meets a body: the distance along the (unit) ray, the outward normal there
/// and the part it meets.
struct BodyHit {
  double t = std::numeric_limits<double>::infinity();
  Vec3 n = Vec3::UnitZ();
  Part part = Part::Post;
};

/// Whether the ray o + t·d (d unit) meets the body at some 0 < t < t_max; then `hit` is set.
bool hitBody(const Body& body, const Vec3& o, const Vec3& d, double t_max, BodyHit& hit);

/// Something a landmark leaves on the ground: the shadow of a post (a capsule: the points within
/// r of the segment ab), of a crown (an ellipse: centre a, unit axis b along the shadow, half
/// widths r across and r_along along) or of a bench's box (a convex polygon), or a manhole's cover
/// (a disc: centre a, radius r).
struct GroundMark {
  enum class Kind : std::uint8_t { Capsule, Ellipse, Polygon, Cover };
  Kind kind = Kind::Capsule;
  std::uint32_t landmark = 0;     // index in Map::landmarks()
  Box2 box;                       // nothing of it (soft edge, wobble) lies beyond
  Vec2 a = Vec2::Zero(), b = Vec2::Zero();
  double r = 0, r_along = 0;
  std::uint32_t first = 0, count = 0;  // a polygon's vertices in Landmarks::mark_points, counter-clockwise
  std::uint64_t salt = 0;         // an ellipse's ragged outline, a cover's pattern
};

/// The sun of WorldOptions: toward it (unit), the ground direction shadows fall along (unit), and
/// a shadow's length per metre of height.
struct Sun {
  Vec3 toward = Vec3::UnitZ();
  Vec2 shadow_dir = Vec2::UnitX();
  double shadow_per_m = 0;
  double sin_elevation = 1;
};
Sun sunOf(double azimuth_rad, double elevation_rad);

/// The map's landmarks prepared for the renderer (world_landmarks.cpp): one body each, the marks
/// they leave on the ground, the sun that lights them.
struct Landmarks {
  std::vector<Body> bodies;       // one per Map::landmarks() entry
  std::vector<GroundMark> marks;  // each body's marks together (Body::first_mark)
  std::vector<Vec2> mark_points;  // the polygons' vertices
  Sun sun;
  float shadow_k = 1, blue_shift = 0;  // WorldOptions' shadow tint
  bool any_upright = false;

  Landmarks() = default;
  /// The map's landmarks, seeded and lit by the options (seed, the sun, the shadows' tint).
  Landmarks(const Map& map, const WorldOptions& options);
  /// The landmarks' shadow at p (0 … 1, soft over a pixel `footprint` wide) from the marks
  /// ids[0 … n); with `c`, a manhole cover there is painted on the ground colour *c; *cover (unless
  /// nullptr) set to the landmark index of the cover holding p, else -1.
  float marksAt(const Vec2& p, const std::uint32_t* ids, std::uint32_t n, double footprint, C3* c, int* cover) const;
  /// The colour of a body where the unit `ray` meets it (at p), seen by a pixel `footprint` wide.
  C3 bodyColour(const Body& body, const Vec3& p, const Vec3& ray, const BodyHit& hit, double footprint) const;
  /// Sunlight on a surface of normal n: the shadow's tint (k·C, blue shift) facing away from the
  /// sun, 1 where it faces the sun as the ground does, more where it faces it squarely.
  C3 sunlight(const Vec3& n) const;

 private:
  /// A bench's orientation along its road and its ground marks (landmark `id`).
  void placeBench(const Map& map, const Landmark& landmark, std::uint32_t id, Body& body);
  /// A tree's crown and its shadow (landmark `id`).
  void placeCrown(std::uint32_t id, Body& body);
  /// The shadow of a box standing on the ground (corners of its footprint, its height) as a mark.
  void addBoxShadow(std::uint32_t landmark, const std::array<Vec2, 4>& footprint, double height);
  /// A landmark's shadow at p (0 … 1, soft over a pixel `footprint` wide); 0 for a cover.
  float markShadow(const GroundMark& mark, const Vec2& p, double footprint) const;
  // The landmarks' materials at p (`rel`: from the landmark's ground point) of normal n, lit.
  C3 metal(C3 base, const Vec3& rel, const Vec3& n, const Vec3& ray, std::uint64_t salt, double footprint,
           float shine) const;
  C3 bark(const Vec3& rel, const Vec3& n, std::uint64_t salt, double footprint) const;
  C3 foliage(const Vec3& p, const Vec3& n, std::uint64_t salt, double footprint) const;
  C3 wood(const Body& body, const Vec3& p, const BodyHit& hit, double footprint) const;
};

/// A box of pixels, inclusive; empty when u0 > u1.
struct PixelBox {
  int u0 = 0, u1 = -1, v0 = 0, v1 = -1;
  bool holdsRow(int v) const { return u0 <= u1 && v0 <= v && v <= v1; }
};

/// A frame's landmarks that may show (World::Impl::landmarkView), ascending by landmark.
struct LandmarkView {
  struct Item {
    std::uint32_t landmark = 0;
    /// The pixels its body may cover: a tree's trunk and crown apart, one box for other kinds.
    std::array<PixelBox, 2> parts{};
    bool hasPixels() const { return parts[0].u0 <= parts[0].u1 || parts[1].u0 <= parts[1].u1; }
  };
  std::vector<Item> items;
  const float* dirs = nullptr;  // RayExtras::dirs: each pixel's unit ray, vehicle frame
  Vec3 eye = Vec3::Zero();   // the optical centre, world
  double ch = 1, sh = 0;     // cos, sin of the vehicle's heading
  bool bodies = false;       // some item has pixels to test
  /// The slot of a landmark among items, or -1.
  int slot(std::uint32_t landmark) const;
};

// Frame::landmark_mask while a frame is rendered: a pixel showing a body, or a cover's disc.
constexpr std::uint8_t kShowsBody = 1, kShowsCover = 2;

}  // namespace mapnav::world_detail
