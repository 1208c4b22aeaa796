#pragma once
// `mapnav simulate`: plan the mission's route, drive it with a controller on the true pose (with a
// gentle lateral wander), render each camera frame from the map (the renderer, sim/world.h), and
// write a replay log (logs/replay_log.h) with the ground truth. Distances m, times s.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/mission/mission_file.h"

namespace mapnav {

struct SimulateOptions {
  /// Overrides the world's seed (and the odometry's, as seed + 1): same seed, same bytes.
  std::optional<std::uint64_t> seed;
  /// Stop after this many frames (0: drive to the goal).
  std::size_t max_frames = 0;
  /// The controller's and the vehicle's time step, s.
  double control_dt_s = 0.05;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// The options' names, rules and descriptions (`seed`, which may be unset, is not in it: it has no
/// rule); validate() checks them.
const OptionTable<SimulateOptions>& simulateOptionTable();

struct SimulateResult {
  std::size_t frames = 0;
  double distance_m = 0;            ///< driven (true)
  double duration_s = 0;
  double route_length_m = 0;
  std::vector<std::string> intersections;  ///< passed, in order (with repeats across legs)
  bool reached_goal = false;
};

/// Runs the mission and writes the log to `log_dir` (which must not exist or be empty; nothing is
/// left there on failure). Throws ValidationError / InvalidInput / Unreachable / IoError.
SimulateResult simulate(const MissionFile& mission, const std::filesystem::path& log_dir,
                        const SimulateOptions& options = {});

}  // namespace mapnav
