#include "mission_commands.h"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <ostream>
#include <system_error>
#include <vector>
#include <unistd.h>

#include "cli.h"
#include "command_line.h"
#include "command_support.h"
#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/map/map_io.h"
#include "mapnav/mission/pipeline_choice.h"
#include "mapnav/mission/report.h"
#include "mapnav/mission/runner.h"
#include "mapnav/mission/trace.h"
#include "mapnav/mission_sim/closed_loop.h"
#include "mapnav/mission_sim/simulate.h"
#include "mapnav/vision/pipelines.h"
#include "pipelines_command.h"

namespace mapnav::cli {

namespace {
namespace fs = std::filesystem;

// A one-line progress bar on a terminal: frames, frames per second, time left. Redrawn at most ten
// times a second; erased at the end.
class ProgressBar {
 public:
  explicit ProgressBar(std::ostream& err) : err_(err), start_(std::chrono::steady_clock::now()) {}
  ~ProgressBar() {
    if (drawn_) err_ << "\r\033[K" << std::flush;
  }
  void update(const RunProgress& p) {
    const auto now = std::chrono::steady_clock::now();
    if (drawn_ && now - last_ < std::chrono::milliseconds(100) && p.frame < p.total) return;
    last_ = now;
    drawn_ = true;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double fps = elapsed > 0 ? static_cast<double>(p.frame) / elapsed : 0.0;
    const std::size_t total = std::max(p.total, p.frame);
    const int width = 30;
    const int filled = total > 0 ? static_cast<int>(width * static_cast<double>(p.frame) / static_cast<double>(total)) : 0;
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(width, '.');
    const double eta = fps > 0 ? static_cast<double>(total - p.frame) / fps : 0.0;
    char line[160];
    std::snprintf(line, sizeof line, "\r[%s] %zu/%zu frames  %.1f frames/s  ETA %d:%02d  t %.1f s\033[K", bar.c_str(),
                  p.frame, total, fps, static_cast<int>(eta) / 60, static_cast<int>(eta) % 60, p.t);
    err_ << line << std::flush;
  }

 private:
  std::ostream& err_;
  std::chrono::steady_clock::time_point start_, last_;
  bool drawn_ = false;
};

// A run with the progress bar and, when config.report_dir is set, the report (and the trace it
// reads back: config.trace, else REPORT/trace.jsonl). Prints nothing.
struct ReportedRun {
  MissionRun run;
  std::string trace;                  // "" : none written
  std::optional<ReportFiles> report;
};

// --displace "FRAME,FORWARD,LEFT": a frame index and two finite distances, m.
EstimateDisplacement parseDisplacement(const std::string& text) {
  const std::string expected =
      "FRAME,FORWARD,LEFT: a frame index and metres along and to the left of the estimated heading, e.g. 120,1.5,-0.8";
  const std::vector<double> v = parseNumbers("--displace", text, 3, 3, expected);
  if (v[0] < 0 || v[0] != std::floor(v[0]) || v[0] > 1e15)
    throw InvalidInput("--displace \"" + text + "\": the frame is not an index; expected " + expected);
  return EstimateDisplacement{static_cast<std::size_t>(v[0]), v[1], v[2]};
}

template <typename Runner>
ReportedRun runReported(const MissionFile& mission, const MissionRunConfig& config, std::ostream& err, Runner&& runner) {
  ReportedRun r;
  RunOptions options;
  options.pipeline = config.pipeline;
  if (!config.options_json.empty()) options.pipeline_options_json = config.options_json;
  options.max_frames = config.max_frames;
  if (!config.displace.empty()) options.displace = parseDisplacement(config.displace);
  options.map = parseMapModuleOptions(config.map_options_json);
  options.map.use_gnss = options.map.use_gnss || config.use_gnss;
  r.trace = config.trace;
  std::optional<ReportFrames> frames;
  bool created_report_dir = false;
  if (!config.report_dir.empty()) {
    std::error_code ec;
    created_report_dir = !fs::exists(config.report_dir, ec);
    fs::create_directories(config.report_dir, ec);
    if (ec) throw IoError(config.report_dir + ": cannot create the report folder: " + ec.message());
    if (r.trace.empty()) r.trace = (fs::path(config.report_dir) / "trace.jsonl").string();
    frames.emplace();
    options.on_frame = [&](const FrameView& f) { frames->add(f); };
  }
  options.trace = r.trace;
  std::optional<ProgressBar> bar;
  if (config.progress) {
    bar.emplace(err);
    options.progress = [&](const RunProgress& p) { bar->update(p); };
  }
  try {
    r.run = runner(mission, options);
    bar.reset();
    if (frames) {
      r.report = writeReport(config.report_dir, r.run, loadMap(mission.map), *frames, readFile(r.trace), r.trace);
    }
  } catch (...) {
    // A failed or interrupted run leaves no empty report folder of its own behind (remove() takes
    // only an empty folder: whatever else is in it stays).
    std::error_code ec;
    if (created_report_dir) fs::remove(config.report_dir, ec);
    throw;
  }
  return r;
}

// The summary (or --json) and what was written; the exit code: 0 when the goal was reached or the
// run was cut short on purpose (`cut_short`, or --max-frames).
int finish(const ReportedRun& r, bool json, bool cut_short, std::ostream& out) {
  if (json) {
    out << runToJson(r.run);
  } else {
    out << summaryText(r.run);
    if (!r.trace.empty()) out << "wrote " << r.trace << "\n";
    if (r.report && r.report->geojson) out << "wrote " << r.report->geojson->string() << "\n";
    if (r.report) out << "report: " << fs::absolute(r.report->html).lexically_normal().string() << "\n";
  }
  const bool ok = r.run.metrics.reached_goal || r.run.stopped_early || cut_short;
  return static_cast<int>(ok ? kOk : kInvalid);
}

template <typename Runner>
int runMissionCommand(const MissionRunConfig& config, std::ostream& out, std::ostream& err, Runner&& runner) {
  return guarded(err, [&] {
    const MissionFile mission = loadMission(config.mission);
    loadPlugins(config.plugins, config.pipeline.empty() ? mission.vision_pipeline : config.pipeline);
    try {
      return finish(runReported(mission, config, err, runner), config.json, false, out);
    } catch (const NoPipelineChosen& e) {
      throw InvalidInput(std::string(e.what()) + "; on the command line: --pipeline NAME");
    }
  });
}

// The demo's log folder may hold a replay log an earlier demo left there (it is replaced); anything
// else there is an error (the demo never deletes what it did not write).
void checkEarlierLog(const fs::path& log) {
  std::error_code ec;
  if (!fs::exists(log, ec)) return;
  bool ours = fs::is_directory(log, ec) && fs::is_regular_file(log / "log.json", ec);
  for (const fs::directory_entry& e : fs::directory_iterator(log, ec)) {
    const std::string name = e.path().filename().string();
    ours = ours && (name == "log.json" || name == "frames.jsonl" || name == "images" || name == "masks");
  }
  if (!ours || ec) {
    throw IoError(log.string() + ": exists and is not a replay log of an earlier demo; remove it or choose another -o");
  }
}

// Puts the freshly simulated log `fresh` in the place of `log` (an earlier demo's, checked).
void replaceLog(const fs::path& fresh, const fs::path& log) {
  std::error_code ec;
  fs::remove_all(log, ec);
  if (ec) throw IoError(log.string() + ": cannot remove the earlier demo's log: " + ec.message());
  fs::rename(fresh, log, ec);
  if (ec) throw IoError(log.string() + ": cannot move the new log into place: " + ec.message());
}

}  // namespace

int runReplayCommand(const ReplayConfig& config, std::ostream& out, std::ostream& err) {
  return runMissionCommand(config, out, err, [&](const MissionFile& mission, RunOptions options) {
    options.strict = config.strict;
    return runReplay(mission, config.log, options);
  });
}

int runRunCommand(const RunConfig& config, std::ostream& out, std::ostream& err) {
  return runMissionCommand(config, out, err, [&](const MissionFile& mission, RunOptions options) {
    options.seed = config.seed;
    return runClosedLoop(mission, options);
  });
}

int runDemo(const DemoConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    MissionRunConfig run;
    run.mission = config.mission.empty() ? dataPath("maps/missions/campus_dialogue.json") : config.mission;
    run.report_dir = config.output;
    run.max_frames = config.max_frames;
    run.progress = config.progress;
    const MissionFile mission = loadMission(run.mission);
    loadPlugins({}, mission.vision_pipeline);
    const fs::path log = fs::path(config.output) / "log";
    checkEarlierLog(log);
    // Simulated beside the earlier log, which is replaced only once the new one is complete: a
    // failure or Ctrl-C while simulating leaves it as it was.
    const fs::path fresh = fs::path(config.output) / "log.new";
    std::error_code ec;
    fs::remove_all(fresh, ec);  // a leftover of a crash
    out << "simulating \"" << mission.name << "\" (" << run.mission << ") to " << log.string() << " ..." << std::endl;
    SimulateOptions simulation;
    simulation.max_frames = config.max_frames;
    const SimulateResult s = simulate(mission, fresh, simulation);
    replaceLog(fresh, log);
    char line[200];
    std::snprintf(line, sizeof line, "  %zu frames, %.1f s, %.1f m driven through %zu intersections\n", s.frames,
                  s.duration_s, s.distance_m, s.intersections.size());
    out << line << "replaying it ..." << std::endl;
    const ReportedRun r = runReported(mission, run, err, [&](const MissionFile& m, const RunOptions& options) {
      return runReplay(m, log, options);
    });
    // With --max-frames the log itself is cut short: its end is the end asked for.
    return finish(r, false, config.max_frames > 0, out);
  });
}

int runTraceShow(const TraceShowConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    out << traceDialogue(readFile(config.file), config.file);
    return static_cast<int>(kOk);
  });
}

// ---- the command line: `mapnav replay`, `run`, `demo` and `trace show` --------------------------

namespace {

constexpr const char* kMissionFooter =
    "Prints a summary (or --json: {\"frames\",\"reached_goal\",\"lateral_rms_m\",\"along_rms_m\",\"heading_rms_deg\",\n"
    "\"max_error_m\",\"odometry_only_max_error_m\",\"vision_failures\",\"replans\",\"latency_ms_median\",\n"
    "\"latency_ms_p99\",\"along_after_intersection_max_m\",...,\"path_agreement\"}: with the truth, how well\n"
    "Vision's road agrees with the vehicle's true future path, as `mapnav log track` says it; null without); a\n"
    "progress bar on a terminal. Exit codes: 0 the goal was reached (or --max-frames stopped it first), 1 the\n"
    "mission failed (halted, goal not reached) or the input is invalid, 2 usage or I/O error.";

/// What replay and run share; a progress bar when stderr is a terminal.
void addMissionOptions(CLI::App* c, MissionRunConfig& config, bool stderr_is_tty) {
  c->add_option("--mission", config.mission, "Mission file (mapnav-mission/1, docs/mission-format.md)")
      ->required()
      ->check(CLI::ExistingFile);
  c->add_option("--pipeline", config.pipeline, "Vision pipeline (default: the mission's vision.pipeline, else the one the surfaces of its route's roads call for)");
  c->add_option("--options", config.options_json,
                "The pipeline's options as a JSON object (default: the mission's vision.options, when the pipeline is "
                "the mission's; e.g. '{\"model\": \"sim\"}' for --pipeline learned)");
  c->add_option("--plugin", config.plugins, "Load a vision plug-in first");
  c->add_option("--trace", config.trace, "Write the JSONL trace of every token (docs/trace-format.md)");
  c->add_option("--max-frames", config.max_frames, "Stop after this many frames (default: to the end)");
  c->add_flag("--json", config.json, "Print the metrics as one JSON object instead of the summary");
  c->add_option("--report", config.report_dir,
                "Write the HTML report (report.html), trajectories.geojson and, without --trace, trace.jsonl "
                "to this folder (docs/report.md)");
  c->add_option("--displace", config.displace,
                "Fault injection FRAME,FORWARD,LEFT: at the start of that frame the Map's estimate jumps FORWARD m "
                "along its heading and LEFT m to its left without the filter knowing (to see recovery)");
  addMapOptionsFlag(c, config.map_options_json);
  config.progress = stderr_is_tty;
}

void addReplay(CLI::App& app, Commands& commands, bool stderr_is_tty) {
  auto* replay = commands.hold<ReplayConfig>();
  CLI::App* rp = app.add_subcommand("replay", "Run a mission open loop over a recorded log: localisation and commands per frame, against the truth");
  addMissionOptions(rp, *replay, stderr_is_tty);
  rp->add_option("--log", replay->log, "Replay log folder (mapnav simulate, docs/replay-log-format.md)")
      ->required()
      ->check(CLI::ExistingDirectory);
  rp->add_flag("--use-gnss", replay->use_gnss,
               "Fuse the log's GNSS fixes into the estimate, each with its stated sigma and a chi-square gate "
               "(as the mission's \"localization\": {\"use_gnss\": true}; a KITTI raw import's fixes are a "
               "consumer receiver's, never the truth: docs/real-drive.md)");
  rp->add_flag("--strict", replay->strict,
               "Stop at the first fault of the log (missing or corrupt frame, time order, odometry spike, cut line) "
               "with an error naming frames.jsonl and the line; by default faults are skipped, counted and traced");
  rp->footer(kMissionFooter);
  rp->callback(commands.choose([replay](std::ostream& out, std::ostream& err) { return runReplayCommand(*replay, out, err); }));
}

void addRun(CLI::App& app, Commands& commands, bool stderr_is_tty) {
  auto* run = commands.hold<RunConfig>();
  auto* seed = commands.hold<std::int64_t>();
  *seed = -1;
  CLI::App* rn = app.add_subcommand("run", "Run a mission closed loop in the simulator: each frame rendered from where the commands drove");
  addMissionOptions(rn, *run, stderr_is_tty);
  rn->add_option("--seed", *seed, "Seed for the world and the odometry noise (default: the mission's)")
      ->check(commands.numberCheck(CLI::Range(std::int64_t{0}, std::int64_t{9007199254740991})));
  rn->footer(kMissionFooter);
  rn->callback(commands.choose([run, seed](std::ostream& out, std::ostream& err) {
    if (*seed >= 0) run->seed = static_cast<std::uint64_t>(*seed);
    return runRunCommand(*run, out, err);
  }));
}

void addDemo(CLI::App& app, Commands& commands, bool stderr_is_tty) {
  auto* demo = commands.hold<DemoConfig>();
  CLI::App* dm = app.add_subcommand("demo", "Simulate the paper's dialogue mission on the campus map, replay it and write the HTML report");
  dm->add_option("-o,--output", demo->output, "Folder to write (default: out/demo)");
  dm->add_option("--mission", demo->mission, "Another mission (default: maps/missions/campus_dialogue.json)")
      ->check(CLI::ExistingFile);
  dm->add_option("--max-frames", demo->max_frames, "Stop after this many frames (default: the whole mission)");
  dm->footer(
      "The whole system of Wallace et al. 1985 on one mission: \"the robot is at road R1, 3 m from I1; navigate to\n"
      "R3, 2 m from I3\". The same as\n"
      "  mapnav simulate --mission maps/missions/campus_dialogue.json -o DIR/log\n"
      "  mapnav replay --mission maps/missions/campus_dialogue.json --log DIR/log --report DIR\n"
      "Writes DIR/log/ (the replay log: frames, odometry, truth; an earlier demo's log there is replaced),\n"
      "DIR/trace.jsonl (every blackboard token; `mapnav trace show` prints the dialogue), DIR/report.html (one\n"
      "self-contained page: map, route and trajectories, errors over time, frames with predicted and detected\n"
      "lines, the dialogue; open it in any browser) and DIR/trajectories.geojson (for QGIS). Prints the summary\n"
      "and the report's path. Exit codes: 0 the goal was reached (or --max-frames stopped it first), 1 the\n"
      "mission failed or the input is invalid, 2 usage or I/O error.");
  demo->progress = stderr_is_tty;
  dm->callback(commands.choose([demo](std::ostream& out, std::ostream& err) { return runDemo(*demo, out, err); }));
}

void addTraceShow(CLI::App& app, Commands& commands) {
  CLI::App* trace = app.add_subcommand("trace", "Read mission traces (docs/trace-format.md)");
  trace->require_subcommand(1);
  auto* show = commands.hold<TraceShowConfig>();
  CLI::App* ts = trace->add_subcommand("show", "Print a trace as the paper's dialogue (Map, Vision, Navigator, Motion Control)");
  ts->add_option("file", show->file, "Trace (JSONL) written by replay or run --trace")->required();
  ts->footer("Exit codes: 0 printed, 1 a bad line (FILE:LINE:1: error: check: message), 2 the file cannot be read.");
  ts->callback(commands.choose([show](std::ostream& out, std::ostream& err) { return runTraceShow(*show, out, err); }));
}

}  // namespace

void registerMissionCommands(CLI::App& app, Commands& commands) {
  const bool stderr_is_tty = ::isatty(STDERR_FILENO) == 1;
  addReplay(app, commands, stderr_is_tty);
  addRun(app, commands, stderr_is_tty);
  addDemo(app, commands, stderr_is_tty);
  addTraceShow(app, commands);
}

}  // namespace mapnav::cli
