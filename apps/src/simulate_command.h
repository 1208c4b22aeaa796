#pragma once
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>

namespace mapnav::cli {

struct SimulateConfig {
  std::string mission;
  std::string output;                  ///< the log directory to write
  std::optional<std::uint64_t> seed;   ///< overrides the mission's seeds
  std::size_t max_frames = 0;          ///< 0: to the goal
};

/// `mapnav simulate`: drive a mission in the synthetic world and write its replay log.
int runSimulate(const SimulateConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
