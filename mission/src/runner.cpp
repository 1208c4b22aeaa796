#include "mapnav/mission/runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "mapnav/core/error.h"
#include "mapnav/core/interrupt.h"
#include "mapnav/core/json.h"
#include "mapnav/core/option_table.h"
#include "mapnav/map/camera_io.h"
#include "mapnav/map/map_io.h"
#include "mapnav/mission/trace.h"
#include "mapnav/navigator/path.h"
#include "mapnav/navigator/progress.h"
#include "mapnav/navigator/road_position.h"
#include "mapnav/navigator/steering.h"
#include "mapnav/sim/odometry.h"
#include "mapnav/sim/replay_log.h"
#include "mapnav/sim/world.h"
#include "mapnav/sim/world_io.h"

#include "drive.h"

namespace mapnav {

namespace {

const OptionTable<RunOptions>& runOptionTable() {
  using O = RunOptions;
  static const OptionTable<O> table =
      OptionTable<O>("RunOptions")
          .field("control_dt_s", &O::control_dt_s, aboveUpTo(0, 0.5),
                 "closed loop: the control period of Motion Control and the vehicle, s")
          .field("token_validity_frames", &O::token_validity_frames, above(0),
                 "a prediction, detection or position is used within this many frame periods")
          .field("command_validity_frames", &O::command_validity_frames, above(0),
                 "a steering plan is used within this many frame periods")
          .field("max_odometry_speed_mps", &O::max_odometry_speed_mps, above(0),
                 "replay: odometry faster than this is a spike, m/s")
          .field("max_odometry_turn_rate_deg_s", &O::max_odometry_turn_rate_deg_s, above(0),
                 "replay: odometry turning faster than this is a spike, deg/s")
          .field("vehicle_width_m", &O::vehicle_width_m, atLeast(0),
                 "the vehicle's width for \"stays on the path\", m");
  return table;
}

}  // namespace

void RunOptions::validate() const {
  runOptionTable().validate(*this);
  map.validate();
  navigator.validate();
}

namespace {

std::string pipelineName(const MissionFile& mission, const RunOptions& options) {
  if (!options.pipeline.empty()) return options.pipeline;
  if (!mission.vision_pipeline.empty()) return mission.vision_pipeline;
  return kDefaultPipelineName;
}

// The pipeline's options: the caller's, else the mission's when the pipeline is the mission's (they
// are that pipeline's options), else none.
std::string pipelineOptions(const MissionFile& mission, const RunOptions& options) {
  if (options.pipeline_options_json) return *options.pipeline_options_json;
  const std::string missions = mission.vision_pipeline.empty() ? kDefaultPipelineName : mission.vision_pipeline;
  return pipelineName(mission, options) == missions ? mission.vision_options_json : "{}";
}

std::string absolutePath(const std::filesystem::path& p) {
  std::error_code ec;
  const auto c = std::filesystem::weakly_canonical(p, ec);
  return ec ? p.string() : c.string();
}

// Where the mission starts: the route's first point, facing along it (a road position says where,
// the route which way: "R1@I1+3" with a route back through I1 faces I1, as simulate() drives it).
Pose2 routeStart(const Route& route) { return Pose2(route.line.front(), route.line.headingAt(0)); }

// The module loop, the same in replay and in closed loop: once a frame, in the paper's order,
// Map (prediction) → Vision → Map (matching) → Navigator → Motion Control; the operator's resume
// before them; the trace, the evaluation against the truth and the frame record after them.
class ModuleLoop {
 public:
  ModuleLoop(const MissionFile& mission, const Map& map, const Camera& camera, const RunOptions& options, bool execute,
             const VehicleLimits& limits, MissionRun& run)
      : mission_(mission),
        map_(map),
        camera_(camera),
        options_(options),
        run_(run),
        board_(boardOptions(mission, options)),
        navigator_(map, mission.start, detail::missionStops(mission), navigatorOptions(mission, options), limits),
        map_module_(map, camera, routeStart(navigator_.route()), options.map),
        vision_(createPipeline(pipelineName(mission, options), pipelineOptions(mission, options)),
                mission.halt),
        motion_(execute, limits, options.navigator.steering.lookahead_m),
        odometry_only_(routeStart(navigator_.route()), Mat3::Identity(), options.map.filter),
        truth_tracker_(densePath(navigator_.route().line, 0.25),
                       std::max(PathTracker::kDefaultWindowM, 4.0 * mission.speed_mps / mission.frame_rate_hz)) {
    run_.pipeline = vision_.pipelineName();
    run_.vehicle_width_m = options.vehicle_width_m;
    run_.route = navigator_.route();
    run_.start = routeStart(run_.route);
    run_.goal = Pose2(run_.route.line.back(), run_.route.line.headingAt(run_.route.line.length()));
    run_.image_width = camera.width();
    run_.image_height = camera.height();
    board_.onPost([this](const Posting& p) { postings_.push_back(p); });
    board_.onDrop([this](const Drop& d) { drops_.push_back(Pending{postings_.size(), d}); });
    vision_.reset();
    replans_seen_ = 0;
  }

  void header(const std::string& log_dir) {
    if (!tracing()) return;
    TraceHeader h;
    h.mode = run_.mode;
    h.mission = mission_.name;
    h.map = absolutePath(mission_.map);
    h.camera_json = cameraToJson(camera_);
    h.log = log_dir;
    h.pipeline = run_.pipeline;
    h.start = mission_.start;
    h.goal = mission_.goal;
    h.via = mission_.via;
    h.start_pose = run_.start;
    h.goal_pose = run_.goal;
    h.speed_mps = mission_.speed_mps;
    h.frame_rate_hz = mission_.frame_rate_hz;
    h.resume_after_frames = mission_.halt.resume_after_frames;
    h.image_width = camera_.width();
    h.image_height = camera_.height();
    trace_.header(h);
    trace_.route(0, navigator_.route(), "planned");
  }

  /// The true position between frames (closed loop: every control step), for "stays on the path".
  void observeTruth(const Vec2& position) {
    const PathOffset o = pathOffset(map_, position, options_.vehicle_width_m);
    if (!between_ || o.offset_m - o.allowed_m > between_->offset_m - between_->allowed_m) between_ = o;
  }

  /// One frame; false when the mission ends here (a halt with no resume).
  bool frame(std::size_t index, double t, const Image& rgb, const VehicleMotion& odometry,
             const std::optional<Pose2>& truth, const std::string& image_path) {
    flush();  // anything dropped between frames (Motion Control's reads) belongs before this frame
    // The operator hands control back once the halt has lasted its frames.
    if (board_.halt(Module::User) != nullptr && mission_.halt.resume_after_frames &&
        index - last_failure_ - 1 >= *mission_.halt.resume_after_frames) {
      board_.post(Module::User, Resume{t, index - halt_start_});
      vision_.reset();  // a new scene: what the pipeline learnt may no longer hold
    }
    const bool halted_before = board_.halt(Module::User) != nullptr;
    odometry_only_.predict(odometry);

    const auto start = std::chrono::steady_clock::now();
    map_module_.predict(board_, t, odometry);
    const auto vision_start = std::chrono::steady_clock::now();
    const DetectedObject& detected = vision_.see(board_, VisionFrame{rgb.width, rgb.height, rgb.data.data(), &camera_, t, tracing()});
    const auto vision_stop = std::chrono::steady_clock::now();
    const CurrentPosition& position = map_module_.localize(board_, t);
    const MotionCommand& command = navigator_.plan(board_, t);
    const MotionCommand* taken = motion_.receive(board_, t);
    const auto stop = std::chrono::steady_clock::now();

    if (tracing()) {
      TraceFrame f;
      f.index = index;
      f.t = t;
      f.image = image_path;
      f.odometry = odometry;
      f.truth = truth;
      f.odometry_only = odometry_only_.pose();
      trace_.frame(f);
    }
    flush();
    if (navigator_.replans() != replans_seen_) {
      replans_seen_ = navigator_.replans();
      if (tracing()) trace_.route(t, navigator_.route(), "replanned");
    }
    if (tracing()) trace_.executing(t, taken, motion_.executing());

    FrameRecord r;
    r.index = index;
    r.t = t;
    r.truth = truth;
    r.estimate = position.pose;
    r.covariance = position.covariance;
    r.status = position.status;
    r.observed_lateral = position.observed_lateral;
    r.observed_along = position.observed_along;
    r.observed_heading = position.observed_heading;
    r.lines_used = position.lines_used;
    r.odometry_only = odometry_only_.pose();
    r.vision_ok = detected.status == DetectedObject::Status::Ok;
    r.vision_reason = r.vision_ok ? "" : detected.reason;
    r.lines_detected = detected.lines.size();
    r.lines_labelled = static_cast<std::size_t>(std::count_if(
        detected.lines.begin(), detected.lines.end(), [](const DetectedLine& l) { return l.label.has_value(); }));
    r.halted = board_.halt(Module::User) != nullptr;
    r.command = command.kind;
    r.setpoint = command.setpoint;
    r.to_go_m = navigator_.status().to_go_m;
    r.latency_ms = std::chrono::duration<double, std::milli>(stop - start).count();
    r.vision_ms = std::chrono::duration<double, std::milli>(vision_stop - vision_start).count();
    if (truth) {
      const PathTracker::Closest c = truth_tracker_.update(truth->translation());
      r.route_s = c.s;
      double road = truth->heading();
      if (c.distance <= 2.0) {
        road = truth_tracker_.path()[c.segment].heading;
      } else if (const auto p = projectToRoad(map_, *truth)) {
        road = truth->heading() - p->heading_error;
      }
      r.error = poseError(r.estimate, *truth, road);
      r.odometry_error = poseError(r.odometry_only, *truth, road);
      observeTruth(truth->translation());
      r.offset_from_centre_m = between_->offset_m;
      r.allowed_offset_m = between_->allowed_m;
    }
    between_.reset();
    run_.frames.push_back(r);

    bool go_on = true;
    if (!r.vision_ok) {
      if (!halted_before) {  // a new halt (failures while halted extend it)
        ++run_.metrics.halts;
        halt_start_ = index;
      }
      last_failure_ = index;
      if (!mission_.halt.resume_after_frames) {
        run_.ended_by_halt = true;
        run_.outcome = "halted at frame " + std::to_string(index) + " (" + detected.reason +
                       "); control passed to the operator and the mission ends there";
        go_on = false;
      }
    }
    if (options_.on_frame) options_.on_frame(FrameView{index, t, &rgb, &map_module_.prediction().view, &detected});
    return go_on;
  }

  /// A fault of the replayed log: recorded, counted and traced (before the next frame's records).
  void fault(const LogFault& f) {
    flush();
    if (tracing()) trace_.fault(run_.frames.empty() ? 0.0 : run_.frames.back().t, f);
    ++run_.metrics.log_faults[f.kind];
    run_.faults.push_back(f);
  }

  void finish() {
    flush();
    run_.metrics.replans = navigator_.replans();
    run_.odometry_scale = map_module_.odometryScale();
    accumulateMetrics(run_.frames, run_.route, run_.metrics);
  }

  void writeTrace() {
    if (!tracing()) return;
    trace_.summary(run_);
    trace_.save(options_.trace);
  }

  MotionControlModule& motion() { return motion_; }
  Blackboard& board() { return board_; }
  const NavigatorModule& navigator() const { return navigator_; }
  const MapModule& mapModule() const { return map_module_; }

 private:
  struct Pending {
    std::size_t before;  // the number of postings queued when it was dropped
    Drop drop;
  };

  static BlackboardOptions boardOptions(const MissionFile& mission, const RunOptions& options) {
    const double period = 1.0 / mission.frame_rate_hz;
    BlackboardOptions b;
    b.prediction_validity_s = b.detection_validity_s = b.position_validity_s = options.token_validity_frames * period;
    b.command_validity_s = options.command_validity_frames * period;
    return b;
  }

  static NavigatorOptions navigatorOptions(const MissionFile& mission, const RunOptions& options) {
    NavigatorOptions n = options.navigator;
    n.steering.speed_mps = mission.speed_mps;
    return n;
  }

  bool tracing() const { return !options_.trace.empty(); }

  // The trace lines of what was posted and dropped, in the order it happened.
  void flush() {
    std::size_t d = 0;
    for (std::size_t i = 0; i <= postings_.size(); ++i) {
      while (d < drops_.size() && drops_[d].before == i) {
        if (tracing()) trace_.drop(drops_[d].drop);
        ++d;
      }
      if (i < postings_.size() && tracing()) trace_.posting(postings_[i]);
    }
    postings_.clear();
    drops_.clear();
  }

  const MissionFile& mission_;
  const Map& map_;
  const Camera& camera_;
  const RunOptions& options_;
  MissionRun& run_;
  Blackboard board_;
  NavigatorModule navigator_;
  MapModule map_module_;
  VisionModule vision_;
  MotionControlModule motion_;
  PoseFilter odometry_only_;
  PathTracker truth_tracker_;
  TraceWriter trace_;
  std::vector<Posting> postings_;
  std::vector<Pending> drops_;
  std::size_t replans_seen_ = 0;
  std::size_t last_failure_ = 0, halt_start_ = 0;
  std::optional<PathOffset> between_;  // the worst offset since the last frame (observeTruth)
};

// The fault a line the reader skipped is, by its check (docs/replay-log-format.md).
LogFaultKind faultKind(const std::string& check) {
  if (check == "log.missing_image") return LogFaultKind::MissingImage;
  if (check == "log.corrupt_image") return LogFaultKind::CorruptImage;
  if (check == "log.image_size") return LogFaultKind::ImageSize;
  if (check == "log.time_order") return LogFaultKind::TimeOrder;
  if (check == "log.truncated") return LogFaultKind::Truncated;
  return LogFaultKind::BadLine;
}

// Strict replay: a fault the runner found, as the error the reader gives for a bad line.
[[noreturn]] void throwLogFault(const std::filesystem::path& frames_file, const LogFault& f, const char* check,
                                const char* pointer) {
  Issue issue;
  issue.severity = Severity::Error;
  issue.check = check;
  issue.where = pointer;
  issue.message = std::string(pointer) + ": " + f.message;
  issue.line = f.line;
  issue.column = 1;
  throw ValidationError(frames_file.string(), {issue});
}

// The motion of two consecutive intervals as one.
void carry(Odometry& into, const Odometry& more) {
  into.distance_m += more.distance_m;
  into.dheading_rad += more.dheading_rad;
}

void progress(const RunOptions& options, std::size_t frame, std::size_t total, double t) {
  if (options.progress) options.progress(RunProgress{frame, total, t});
}

}  // namespace

MissionRun runReplay(const MissionFile& mission, const std::filesystem::path& log_dir, const RunOptions& options) {
  options.validate();
  ReadOptions read;
  read.skip_bad_frames = !options.strict;  // strict: the reader throws at the first bad line
  const ReplayLog log = ReplayLog::open(log_dir, read);
  const Map map = loadMap(mission.map);
  const Camera& camera = *log.header().camera;
  MissionRun run;
  run.mode = "replay";
  run.mission = mission.name;
  run.log = log_dir;
  VehicleLimits limits;
  limits.max_speed_mps = std::max(limits.max_speed_mps, mission.speed_mps);
  ModuleLoop loop(mission, map, camera, options, false, limits, run);
  loop.header(absolutePath(log_dir));

  const std::filesystem::path frames_file = log_dir / "frames.jsonl";
  // A fault the runner finds itself: an error in strict mode, else recorded and the run goes on.
  auto fault = [&](const LogFault& f, const char* check, const char* pointer) {
    if (options.strict) throwLogFault(frames_file, f, check, pointer);
    loop.fault(f);
  };
  // The lines the reader skipped, up to (not including) `line`. A frame skipped for its image still
  // moved the vehicle: its odometry goes to the next frame. A line out of time order is dropped whole.
  const std::vector<SkippedLine>& skipped = log.skippedLines();
  std::size_t next_skipped = 0;
  Odometry carried;
  auto faultsBefore = [&](int line) {
    for (; next_skipped < skipped.size() && skipped[next_skipped].line < line; ++next_skipped) {
      const SkippedLine& s = skipped[next_skipped];
      LogFault f{faultKind(s.check), s.line, s.t, "", "skipped", s.message};
      if (f.kind == LogFaultKind::MissingImage && s.odometry) {
        carry(carried, *s.odometry);
        f.action = "skipped; its odometry goes to the next frame";
      }
      loop.fault(f);
    }
  };

  const std::vector<LogFrame>& frames = log.frames();
  const std::size_t total = options.max_frames > 0 ? std::min(options.max_frames, frames.size()) : frames.size();
  std::optional<double> last_t;       // the previous frame the modules saw
  std::optional<Odometry> last_rate;  // its odometry per second, to replace a spike
  bool ended = true;                  // the log was read to its end
  for (std::size_t i = 0; i < total; ++i) {
    throwIfInterrupted();
    const LogFrame& f = frames[i];
    const int line = log.lineOf(i);
    faultsBefore(line);
    // The image: a frame whose PNG does not decode, or is not the camera's size, is skipped.
    Image rgb;
    try {
      rgb = toRgb(log.image(i));
    } catch (const Error& e) {
      carry(carried, f.odometry);
      fault(LogFault{LogFaultKind::CorruptImage, line, f.t, f.image, "skipped; its odometry goes to the next frame",
                     "image \"" + f.image + "\" is not a readable PNG: " + e.what()},
            "log.corrupt_image", "/image");
      continue;
    }
    if (rgb.width != camera.width() || rgb.height != camera.height()) {
      carry(carried, f.odometry);
      fault(LogFault{LogFaultKind::ImageSize, line, f.t, f.image, "skipped; its odometry goes to the next frame",
                     "image \"" + f.image + "\" is " + std::to_string(rgb.width) + "x" + std::to_string(rgb.height) +
                         "; the log's camera takes " + std::to_string(camera.width()) + "x" +
                         std::to_string(camera.height())},
            "log.image_size", "/image");
      continue;
    }
    // The odometry since the previous frame the modules saw (with that of the frames skipped since):
    // faster than a vehicle goes, it is a spike and the previous rate stands in for it.
    Odometry odo = carried;
    carry(odo, f.odometry);
    carried = Odometry{};
    const double dt = last_t ? f.t - *last_t : 1.0 / log.header().frame_rate_hz;
    if (std::abs(odo.distance_m) > options.max_odometry_speed_mps * dt ||
        std::abs(odo.dheading_rad) > degToRad(options.max_odometry_turn_rate_deg_s) * dt) {
      char text[300];
      std::snprintf(text, sizeof text,
                    "odometry %.3f m, %.1f deg in %.3f s is faster than %.2f m/s or %.0f deg/s "
                    "(RunOptions::max_odometry_speed_mps, max_odometry_turn_rate_deg_s)",
                    odo.distance_m, radToDeg(odo.dheading_rad), dt, options.max_odometry_speed_mps,
                    options.max_odometry_turn_rate_deg_s);
      fault(LogFault{LogFaultKind::OdometrySpike, line, f.t, f.image,
                     last_rate ? "odometry replaced by the previous frame's rate" : "odometry replaced by no motion",
                     text},
            "log.odometry_spike", "/odometry");
      odo = last_rate ? Odometry{last_rate->distance_m * dt, last_rate->dheading_rad * dt} : Odometry{};
    } else {
      last_rate = Odometry{odo.distance_m / dt, odo.dheading_rad / dt};
    }
    last_t = f.t;
    run.distance_m += odo.distance_m;
    const VehicleMotion odometry{odo.distance_m, odo.dheading_rad};
    const bool go_on = loop.frame(i, f.t, rgb, odometry, f.truth, f.image);
    progress(options, i + 1, total, f.t);
    if (!go_on) {
      ended = false;
      break;
    }
  }
  if (ended && total == frames.size()) faultsBefore(std::numeric_limits<int>::max());  // after the last frame
  run.stopped_early = !run.ended_by_halt && total < frames.size();
  if (!run.frames.empty()) run.duration_s = run.frames.back().t - run.frames.front().t;
  loop.finish();

  MissionMetrics& m = run.metrics;
  if (!run.frames.empty()) {
    const FrameRecord& last = run.frames.back();
    const Pose2& at = last.truth ? *last.truth : last.estimate;
    m.goal_distance_m = (at.translation() - run.goal.translation()).norm();
    m.reached_goal = !run.ended_by_halt && loop.navigator().finished() && m.goal_distance_m <= 0.5;
  }
  if (run.outcome.empty()) {
    char text[200];
    if (m.reached_goal) {
      std::snprintf(text, sizeof text, "goal reached (%.2f m from it)", m.goal_distance_m);
    } else if (run.stopped_early) {
      std::snprintf(text, sizeof text, "stopped after %zu frames (--max-frames), %.1f m before the goal", run.frames.size(),
                    loop.navigator().status().to_go_m);
    } else {
      std::snprintf(text, sizeof text, "the log ended %.2f m from the goal", m.goal_distance_m);
    }
    run.outcome = text;
  }
  loop.writeTrace();
  return run;
}

MissionRun runClosedLoop(const MissionFile& mission, const RunOptions& options) {
  options.validate();
  const Map map = loadMap(mission.map);
  const std::shared_ptr<const Camera> camera = loadCamera(mission.camera);
  const detail::SimulationSettings settings = detail::simulationSettings(mission, options.seed);
  const World world(map, settings.world);
  const RayTable rays(*camera);
  OdometrySensor sensor(settings.odometry);

  MissionRun run;
  run.mode = "closed-loop";
  run.mission = mission.name;
  VehicleLimits limits;
  limits.max_speed_mps = std::max(limits.max_speed_mps, mission.speed_mps);
  ModuleLoop loop(mission, map, *camera, options, true, limits, run);
  loop.header("");
  SkidSteerVehicle vehicle(run.start, limits);

  detail::DriveLoopOptions drive;
  drive.frame_dt_s = 1.0 / mission.frame_rate_hz;
  drive.control_dt_s = options.control_dt_s;
  drive.time_limit_s = 3.0 * run.route.length_m / mission.speed_mps + 60.0;
  drive.max_frames = options.max_frames;
  const std::size_t expected = static_cast<std::size_t>(run.route.length_m / mission.speed_mps * mission.frame_rate_hz) + 2;
  const std::size_t total = options.max_frames > 0 ? std::min(options.max_frames, expected) : expected;
  std::size_t index = 0;
  const detail::DriveLoopResult driven = detail::driveLoop(
      vehicle, drive,
      [&](double t, const Pose2& truth, const detail::TrueMotion& motion) {
        const Frame frame = world.render(rays, truth, t);  // not in the latency
        const Odometry o = sensor.measure(motion.distance_m, motion.dheading_rad, motion.dt_s);
        const bool go_on = loop.frame(index, t, frame.rgb, VehicleMotion{o.distance_m, o.dheading_rad}, truth, "");
        ++index;
        progress(options, index, std::max(total, index), t);
        return go_on;
      },
      [&](double t) {
        loop.observeTruth(vehicle.pose().translation());
        return loop.motion().control(loop.board(), t, options.control_dt_s);
      },
      [&] { return loop.motion().arrived(); });
  run.duration_s = driven.duration_s;
  run.distance_m = driven.distance_m;
  run.stopped_early =
      !run.ended_by_halt && !driven.finished && options.max_frames > 0 && driven.frames >= options.max_frames;
  loop.finish();

  MissionMetrics& m = run.metrics;
  m.goal_distance_m = (vehicle.pose().translation() - run.goal.translation()).norm();
  m.reached_goal = !run.ended_by_halt && driven.finished && m.goal_distance_m <= 0.5;
  if (run.outcome.empty()) {
    char text[200];
    if (m.reached_goal) {
      std::snprintf(text, sizeof text, "goal reached (%.2f m from it)", m.goal_distance_m);
    } else if (driven.finished) {
      std::snprintf(text, sizeof text, "stopped where it believed the goal was, %.2f m from it", m.goal_distance_m);
    } else if (run.stopped_early) {
      std::snprintf(text, sizeof text, "stopped after %zu frames (--max-frames), %.1f m before the goal", driven.frames,
                    loop.navigator().status().to_go_m);
    } else {
      std::snprintf(text, sizeof text, "time limit (%.0f s) reached %.2f m from the goal", drive.time_limit_s,
                    m.goal_distance_m);
    }
    run.outcome = text;
  }
  loop.writeTrace();
  return run;
}

// ---------------------------------------------------------------------------------------------
// Output

namespace {
double round(double x, double scale) { return std::round(x * scale) / scale + 0.0; }

// {"missing_image":N, ..., "total":N}: every kind, also the ones that did not happen.
Json logFaultsJson(const LogFaultCounts& counts) {
  Json j = Json::object();
  for (std::size_t k = 0; k < kLogFaultKinds; ++k) j[toString(static_cast<LogFaultKind>(k))] = counts.by_kind[k];
  j["total"] = counts.total();
  return j;
}
}  // namespace

std::string logFaultsText(const LogFaultCounts& counts) {
  std::string kinds;
  for (std::size_t k = 0; k < kLogFaultKinds; ++k) {
    const auto kind = static_cast<LogFaultKind>(k);
    if (counts[kind] == 0) continue;
    kinds += (kinds.empty() ? "" : ", ") + toString(kind) + " " + std::to_string(counts[kind]);
  }
  return std::to_string(counts.total()) + " (" + kinds + ")";
}

std::string runToJson(const MissionRun& run) {
  const MissionMetrics& m = run.metrics;
  auto err = [&](double v, double scale) { return m.has_truth ? Json(round(v, scale)) : Json(nullptr); };
  Json j{{"frames", m.frames},
         {"reached_goal", m.reached_goal},
         {"lateral_rms_m", err(m.estimate.lateral_rms_m, 1e5)},
         {"along_rms_m", err(m.estimate.along_rms_m, 1e5)},
         {"heading_rms_deg", err(m.estimate.heading_rms_deg, 1e4)},
         {"max_error_m", err(m.estimate.max_error_m, 1e5)},
         {"odometry_only_max_error_m", err(m.odometry_only.max_error_m, 1e5)},
         {"vision_failures", m.vision_failures},
         {"replans", m.replans},
         {"latency_ms_median", round(m.latency_ms_median, 1e3)},
         {"latency_ms_p99", round(m.latency_ms_p99, 1e3)},
         {"along_after_intersection_max_m", err(m.along_after_intersection_max_m, 1e5)},
         {"max_offset_from_centre_m", err(m.max_offset_from_centre_m, 1e5)},
         {"min_path_clearance_m", err(m.min_path_clearance_m, 1e5)},
         {"left_path_frames", m.left_path_frames},
         {"stayed_on_path", m.has_truth ? Json(m.stayedOnPath()) : Json(nullptr)},
         // More of the same, for people and the report.
         {"mode", run.mode},
         {"mission", run.mission},
         {"pipeline", run.pipeline},
         {"outcome", run.outcome},
         {"goal_distance_m", round(m.goal_distance_m, 1e4)},
         {"lateral_max_m", err(m.estimate.lateral_max_m, 1e5)},
         {"along_max_m", err(m.estimate.along_max_m, 1e5)},
         {"heading_max_deg", err(m.estimate.heading_max_deg, 1e4)},
         {"odometry_only_lateral_rms_m", err(m.odometry_only.lateral_rms_m, 1e5)},
         {"odometry_only_along_rms_m", err(m.odometry_only.along_rms_m, 1e5)},
         {"odometry_only_heading_rms_deg", err(m.odometry_only.heading_rms_deg, 1e4)},
         {"intersections_checked", m.intersections_checked},
         {"halts", m.halts},
         {"ended_by_halt", run.ended_by_halt},
         {"latency_ms_max", round(m.latency_ms_max, 1e3)},
         {"vision_ms_median", round(m.vision_ms_median, 1e3)},
         {"odometry_scale", round(run.odometry_scale, 1e6)},
         {"image_size", std::to_string(run.image_width) + "x" + std::to_string(run.image_height)},
         {"duration_s", round(run.duration_s, 1e3)},
         {"distance_m", round(run.distance_m, 1e3)},
         {"log_faults", logFaultsJson(m.log_faults)}};
  return j.dump() + "\n";
}

std::string summaryText(const MissionRun& run) {
  const MissionMetrics& m = run.metrics;
  std::string out;
  char line[400];
  std::snprintf(line, sizeof line, "%s (%s, pipeline %s): %s\n", run.mission.c_str(), run.mode.c_str(),
                run.pipeline.c_str(), run.outcome.c_str());
  out += line;
  std::snprintf(line, sizeof line, "  %zu frames, %.1f s, %.1f m driven, route %.1f m through %zu intersections\n", m.frames,
                run.duration_s, run.distance_m, run.route.length_m, run.route.intersections.size());
  out += line;
  auto errors = [&](const char* what, const ErrorStats& s) {
    std::snprintf(line, sizeof line,
                  "  %-16s lateral RMS %.3f m (max %.3f), along RMS %.3f m (max %.3f), heading RMS %.2f deg (max %.2f), "
                  "max error %.3f m\n",
                  what, s.lateral_rms_m, s.lateral_max_m, s.along_rms_m, s.along_max_m, s.heading_rms_deg,
                  s.heading_max_deg, s.max_error_m);
    out += line;
  };
  if (m.has_truth) {
    errors("estimate:", m.estimate);
    errors("odometry alone:", m.odometry_only);
    std::snprintf(line, sizeof line,
                  "  along-road error within 2 m after each intersection: max %.3f m (%zu of %zu intersections)\n",
                  m.along_after_intersection_max_m, m.intersections_checked, run.route.intersections.size());
    out += line;
    std::snprintf(line, sizeof line,
                  "  on the path: %s (truth at most %.3f m from the centre line, clearance to the edge %.3f m for a "
                  "%.2f m wide vehicle, %zu frames off the path)\n",
                  m.stayedOnPath() ? "yes" : "NO", m.max_offset_from_centre_m, m.min_path_clearance_m,
                  run.vehicle_width_m, m.left_path_frames);
    out += line;
  } else {
    out += "  no ground truth: errors not measured\n";
  }
  std::snprintf(line, sizeof line, "  vision failures %zu, halts %zu, replans %zu\n", m.vision_failures, m.halts, m.replans);
  out += line;
  if (m.log_faults.total() > 0) {
    out += "  log faults skipped or repaired: " + logFaultsText(m.log_faults) + "\n";
  }
  std::snprintf(line, sizeof line,
                "  loop latency (%dx%d): median %.2f ms, p99 %.2f ms, max %.2f ms (Vision alone: median %.2f ms)\n",
                run.image_width, run.image_height, m.latency_ms_median, m.latency_ms_p99, m.latency_ms_max,
                m.vision_ms_median);
  out += line;
  return out;
}

}  // namespace mapnav
