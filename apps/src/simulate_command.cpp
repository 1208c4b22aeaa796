#include "simulate_command.h"

#include <cstdint>
#include <cstdio>
#include <ostream>

#include "cli.h"
#include "command_line.h"
#include "command_support.h"
#include "mapnav/mission_sim/simulate.h"

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

void registerSimulateCommand(CLI::App& app, Commands& commands) {
  auto* simulate = commands.hold<SimulateConfig>();
  auto* seed = commands.hold<std::int64_t>();
  *seed = -1;
  CLI::App* sim = app.add_subcommand("simulate", "Drive a mission in the synthetic world and write its replay log");
  sim->add_option("--mission", simulate->mission, "Mission file (mapnav-mission/1, docs/mission-format.md)")
      ->required()
      ->check(CLI::ExistingFile);
  sim->add_option("-o,--output", simulate->output, "Log folder to write (must not exist, or be empty)")->required();
  sim->add_option("--seed", *seed, "Seed for the world and the odometry noise (default: the mission's)")
      ->check(commands.numberCheck(CLI::Range(std::int64_t{0}, std::int64_t{9007199254740991})));
  sim->add_option("--max-frames", simulate->max_frames, "Stop after this many frames (default: drive to the goal)");
  sim->footer("The same mission and seed give the same bytes. Exit codes: 0 written, 1 invalid mission or no route,\n"
              "2 usage or I/O error (nothing is left in the output folder on failure).");
  sim->callback(commands.choose([simulate, seed](std::ostream& out, std::ostream& err) {
    if (*seed >= 0) simulate->seed = static_cast<std::uint64_t>(*seed);
    return runSimulate(*simulate, out, err);
  }));
}

}  // namespace mapnav::cli
