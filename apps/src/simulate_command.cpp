#include "simulate_command.h"

#include <cstdio>
#include <ostream>

#include "cli.h"
#include "command_support.h"
#include "mapnav/mission/simulate.h"

namespace mapnav::cli {

int runSimulate(const SimulateConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    const MissionFile mission = loadMission(config.mission);
    SimulateOptions options;
    options.seed = config.seed;
    options.max_frames = config.max_frames;
    const SimulateResult r = simulate(mission, config.output, options);
    char line[256];
    std::snprintf(line, sizeof line, "wrote %s: %zu frames, %.1f s, %.1f m driven of a %.1f m route through %zu intersections%s\n",
                  config.output.c_str(), r.frames, r.duration_s, r.distance_m, r.route_length_m, r.intersections.size(),
                  r.reached_goal ? ", goal reached" : "");
    out << line;
    return static_cast<int>(kOk);
  });
}

}  // namespace mapnav::cli
