#pragma once
// A mission in closed loop in the simulator (`mapnav run`, Python's `mapnav.run`): the simulated
// plant (sim/plant.h) renders each camera frame at the vehicle's true pose and reads its odometry
// sensor, and the mission runner's four modules drive it (mission/frame_source.h,
// runClosedLoopOver). Poses are world frame (x, y in m, heading in rad), times mission time in s.
#include "mapnav/mission/mission_file.h"
#include "mapnav/mission/runner.h"

namespace mapnav {

/// Closed loop in the synthetic world of the mission's `world` and `odometry` blocks (their seeds
/// overridden by RunOptions::seed: the world's by it, the odometry's by it + 1). Throws as runReplay,
/// and ValidationError naming the mission's file for a bad `world` or `odometry` block.
MissionRun runClosedLoop(const MissionFile& mission, const RunOptions& options = {});

}  // namespace mapnav
