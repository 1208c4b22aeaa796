#include "mission_commands.h"

#include <chrono>
#include <cstdio>
#include <ostream>

#include "cli.h"
#include "command_support.h"
#include "mapnav/core/io.h"
#include "mapnav/mission/runner.h"
#include "mapnav/mission/trace.h"
#include "mapnav/vision/pipelines.h"
#include "pipelines_command.h"

namespace mapnav::cli {

namespace {

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

template <typename Runner>
int runMissionCommand(const MissionRunConfig& config, std::ostream& out, std::ostream& err, Runner&& runner) {
  return guarded(err, [&] {
    registerBuiltinPipelines();
    loadPlugins(config.plugins);
    const MissionFile mission = loadMission(config.mission);
    RunOptions options;
    options.pipeline = config.pipeline;
    options.max_frames = config.max_frames;
    options.trace = config.trace;
    std::optional<ProgressBar> bar;
    if (config.progress) {
      bar.emplace(err);
      options.progress = [&](const RunProgress& p) { bar->update(p); };
    }
    const MissionRun run = runner(mission, options);
    bar.reset();
    // The HTML report (issue 9, item 5) is written here from `run` and the trace when
    // config.report_dir is set.
    if (config.json) {
      out << runToJson(run);
    } else {
      out << summaryText(run);
      if (!config.trace.empty()) out << "wrote " << config.trace << "\n";
    }
    const bool ok = run.metrics.reached_goal || run.stopped_early;
    return static_cast<int>(ok ? kOk : kInvalid);
  });
}

}  // namespace

int runReplayCommand(const ReplayConfig& config, std::ostream& out, std::ostream& err) {
  return runMissionCommand(config, out, err, [&](const MissionFile& mission, const RunOptions& options) {
    return runReplay(mission, config.log, options);
  });
}

int runRunCommand(const RunConfig& config, std::ostream& out, std::ostream& err) {
  return runMissionCommand(config, out, err, [&](const MissionFile& mission, RunOptions options) {
    options.seed = config.seed;
    return runClosedLoop(mission, options);
  });
}

int runTraceShow(const TraceShowConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    out << traceDialogue(readFile(config.file), config.file);
    return static_cast<int>(kOk);
  });
}

}  // namespace mapnav::cli
