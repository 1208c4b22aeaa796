#pragma once
// The synthetic world: realistic camera frames, with a ground-truth road mask, rendered from a map
// (Wallace et al. 1985, 3 and 3.4: concrete sidewalks between lawns with cracks, dust and gaps
// between slabs; an asphalt park path partly shaded by trees, shadows C1 = k·C2 tinted toward the
// skylight, fallen leaves, a TV camera of small dynamic range whose colour drifts in transmission).
//
// The world is flat (the local ground plane): every pixel whose ray meets the ground shows the
// ground point's procedural texture, every other pixel the sky. Texture is a seeded function of the
// world point (continuous in world coordinates, so consecutive frames agree as the vehicle moves);
// nothing is stored per texel. Rendering is deterministic: the same map, options, camera, pose and
// time give byte-identical frames.
//
// The map's landmarks (Map::landmarks()) stand on that plane: a pixel shows the nearest
// landmark its ray meets above the ground (and below the landmark's top) before the ground.
//  - pole, bollard: a vertical cylinder (radius, height), grey metal shaded by the sun; a bollard
//    with a light band at 72–84 % of its height;
//  - tree: a trunk (a cylinder of its radius) up into a crown, a sphere of radius 0.3 × height
//    centred at 0.7 × height (its top at the height, its bottom at 40 % of it: the trunk's visible
//    part) with a seeded ragged outline;
//  - bench: a box 2 × radius long along its road (Map::roadBeside), 0.5 m deep, solid up to its seat
//    at 0.45 m, and its back (the 0.08 m of the box away from the road) up to its height;
//  - manhole: a dark-grey disc with a rim painted on the ground (no height, no shadow).
// Each upright landmark casts a shadow away from the sun (WorldOptions::sun_azimuth_rad,
// sun_elevation_rad), height / tan(elevation) long and its diameter wide (a crown's: an ellipse),
// by the same model as the canopies (C1 = k·C2, tinted), so World::shadowAt includes them. The
// seeded canopies (shadow_density) stay: they model trees the map does not hold. A landmark's
// surface is lit by the sun by its facing alone (the side away from it is k·C, tinted); no shadow
// falls on it. Frame::mask is 0 where a landmark stands in front of the road; Frame::landmarks
// and landmark_mask give the landmarks' truth. A frame pays only for the landmarks that may show
// in it (culled by the ground it sees, then by the pixels each projects to): a map without
// landmarks renders the very bytes it rendered before they existed.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/image/image.h"
#include "mapnav/map/map.h"

namespace mapnav {

struct WorldOptions {
  /// Seeds every random effect (texture, cracks, trees, leaves, sensor noise).
  std::uint64_t seed = 1;

  // --- Pavement --------------------------------------------------------------------------------
  /// Scales the texture noise of concrete and asphalt (mottling and grain; 1 = the surface's
  /// `spread` from the map, 0 = flat colour). In [0, 1000].
  double pavement_noise = 1.0;
  /// Distance between the gaps of concrete slabs along a road (and the slab grid of concrete
  /// intersections), m; 0 = no gaps. In [0, 1000].
  double slab_spacing_m = 1.5;
  /// Width of a gap between slabs, m. In (0, 1000].
  double slab_gap_width_m = 0.02;
  /// A gap's colour is (1 − this) × the concrete's: 0 = invisible, 1 = black. In [0, 1].
  double slab_gap_darkness = 0.55;
  /// Fraction of concrete slabs (and of asphalt area) that is cracked. In [0, 1].
  double crack_density = 0.3;
  /// Brownish dust and stains on pavement, 0 = clean, 1 = strong. In [0, 1].
  double dust = 0.4;

  // --- Shoulders ---------------------------------------------------------------------------------
  /// Scales the texture of grass, dirt, gravel and brick (1 = the map's `spread`). In [0, 1000].
  double ground_noise = 1.0;
  /// How far from a road's edge its `left`/`right` shoulder surface reaches before the lawn
  /// ("grass", when the map has it) takes over, m. In [0, 1000].
  double shoulder_width_m = 2.5;

  // --- Illumination ------------------------------------------------------------------------------
  /// Fraction of the ground near roads in tree shadow (seeded canopies: clusters of discs beside
  /// roads). 0 = no trees; ≥ 0.999 = every ground point is in full shadow (a test hook). In [0, 1].
  double shadow_density = 0.2;
  /// Shadowed colour = k × sunlit colour (the paper's C1 = k·C2), before the blue shift. In (0, 1].
  double shadow_k = 0.45;
  /// Skylight tint of shadows: the shadowed colour is multiplied per channel by
  /// (1 − b, 1, 1 + b). 0 = pure k·C. In [0, 1).
  double shadow_blue_shift = 0.12;
  /// Fraction of the ground covered by fallen leaves (more under trees). In [0, 1].
  double leaf_density = 0.02;
  /// Relative amplitude of the slow brightness drift along a mission: brightness gain
  /// 1 + a·sin(2π t / period). In [0, 1).
  double illumination_drift = 0.08;
  /// Relative amplitude of the white-balance drift: channel gains (1 + w·s, 1, 1 − w·s) with
  /// s = sin(2π t / (1.618 · period)). In [0, 1).
  double white_balance_drift = 0.04;
  /// Period of both drifts, s. > 0.
  double illumination_period_s = 120.0;
  /// Aerial perspective: ground at range d blends toward the horizon haze by 1 − exp(−d / this),
  /// m; 0 = no haze. In [0, 1e9].
  double haze_distance_m = 700.0;

  // --- Camera --------------------------------------------------------------------------------------
  /// Standard deviation of the sensor noise, 8-bit levels (0 = none). In [0, 1000].
  double noise_sigma = 2.0;
  /// A real sensor integrates light over each pixel, so a pixel the paved area's edge crosses is
  /// a mix of pavement and shoulder. The renderer samples every pixel at its centre (textures,
  /// lines and shadows are filtered by the pixel's footprint), and a pixel whose centre's class
  /// (paved or not) differs from a 4-neighbour's is rendered as the mean of n × n samples over
  /// the pixel. 1 = the centre alone (the edge a whole pixel).
  /// Frame::mask stays the centre's class. In [1, 16].
  int paved_edge_samples = 1;
  /// The paper's TV transmission (3.4.2): chroma turned by tv_hue_shift_rad (plus a slow wobble of
  /// ±0.05 rad), scaled by tv_chroma_gain and blurred horizontally over ±tv_chroma_blur_px pixels.
  bool tv_color_shift = false;
  double tv_hue_shift_rad = 0.15;  ///< finite
  double tv_chroma_gain = 0.85;    ///< in [0, 2]
  int tv_chroma_blur_px = 2;       ///< in [0, 16]
  // --- Sun (the map's landmarks) ------------------------------------------------------------------
  /// Where the sun stands, for the map's landmarks alone (their shading and the shadows they cast
  /// on the ground; the seeded canopies' shadows lie straight below them): its azimuth, rad,
  /// counter-clockwise from +x (east). Default −2.0 (114.6° clockwise from east: south-south-west,
  /// an afternoon sun in the northern hemisphere), so shadows fall toward north-north-east. Finite.
  double sun_azimuth_rad = -2.0;
  /// The sun's elevation above the horizon, rad: a shadow is height / tan(elevation) long.
  /// Default 0.7 (40°: shadows 1.19 × the height). In [0.1, π/2].
  double sun_elevation_rad = 0.7;

  /// The paper's TV camera of 7:1 dynamic range (3.4.3): every channel is clipped to [37, 255], so
  /// shadows on dark surfaces become flat splotches of black level and max/min ≤ 255/37 < 7.
  bool low_dynamic_range = false;

  /// Memory for the ground's colour kept in world space across frames, MiB; 0 (the default) =
  /// none: every pixel shaded on its own. With a cache the renderer shades the ground once per
  /// texel, on a world grid per level of footprint (1/1024 m · 2^level) kept across frames, and a
  /// pixel takes the bilinear samples of the two levels around its footprint, then adds the shadows
  /// of the map's landmarks at its own point and its haze. The masks, the landmarks and the colours
  /// of the pixels beside the paved area's edge and on manhole covers stay the per-pixel
  /// renderer's; the other colours differ from its by the texels' interpolation (about 1 level on
  /// average, the finest grain a little smoother: docs/measurements.md). It pays where consecutive
  /// frames are close (a camera at video rate), not for a lone frame (the speeds:
  /// docs/measurements.md). 64 holds a frame's texels many times over. The frame does not depend on
  /// what the cache held, nor on the threads. In [0, 1e6].
  double texel_cache_mib = 0;
  /// Runtime threads: bands of rows rendered in parallel (1 = this thread only, 0 = every core).
  /// The frame does not depend on it. Default 1: the simulator's callers (tests, missions) often
  /// run side by side on every core already. In [0, 256].
  int threads = 1;

  /// Throws InvalidInput naming the first bad field and its value (worldOptionTable()'s rules).
  void validate() const;
};

/// WorldOptions' fields by name, with their rules: validate() and the mission file's `world` block.
const OptionTable<WorldOptions>& worldOptionTable();

/// A map landmark in a rendered frame (Frame::landmarks): one whose ground contact point
/// (Landmark::position) projects into the image and that a nearer landmark does not hide (some
/// pixel shows it, or nothing hides its base from the optical centre).
struct LandmarkInView {
  std::size_t index = 0;  ///< in Map::landmarks()
  /// The pixel of its base: where it meets the ground nearest the camera, i.e. the point of a
  /// post's, bollard's or trunk's circle toward the optical centre (position + radius × the unit
  /// vector toward the optical centre's ground point), the point of a bench's footprint nearest
  /// that ground point; a manhole cover's centre. Image frame, may lie outside the image.
  Vec2 base_px = Vec2::Zero();
  /// The pixel of the point `height` above the base (a manhole's: its base's). May lie outside;
  /// nothing when the lens cannot image it (above a pin-hole's near plane, beyond a fish-eye's field).
  std::optional<Vec2> top_px;
  /// No nearer landmark stands between the optical centre and the base.
  bool base_visible = false;
  /// How many pixels show it (its pixels in landmark_mask).
  int pixels = 0;
};

/// One rendered camera frame.
struct Frame {
  Image rgb;   ///< 3 channels
  Image mask;  ///< 1 channel: 255 where the pixel shows the ground (no landmark stands in front of
               ///< it) and its ground point is on a road or intersection's paved area (a manhole
               ///< cover in the paving included), 0 elsewhere (shoulders, sky, outside the lens'
               ///< field, a pole or tree in front of the road)
  /// 1 channel: 255 where the pixel shows a map landmark (a standing one, or a manhole cover's
  /// disc on the ground), 0 elsewhere. All 0 for a map without landmarks.
  Image landmark_mask;
  /// The landmarks in view, by index in Map::landmarks() (see LandmarkInView).
  std::vector<LandmarkInView> landmarks;
};

/// For each pixel of a camera, the ground point (vehicle frame) its centre's ray meets, or the sky.
/// Build once per camera and keep: a frame is then a transform plus lookups.
class RayTable {
 public:
  enum class Kind : std::uint8_t { None, Ground, Sky };
  struct Ray {
    float x = 0, y = 0;      ///< Ground: the vehicle-frame ground point, m
    float footprint = 0;     ///< Ground: the pixel's size on the ground (its longer side), m
    float range = 0;         ///< Ground: distance from the optical centre, m
    float elevation = 0;     ///< Sky: the ray's angle above the horizon, rad
    Kind kind = Kind::None;  ///< None: outside the lens' field (black)
  };

  explicit RayTable(const Camera& camera);
  int width() const { return width_; }
  int height() const { return height_; }
  /// The camera it was built for (a copy: the same model, intrinsics and mount).
  const Camera& camera() const { return *camera_; }
  const std::vector<Ray>& rays() const { return rays_; }
  const Ray& at(int u, int v) const { return rays_[static_cast<std::size_t>(v) * width_ + u]; }
  /// True when built for a camera with this model, intrinsics and mount.
  bool matches(const Camera& camera) const;
  /// A number unique to this table among those built in the process (a copy keeps it: the same
  /// rays), so a World can keep what it derives from the rays (the haze of each pixel's range).
  std::uint64_t id() const { return id_; }

 private:
  LensModel model_;
  CameraIntrinsics intrinsics_;
  CameraMount mount_;
  int width_ = 0, height_ = 0;
  std::uint64_t id_ = 0;
  std::shared_ptr<const Camera> camera_;
  std::vector<Ray> rays_;
};

class World {
 public:
  /// Copies what it needs from the map (the map need not outlive the world). Validates options.
  World(const Map& map, const WorldOptions& options = {});
  ~World();
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;

  /// The frame a camera on a vehicle at `pose` (world frame) sees at mission time t (s). The ray
  /// table is cached per camera (model, intrinsics, mount; the last few cameras). Thread-safe.
  Frame render(const Camera& camera, const Pose2& pose, double t) const;
  /// Same, with a ray table the caller keeps.
  Frame render(const RayTable& rays, const Pose2& pose, double t) const;

  /// Ground truth at a world point: on a road's or an intersection's paved area.
  bool isPaved(const Vec2& world_point) const;
  /// How much a world point is in shadow (the canopies' and the landmarks'): 0 sunlit … 1 full.
  double shadowAt(const Vec2& world_point) const;
  /// The landmarks (indices in Map::landmarks(), ascending) a frame from `pose` tests: those whose
  /// body, shadow or cover may show in the image. The others cost the frame nothing.
  std::vector<std::size_t> landmarksInView(const RayTable& rays, const Pose2& pose) const;
  const WorldOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mapnav
