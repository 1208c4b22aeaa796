// The synthetic world (see world.h): the validation of its options, and World's construction and
// point queries. The scene is built in world_scene.cpp, shaded in world_shading.cpp and rendered in
// world_render.cpp.
#include "mapnav/sim/world.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string_view>

#include "mapnav/core/options.h"
#include "world_scene.h"

namespace mapnav {

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
  requireOption(std::isfinite(sun_azimuth_rad), kOwner, "sun_azimuth_rad", sun_azimuth_rad, "finite");
  requireOption(finiteIn(sun_elevation_rad, 0.1, kPi / 2), kOwner, "sun_elevation_rad", sun_elevation_rad,
                "in [0.1, pi/2]");
  requireOption(std::isfinite(tv_hue_shift_rad), kOwner, "tv_hue_shift_rad", tv_hue_shift_rad, "finite");
  requireOption(finiteIn(tv_chroma_gain, 0, 2), kOwner, "tv_chroma_gain", tv_chroma_gain, "in [0, 2]");
  requireOption(paved_edge_samples >= 1 && paved_edge_samples <= 16, kOwner, "paved_edge_samples",
                paved_edge_samples, "in [1, 16]");
  requireOption(finiteIn(texel_cache_mib, 0, 1e6), kOwner, "texel_cache_mib", texel_cache_mib, "in [0, 1e6]");
  requireOption(threads >= 0 && threads <= 256, kOwner, "threads", threads, "in [0, 256]");
  requireOption(tv_chroma_blur_px >= 0 && tv_chroma_blur_px <= 16, kOwner, "tv_chroma_blur_px", tv_chroma_blur_px,
                "in [0, 16]");
}

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
