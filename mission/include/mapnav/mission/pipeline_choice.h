#pragma once
// Which vision pipeline a mission runs (docs/mission-format.md, "Which pipeline"): the one the
// caller names (RunOptions::pipeline), else the mission's `vision.pipeline`, else the one the surfaces of
// the roads its route drives call for — or an error that says to name one, never a silent default.
#include <string>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/map/map.h"

namespace mapnav {

/// A mission that names no pipeline, on roads whose surfaces do not decide one (pipelineForRoads);
/// what() says which roads call for which pipeline. The CLI adds its flag to the advice.
class NoPipelineChosen : public InvalidInput {
 public:
  using InvalidInput::InvalidInput;
};

/// The pipeline that each of the map format's six surfaces calls for, when a mission names none:
///   concrete, brick        → "sidewalk"      (Wallace 1985 §2: the campus sidewalks, a colour
///                                              classifier on paved slabs, its region's lines
///                                              labelled against the map's edges)
///   asphalt, gravel        → "color-rgb"     (Wallace 1985 §3.4: Gaussian classes in RGB, whose
///                                              brightness parts a grey road from grey gravel and
///                                              kerbs, which normalised colour cannot;
///                                              docs/measurements.md)
///   dirt                   → "edge-tracker"  (§3: the park path, its edges followed up the frame)
///   grass, any other name  → none (no pipeline here is known to follow it)
/// Returns "" for a surface that calls for none.
std::string pipelineForSurface(const std::string& surface);

/// The pipeline that the surfaces of `roads` (ids of `map`, the roads a route drives) call for, when
/// they all call for the same one; on a route over paved surfaces of both families (asphalt or
/// gravel, and concrete or brick) "sidewalk", which keeps a road class per surface in view and at
/// its defaults follows both (the random-campus suite's 14 asphalt/gravel campuses all within 0.3 m
/// of the goal with it, park_loop's asphalt 0.04 m; docs/mission-format.md). Throws
/// NoPipelineChosen otherwise (a route with dirt, grass or an unknown surface beside another),
/// saying which roads call for which pipeline (or for none) and to name the pipeline in the
/// mission's `vision.pipeline` or for the run; `what` (the mission) starts the message. Throws
/// NotFound for an unknown road id.
std::string pipelineForRoads(const Map& map, const std::vector<std::string>& roads, const std::string& what);

}  // namespace mapnav
