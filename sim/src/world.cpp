// The synthetic world (see world.h): the validation of its options, and World's construction and
// point queries. The scene is built in world_scene.cpp, shaded in world_shading.cpp and rendered in
// world_render.cpp.
#include "mapnav/sim/world.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "world_scene.h"

namespace mapnav {

const OptionTable<WorldOptions>& worldOptionTable() {
  using O = WorldOptions;
  const OptionRule kFraction = inRange(0, 1), kBelowOne = {.min = 0, .max = 1, .max_open = true};
  static const OptionTable<O> table =
      OptionTable<O>("WorldOptions")
          .field("seed", &O::seed, "seeds every random effect (texture, cracks, trees, leaves, sensor noise)")
          .field("pavement_noise", &O::pavement_noise, inRange(0, 1e3),
                 "scales the texture noise of concrete and asphalt (1: the map's spread, 0: flat colour)")
          .field("slab_spacing_m", &O::slab_spacing_m, inRange(0, 1e3),
                 "distance between the gaps of concrete slabs along a road, m; 0: no gaps")
          .field("slab_gap_width_m", &O::slab_gap_width_m, aboveUpTo(0, 1e3), "width of a gap between slabs, m")
          .field("slab_gap_darkness", &O::slab_gap_darkness, kFraction,
                 "a gap's colour is (1 - this) x the concrete's: 0 invisible, 1 black")
          .field("crack_density", &O::crack_density, kFraction,
                 "fraction of concrete slabs (and of asphalt area) that is cracked")
          .field("dust", &O::dust, kFraction, "brownish dust and stains on pavement: 0 clean, 1 strong")
          .field("ground_noise", &O::ground_noise, inRange(0, 1e3),
                 "scales the texture of grass, dirt, gravel and brick (1: the map's spread)")
          .field("shoulder_width_m", &O::shoulder_width_m, inRange(0, 1e3),
                 "how far from a road's edge its shoulder surface reaches before the lawn takes over, m")
          .field("shadow_density", &O::shadow_density, kFraction,
                 "fraction of the ground near roads in tree shadow (0: no trees; >= 0.999: all in full shadow)")
          .field("shadow_k", &O::shadow_k, aboveUpTo(0, 1), "shadowed colour = k x sunlit colour (C1 = k C2)")
          .field("shadow_blue_shift", &O::shadow_blue_shift, kBelowOne,
                 "skylight tint of shadows: channels x (1 - b, 1, 1 + b); 0: pure k C")
          .field("leaf_density", &O::leaf_density, kFraction, "fraction of the ground covered by fallen leaves")
          .field("illumination_drift", &O::illumination_drift, kBelowOne,
                 "relative amplitude of the slow brightness drift along a mission")
          .field("white_balance_drift", &O::white_balance_drift, kBelowOne,
                 "relative amplitude of the white-balance drift")
          .field("illumination_period_s", &O::illumination_period_s, above(0), "period of both drifts, s")
          .field("haze_distance_m", &O::haze_distance_m, inRange(0, 1e9),
                 "ground at range d blends toward the horizon haze by 1 - exp(-d / this), m; 0: no haze")
          .field("noise_sigma", &O::noise_sigma, inRange(0, 1e3), "standard deviation of the sensor noise, 8-bit levels")
          .field("paved_edge_samples", &O::paved_edge_samples, inRange(1, 16),
                 "a pixel the paved area's edge crosses is the mean of n x n samples (1: the centre alone)")
          .field("tv_color_shift", &O::tv_color_shift,
                 "the paper's TV transmission: chroma turned, scaled and blurred horizontally")
          .field("tv_hue_shift_rad", &O::tv_hue_shift_rad, "the TV transmission's chroma turn, rad")
          .field("tv_chroma_gain", &O::tv_chroma_gain, inRange(0, 2), "the TV transmission's chroma scale")
          .field("tv_chroma_blur_px", &O::tv_chroma_blur_px, inRange(0, 16),
                 "the TV transmission's horizontal chroma blur, +- pixels")
          .field("sun_azimuth_rad", &O::sun_azimuth_rad,
                 "where the sun stands for the map's landmarks, rad counter-clockwise from east")
          .field("sun_elevation_rad", &O::sun_elevation_rad, inRange(0.1, kPi / 2),
                 "the sun's elevation, rad: a landmark's shadow is height / tan(elevation) long")
          .field("low_dynamic_range", &O::low_dynamic_range,
                 "the paper's TV camera of 7:1 dynamic range: every channel clipped to [37, 255]")
          .field("texel_cache_mib", &O::texel_cache_mib, inRange(0, 1e6),
                 "memory for the ground's colour kept in world space across frames, MiB; 0: none")
          .field("threads", &O::threads, inRange(0, 256),
                 "bands of rows rendered in parallel (1: this thread only, 0: every core)");
  return table;
}

void WorldOptions::validate() const { worldOptionTable().validate(*this); }

World::World(const Map& map, const WorldOptions& options) : impl_(std::make_unique<Impl>(map, options)) {}
World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

const WorldOptions& World::options() const { return impl_->options; }

bool World::isPaved(const Vec2& p) const { return impl_->pavedAt(p, impl_->cellLists(impl_->cellIndex(p))) >= 0; }

double World::shadowAt(const Vec2& p) const {
  float bare = 0, flecked = 0;
  const world_detail::CellLists lists = impl_->cellLists(impl_->cellIndex(p));
  impl_->canopy(p, lists, 0.0, nullptr, bare, flecked);
  return std::max(flecked, impl_->landmarks.marksAt(p, lists.marks, lists.n_marks, 0.0, nullptr, nullptr));
}

}  // namespace mapnav
