#include "mapnav/sim/world_io.h"

#include <cmath>
#include <utility>

#include "mapnav/core/error.h"
#include "mapnav/core/json.h"

namespace mapnav {

WorldOptions parseWorldOptions(const std::string& json, const std::string& pointer, Issues& issues) {
  WorldOptions o;
  const auto parsed = parseJson(json, issues);
  if (!parsed) return o;
  JsonObject block(*parsed, pointer, issues);
  if (const auto seed = block.number("seed", false, 0, 9007199254740992.0)) o.seed = static_cast<std::uint64_t>(*seed);
  // Numbers: read by name; WorldOptions::validate() below judges the values and names the field.
  const std::pair<const char*, double WorldOptions::*> numbers[] = {
      {"pavement_noise", &WorldOptions::pavement_noise},
      {"slab_spacing_m", &WorldOptions::slab_spacing_m},
      {"slab_gap_width_m", &WorldOptions::slab_gap_width_m},
      {"slab_gap_darkness", &WorldOptions::slab_gap_darkness},
      {"crack_density", &WorldOptions::crack_density},
      {"dust", &WorldOptions::dust},
      {"ground_noise", &WorldOptions::ground_noise},
      {"shoulder_width_m", &WorldOptions::shoulder_width_m},
      {"shadow_density", &WorldOptions::shadow_density},
      {"shadow_k", &WorldOptions::shadow_k},
      {"shadow_blue_shift", &WorldOptions::shadow_blue_shift},
      {"leaf_density", &WorldOptions::leaf_density},
      {"illumination_drift", &WorldOptions::illumination_drift},
      {"white_balance_drift", &WorldOptions::white_balance_drift},
      {"illumination_period_s", &WorldOptions::illumination_period_s},
      {"haze_distance_m", &WorldOptions::haze_distance_m},
      {"noise_sigma", &WorldOptions::noise_sigma},
      {"tv_hue_shift_rad", &WorldOptions::tv_hue_shift_rad},
      {"tv_chroma_gain", &WorldOptions::tv_chroma_gain},
      {"sun_azimuth_rad", &WorldOptions::sun_azimuth_rad},
      {"sun_elevation_rad", &WorldOptions::sun_elevation_rad},
  };
  for (const auto& [name, member] : numbers) {
    if (const auto v = block.number(name, false)) o.*member = *v;
  }
  if (const auto v = block.number("paved_edge_samples", false, 1, 16)) o.paved_edge_samples = static_cast<int>(std::lround(*v));
  if (const auto v = block.number("tv_chroma_blur_px", false, 0, 16)) o.tv_chroma_blur_px = static_cast<int>(std::lround(*v));
  if (const auto v = block.number("texel_cache_mib", false, 0, 1e6)) o.texel_cache_mib = *v;
  if (const auto v = block.number("threads", false, 0, 256)) o.threads = static_cast<int>(std::lround(*v));
  if (const auto v = block.boolean("tv_color_shift", false)) o.tv_color_shift = *v;
  if (const auto v = block.boolean("low_dynamic_range", false)) o.low_dynamic_range = *v;
  block.rejectUnknownMembers();
  try {
    o.validate();
  } catch (const InvalidInput& e) {
    addIssue(issues, Severity::Error, "schema.range", pointer, e.what());
  }
  return o;
}

}  // namespace mapnav
