#include "suite_command.h"

#include <filesystem>
#include <ostream>
#include <system_error>
#include <unistd.h>

#include "cli.h"
#include "command_line.h"
#include "command_support.h"
#include "pipelines_command.h"
#include "mapnav/core/error.h"
#include "mapnav/mission_sim/suite.h"
#include "mapnav/vision/pipelines.h"

namespace mapnav::cli {

namespace fs = std::filesystem;

namespace {

// A folder of our own under the system's temporary folder, removed when the run is over.
class TemporaryFolder {
 public:
  TemporaryFolder() {
    const fs::path base = fs::temp_directory_path();
    for (int k = 0; k < 1000 && path_.empty(); ++k) {
      const fs::path p = base / ("mapnav-suite-" + std::to_string(::getpid()) + "-" + std::to_string(k));
      std::error_code ec;
      if (fs::create_directory(p, ec)) path_ = p;
    }
    if (path_.empty()) throw IoError(base.string() + ": cannot create a temporary folder for the suite's maps");
  }
  ~TemporaryFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

}  // namespace

int runSuiteCommand(const SuiteConfig& config, std::ostream& out, std::ostream& err) {
  SuiteOptions options = config.options;
  options.seeds = namingFlag("--seeds", [&] { return parseSeedList(config.seeds); });
  options.map = parseMapModuleOptions(config.map_options_json);
  options.camera = dataPath("maps/cameras/terregator_pinhole.json");
  return guarded(err, [&] {
    loadPlugins({});
    std::optional<TemporaryFolder> temporary;
    if (config.output.empty()) {
      temporary.emplace();
      options.folder = temporary->path();
    } else {
      options.folder = config.output;
    }
    // Rows go to stdout as the runs finish, or with --json to stderr as progress.
    std::ostream& rows = config.json ? err : out;
    rows << suiteHeaderText(config.wall_time) << std::flush;
    const std::vector<SuiteRun> runs =
        runSuite(options, [&](const SuiteRun& r) { rows << suiteRowText(r, config.wall_time) << std::flush; });
    const SuiteSummary summary = summarizeSuite(runs);
    if (config.json) {
      out << suiteJson(options, runs, summary, config.wall_time);
    } else {
      out << suiteSummaryText(summary, config.wall_time);
      if (!config.output.empty()) {
        out << "maps and missions in " << config.output << "/seed-N/ (mapnav run --mission " << config.output
            << "/seed-N/mission.json)\n";
      }
    }
    bool ok = true;
    for (const SuiteRun& r : runs) ok = ok && (r.reached || (r.stopped_early && !r.error));
    return static_cast<int>(ok ? kOk : kInvalid);
  });
}

void registerSuiteCommand(CLI::App& app, Commands& commands) {
  CLI::App* suite = app.add_subcommand("suite", "Run a suite of missions on maps no one tuned for and sum them up");
  suite->require_subcommand(1);
  auto* config = commands.hold<SuiteConfig>();
  auto* no_wall_time = commands.hold<bool>();
  CLI::App* rc = suite->add_subcommand(
      "random-campus", "Random small campuses and their missions (map/random_campus.h), closed loop at the defaults");
  rc->add_option("--seeds", config->seeds, "Seeds, one map and mission each: ranges and lists, e.g. 1-30 or 1,4,9-12")
      ->default_str("1-30");
  rc->add_option("--junctions", config->options.campus.junctions, "Junctions along each campus' spine")
      ->capture_default_str()
      ->check(commands.ruleCheck(suiteOptionTable(), "junctions"));
  rc->add_option("--map-error-m", config->options.map_error_m,
                 "How wrong each map is, m: the world is rendered from the map with its roads moved by a smooth random\n"
                 "lateral offset of this 1-sigma (30 m correlation, widths to 5 %) while the vehicle navigates by the map;\n"
                 "truth, the path and the goal are the world's (0: the world is the map)")
      ->capture_default_str()
      ->check(commands.ruleCheck(suiteOptionTable(), "map_error_m"));
  rc->add_option("--max-frames", config->options.max_frames, "Stop each run after this many frames (default: to the goal)");
  rc->add_option("-o,--output", config->output,
                 "Keep each seed's map.json and mission.json in DIR/seed-N/ (default: a temporary folder, removed)");
  rc->add_option("--threads", config->options.threads, "Seeds run at once (the results do not depend on it)")
      ->capture_default_str()
      ->check(commands.ruleCheck(suiteOptionTable(), "threads"));
  addMapOptionsFlag(rc, config->map_options_json);
  rc->add_flag("--json", config->json, "Print one JSON object (rows go to stderr as progress)");
  rc->add_flag("--no-wall-time", *no_wall_time, "Leave out wall times: the same bytes for the same seeds");
  rc->footer(
      "For each seed: makeRandomCampus(seed) (a spine of roads through --junctions crosses, Ts, Ys and Ls, some\n"
      "roads arcs, widths 1.5-4 m, one surface family), its mission (start near the spine's first end, goal near\n"
      "its last, on half the maps via a branch's far end) written as a mission file with the defaults of one —\n"
      "the pipeline its surfaces call for, 0.6 m/s, 2 frames/s — and the shipped campus missions' shadows and\n"
      "odometry errors (1 % scale error), seeded by the seed; run closed loop as `mapnav run` runs it. A row per\n"
      "seed as it finishes: junctions, via, surfaces, pipeline, frames, reached (within 0.3 m), goal distance,\n"
      "frames off the path, lateral RMS, along max, heading RMS, the fractions of frames whose true error lies\n"
      "within 2 sigma of the filter's covariance (along, lateral, heading), mean NEES, vision failures, replans,\n"
      "wall time. Then the summary beside the suite's targets (docs/suite.md).\n"
      "Exit codes: 0 every run reached its goal within 0.3 m (or --max-frames cut it), 1 some did not, 2 usage or\n"
      "I/O error.");
  rc->callback(commands.choose([config, no_wall_time](std::ostream& out, std::ostream& err) {
    config->wall_time = !*no_wall_time;
    return runSuiteCommand(*config, out, err);
  }));
}

}  // namespace mapnav::cli
