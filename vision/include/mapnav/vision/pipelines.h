#pragma once
// The built-in vision pipelines:
//   "sidewalk"  normalised-rg Gaussian classifier + region reproduction + line labelling (the default)
//   "color-rgb" the same with an RGB classifier (3.4, before 3.4.3)
//   "blue-band" a threshold on the blue channel (3.6.3, the Warp runs), region + labelling
// Their options, with defaults, are listed in PipelineInfo::options (listPipelines()).
#include <string>

namespace mapnav {

/// Registers the built-in pipelines (idempotent).
void registerBuiltinPipelines();

/// The default pipeline's name: "sidewalk".
inline constexpr const char* kDefaultPipeline = "sidewalk";

}  // namespace mapnav
