#pragma once
// `mapnav replay`, `mapnav run` and `mapnav trace show`: the mission runner (mission/runner.h) on the
// command line, with a progress bar on a terminal and a summary (or --json) at the end.
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace mapnav::cli {

/// What replay and run share.
struct MissionRunConfig {
  std::string mission;                 ///< mapnav-mission/1 file
  std::string pipeline;                ///< "" : the mission's vision.pipeline, else "sidewalk"
  std::string options_json;            ///< the pipeline's options, a JSON object; "" : the mission's vision.options
  std::vector<std::string> plugins;    ///< vision plug-ins to load first
  std::string trace;                   ///< JSONL trace to write ("" = none)
  std::size_t max_frames = 0;          ///< 0: to the end
  bool json = false;                   ///< print the metrics as one JSON object instead of the summary
  bool progress = false;               ///< draw a progress bar on stderr (the CLI sets it when stderr is a TTY)
  /// The HTML report folder (docs/report.md): report.html and trajectories.geojson, and the trace
  /// (trace.jsonl) when `trace` is not set; "" = none.
  std::string report_dir;
  /// Fault injection, "FRAME,FORWARD,LEFT" ("": none): RunOptions::displace.
  std::string displace;
  /// The Map module's options, a JSON object ("": the defaults): RunOptions::map.
  std::string map_options_json;
  /// replay --use-gnss: fuse the log's GNSS fixes (MapModuleOptions::use_gnss on top of the map options).
  bool use_gnss = false;
};

struct ReplayConfig : MissionRunConfig {
  std::string log;  ///< the replay log folder (`mapnav simulate`)
  bool strict = false;  ///< stop at the first fault of the log (RunOptions::strict)
};

struct RunConfig : MissionRunConfig {
  std::optional<std::uint64_t> seed;  ///< overrides the world's and the odometry's seeds
};

/// `mapnav demo`: the paper's dialogue mission on the campus map, simulated, replayed and reported.
struct DemoConfig {
  std::string output = "out/demo";  ///< the folder: log/, trace.jsonl, report.html, trajectories.geojson
  std::string mission;              ///< "" : maps/missions/campus_dialogue.json (installed or the source tree's)
  std::size_t max_frames = 0;       ///< 0: the whole mission
  bool progress = false;            ///< a progress bar on stderr
};

struct TraceShowConfig {
  std::string file;
};

/// `mapnav replay`: open loop over a recorded log. Exit 0 when the goal was reached (or --max-frames
/// stopped it first), 1 when the mission failed (halted, goal not reached) or the input is invalid,
/// 2 usage or I/O error.
int runReplayCommand(const ReplayConfig& config, std::ostream& out, std::ostream& err);
/// `mapnav run`: closed loop in the simulator. Exit codes as replay.
int runRunCommand(const RunConfig& config, std::ostream& out, std::ostream& err);
/// `mapnav demo`: simulate the mission to DIR/log (replacing a replay log left there by an earlier
/// demo, never anything else), replay it with the mission's pipeline, write the trace and the report
/// in DIR, print the summary and the report's path. Exit codes as replay.
int runDemo(const DemoConfig& config, std::ostream& out, std::ostream& err);
/// `mapnav trace show`: the trace as the paper's dialogue. Exit 1 for bad lines (FILE:LINE:1: ...).
int runTraceShow(const TraceShowConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
