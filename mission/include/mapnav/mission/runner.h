#pragma once
// The mission runner (Wallace 1985, 4): "First, the Map module announces a set of predictions for
// the current scene, knowing the vehicle's position. The Vision module then [...] extract[s] the
// predicted road region [...] If road or intersection region detection is successful, the Navigator
// is alerted and generates a steering plan [...] If not successful, the Vision system halts and
// signals the blackboard so that another module (or person) [can] take control. [...] The steering
// plan is received by the low-level motion control module [...]".
//
// One loop over a frame source (mission/frame_source.h), two entry points:
//   runReplay         — open loop over a recorded log (`mapnav simulate`, a KITTI import;
//                       docs/replay-log-format.md): the replay source reads the log and repairs or
//                       skips its faults; localisation and commands computed frame by frame from the
//                       log's images and odometry, compared with the log's truth when it has it;
//                       Motion Control records.
//   runClosedLoopOver — (frame_source.h) Motion Control's commands drive the vehicle of a source
//                       the caller makes; the simulator's is mission_sim's runClosedLoop
//                       (mission_sim/closed_loop.h: the plant renders each frame from the true pose,
//                       odometry from its sensor).
// Both return the metrics and a record per frame, and can write the JSONL trace (docs/trace-format.md).
// Poses are world frame (x, y in m, heading in rad); times are mission time in s. Nothing here links
// the renderer: replaying a real drive needs only the log.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/image/image.h"
#include "mapnav/mission/metrics.h"
#include "mapnav/mission/mission_file.h"
#include "mapnav/mission/modules.h"

namespace mapnav {

/// Where a run is, for a progress bar.
struct RunProgress {
  std::size_t frame = 0;  ///< frames done
  std::size_t total = 0;  ///< frames expected (replay: the log's; closed loop: an estimate), 0 unknown
  double t = 0;           ///< mission time, s
};

/// A camera frame and what the modules made of it, for pictures of the run (the report's thumbnails,
/// as the paper's Figure 2). The pointers are valid during the call only.
struct FrameView {
  std::size_t index = 0;
  double t = 0;
  const Image* rgb = nullptr;                  ///< the frame the pipeline saw (RGB)
  const PredictedObject* predicted = nullptr;  ///< the Map's prediction for it (empty: no road in view)
  const DetectedObject* detected = nullptr;    ///< Vision's answer (lines labelled with predicted segment ids)
};

/// A fault of the replayed log and what the replay did about it (RunOptions::strict = false).
struct LogFault {
  LogFaultKind kind = LogFaultKind::BadLine;
  int line = 0;              ///< 1-based line of frames.jsonl
  std::optional<double> t;   ///< the line's `t`, when it could be read
  std::string image;         ///< the frame's image path, when known
  std::string action;        ///< "skipped", "skipped; its odometry goes to the next frame", ...
  std::string message;       ///< what is wrong, as the strict mode's error says it
};

/// A fault injected into a run (tests of recovery): at the start of frame `frame` the Map's estimate
/// jumps by `forward_m` along its own heading and `left_m` to the left of it, its covariance as it
/// was: the filter does not know (a wheel slipping on a kerb, a wrong start told by the user).
struct EstimateDisplacement {
  std::size_t frame = 0;
  double forward_m = 0;
  double left_m = 0;
};

struct RunOptions {
  /// The vision pipeline by name (registry: createPipeline); "" keeps the mission's `vision.pipeline`,
  /// and a mission without one runs the pipeline the surfaces of its route's roads call for
  /// (pipelineForRoads, mission/pipeline_choice.h; InvalidInput when they do not decide).
  std::string pipeline;
  /// The pipeline's options as a JSON object; nothing keeps the mission's `vision.options`.
  std::optional<std::string> pipeline_options_json;
  /// Stop after this many frames (0: to the end of the log / the goal).
  std::size_t max_frames = 0;
  /// Replay: false skips (or repairs) every fault of the log, counts it (MissionMetrics::log_faults)
  /// and records it (MissionRun::faults, a `Sensors/LogFault` trace line); true stops at the first
  /// with a ValidationError naming frames.jsonl and the line.
  bool strict = false;
  /// Replay: odometry faster than this over the time since the previous frame is a spike, m/s (>= 0);
  /// 0 = twice the mission's speed_mps, at least 5 (a sidewalk robot's log: 5; a car's at 12 m/s: 24).
  double max_odometry_speed_mps = 0.0;
  /// Replay: ... or turning faster than this, deg/s (> 0).
  double max_odometry_turn_rate_deg_s = 360.0;
  /// Closed loop: overrides the world's seed and the odometry's (seed + 1), as `mapnav simulate --seed`.
  std::optional<std::uint64_t> seed;
  /// Closed loop: the control period of Motion Control and the vehicle, s, in (0, 0.5].
  double control_dt_s = 0.05;
  /// Token validities in frame periods (the blackboard's, set from the mission's frame rate): a
  /// prediction, detection or position is used within this many frame periods (> 0) ...
  double token_validity_frames = 1.0;
  /// ... and a steering plan within this many (> 0): Motion Control stops when none newer came.
  double command_validity_frames = 2.5;
  /// Write the JSONL trace here ("": none). Written atomically at the end of the run.
  std::filesystem::path trace;
  /// The vehicle's width, m (>= 0), for "stays on the path": its side must stay on the paved path,
  /// so the true position may be at most (road width − vehicle_width_m) / 2 from the centre line
  /// (MissionMetrics::left_path_frames). 0.6 m: a small sidewalk robot.
  double vehicle_width_m = 0.6;
  /// Fault injection: the estimate displaced once (none: never).
  std::optional<EstimateDisplacement> displace;
  MapModuleOptions map;
  /// Where each frame's future path is sampled and the goals of path agreement (path_agreement.h),
  /// measured when the run has truth: Vision's detection of each frame against the truth poses of
  /// the frames after it (replay: the log's, also beyond max_frames; closed loop: the frames run).
  /// Vision then outlines the road region on every frame with truth (VisionFrame::want_region), as
  /// it does on every frame when a trace is written.
  PathAgreementOptions path_agreement;
  /// The Navigator's options; the steering speed is the mission's speed_mps.
  NavigatorOptions navigator;
  /// Called after every frame (a progress bar). Not in the trace.
  std::function<void(const RunProgress&)> progress;
  /// Called with every camera frame and its prediction and detection (the report's thumbnails),
  /// after the modules ran.
  std::function<void(const FrameView& frame)> on_frame;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

const OptionTable<RunOptions>& runOptionTable();

struct MissionRun {
  std::string mode;           ///< "replay" or "closed-loop"
  std::string mission;        ///< its name
  std::string pipeline;       ///< the vision pipeline used
  std::filesystem::path log;  ///< replay: the log folder
  int image_width = 0, image_height = 0;
  Route route;                ///< as planned at the start
  Pose2 start, goal;          ///< world poses of the mission's start and goal
  std::vector<FrameRecord> frames;
  MissionMetrics metrics;
  double duration_s = 0;      ///< mission time covered
  double distance_m = 0;      ///< driven: closed loop the truth, replay the odometry
  bool ended_by_halt = false; ///< a halt with no resume ended the mission
  bool stopped_early = false; ///< max_frames ended it
  double vehicle_width_m = 0; ///< RunOptions::vehicle_width_m, for "stays on the path"
  double odometry_scale = 1;  ///< the pose filter's odometry scale estimate at the end, 1 + e (MotionNoiseOptions::scale_sigma)
  std::vector<LogFault> faults;  ///< replay: the log's faults met, in file order (counted in metrics.log_faults)
  /// Each frame's path agreement, in the order of `frames`, when the run has truth (else empty);
  /// summed up in metrics.path_agreement.
  std::vector<PathAgreement> path_agreement;
  PathAgreementOptions path_options;  ///< RunOptions::path_agreement, what they were measured with
  std::string outcome;        ///< one line: "goal reached", "halted at frame 12: ...", ...
};

/// Open loop over `log_dir`. The log's camera is used (it took the frames); the mission gives the
/// map, start, goal, stops, speed, vision and halt policy. Throws ValidationError / IoError for the
/// mission, log or map, NotFound for an unknown pipeline, Unreachable for no route.
MissionRun runReplay(const MissionFile& mission, const std::filesystem::path& log_dir, const RunOptions& options = {});

/// `--json`: {"frames","reached_goal","lateral_rms_m","along_rms_m","heading_rms_deg","max_error_m",
/// "odometry_only_max_error_m","vision_failures","replans","latency_ms_median","latency_ms_p99",
/// "along_after_intersection_max_m", "max_offset_from_centre_m", "left_path_frames", ...more,
/// "log_faults":{"missing_image":N,...,"total":N}, "path_agreement":{...}}; errors and
/// path_agreement (pathAgreementJson) are null without truth. One line.
std::string runToJson(const MissionRun& run);

/// "3 (missing_image 1, time_order 2)": the total and the kinds that happened, for people.
std::string logFaultsText(const LogFaultCounts& counts);

/// "filter consistency: true error within 2 sigma ... in 97.1 % of frames along, ...; NEES mean 2.84
/// (expected 3)", one line after `indent`.
std::string consistencyText(const FilterConsistency& consistency, const std::string& indent);

/// The summary a person reads at the end: outcome, errors of the estimate and of odometry alone,
/// path agreement (pathAgreementText), failures, replans, latency.
std::string summaryText(const MissionRun& run);

}  // namespace mapnav
