#pragma once
// `mapnav suite random-campus`: the suite of unseen maps (mission_sim/suite.h) — random
// campuses and their missions run closed loop at the defaults, a row per seed as it finishes, then
// the summary beside the suite's targets.
#include <cstddef>
#include <iosfwd>
#include <string>

#include "mapnav/mission_sim/suite.h"

namespace mapnav::cli {

struct SuiteConfig {
  std::string seeds = "1-30";  ///< --seeds, parsed by parseSeedList
  /// --junctions, --max-frames, --threads: the library's options and defaults (the seeds, the camera
  /// and the folder are set from the other flags).
  SuiteOptions options;
  std::string output;          ///< -o: keep each seed's map and mission there ("": a temporary folder, removed)
  std::string map_options_json;  ///< --map-options: SuiteOptions::map as a JSON object ("": the defaults)
  bool json = false;
  bool wall_time = true;       ///< false (--no-wall-time): the same bytes for the same seeds
};

/// Exit codes: 0 every run reached its goal within 0.3 m (or --max-frames cut it), 1 some did not,
/// 2 usage or I/O error.
int runSuiteCommand(const SuiteConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
