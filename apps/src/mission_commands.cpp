#include "mission_commands.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <ostream>
#include <system_error>

#include "cli.h"
#include "command_support.h"
#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/map/map_io.h"
#include "mapnav/mission/report.h"
#include "mapnav/mission/runner.h"
#include "mapnav/mission/simulate.h"
#include "mapnav/mission/trace.h"
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

template <typename Runner>
ReportedRun runReported(const MissionFile& mission, const MissionRunConfig& config, std::ostream& err, Runner&& runner) {
  ReportedRun r;
  RunOptions options;
  options.pipeline = config.pipeline;
  options.max_frames = config.max_frames;
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
    registerBuiltinPipelines();
    loadPlugins(config.plugins);
    const MissionFile mission = loadMission(config.mission);
    return finish(runReported(mission, config, err, runner), config.json, false, out);
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
    registerBuiltinPipelines();
    MissionRunConfig run;
    run.mission = config.mission.empty() ? dataPath("maps/missions/campus_dialogue.json") : config.mission;
    run.report_dir = config.output;
    run.max_frames = config.max_frames;
    run.progress = config.progress;
    const MissionFile mission = loadMission(run.mission);
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
    out << line << "replaying it with the pipeline " << (mission.vision_pipeline.empty() ? kDefaultPipelineName : mission.vision_pipeline.c_str())
        << " ..." << std::endl;
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

}  // namespace mapnav::cli
