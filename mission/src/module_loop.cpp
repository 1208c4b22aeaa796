// The module loop: the four modules once a frame, the trace, and the evaluation against the truth.
#include "module_loop.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>

#include "mapnav/geometry/camera_io.h"
#include "mapnav/mission/mission_route.h"
#include "mapnav/mission/pipeline_choice.h"
#include "mapnav/navigator/path.h"
#include "mapnav/navigator/progress.h"
#include "mapnav/navigator/road_position.h"

namespace mapnav::detail {

namespace {

// The pipeline: the caller's, else the mission's, else the one the surfaces of the route's roads
// call for (pipeline_choice.h; an InvalidInput saying to name one when they do not decide).
std::string pipelineName(const MissionFile& mission, const RunOptions& options, const Map& map, const Route& route) {
  if (!options.pipeline.empty()) return options.pipeline;
  if (!mission.vision_pipeline.empty()) return mission.vision_pipeline;
  return pipelineForRoads(map, route.roads, "mission \"" + mission.name + "\"");
}

// The pipeline's options: the caller's, else the mission's when the pipeline is the mission's (they
// are that pipeline's options), else none.
std::string pipelineOptions(const MissionFile& mission, const RunOptions& options, const std::string& pipeline) {
  if (options.pipeline_options_json) return *options.pipeline_options_json;
  return pipeline == mission.vision_pipeline ? mission.vision_options_json : "{}";
}

std::unique_ptr<VisionPipeline> missionPipeline(const MissionFile& mission, const RunOptions& options, const Map& map,
                                                const Route& route) {
  const std::string name = pipelineName(mission, options, map, route);
  return createPipeline(name, pipelineOptions(mission, options, name));
}

// Where the mission starts: the route's first point, facing along it (a road position says where,
// the route which way: "R1@I1+3" with a route back through I1 faces I1, as simulate() drives it).
/// Where the mission starts: its start road position, the lateral offset included (a car's log
/// starts in its lane, not on the road's centre line), heading the way the route leaves it.
Pose2 missionStart(const Map& map, const MissionFile& mission, const Route& route) {
  return Pose2(toPose(map, mission.start).translation(), route.line.headingAt(0));
}

BlackboardOptions boardOptions(const MissionFile& mission, const RunOptions& options) {
  const double period = 1.0 / mission.frame_rate_hz;
  BlackboardOptions b;
  b.prediction_validity_s = b.detection_validity_s = b.position_validity_s = options.token_validity_frames * period;
  b.command_validity_s = options.command_validity_frames * period;
  return b;
}

// The run's Map module options, with the mission's GNSS fixes on when it says so.
MapModuleOptions mapOptions(const MissionFile& mission, const RunOptions& options) {
  MapModuleOptions m = options.map;
  m.use_gnss = m.use_gnss || mission.use_gnss;
  return m;
}

NavigatorOptions navigatorOptions(const MissionFile& mission, const RunOptions& options) {
  NavigatorOptions n = options.navigator;
  n.steering.speed_mps = mission.speed_mps;
  return n;
}

}  // namespace

std::string absolutePath(const std::filesystem::path& p) {
  std::error_code ec;
  const auto c = std::filesystem::weakly_canonical(p, ec);
  return ec ? p.string() : c.string();
}

TruthPoses framesTruth(const std::vector<FrameRecord>& frames) {
  TruthPoses truth;
  for (const FrameRecord& f : frames) {
    if (truth.size() <= f.index) truth.resize(f.index + 1);
    truth[f.index] = f.truth;
  }
  return truth;
}

ModuleLoop::ModuleLoop(const MissionFile& mission, const Map& map, const Map& world, const Camera& camera,
                       const RunOptions& options, bool execute, const VehicleLimits& limits, MissionRun& run)
    : mission_(mission),
      map_(map),
      world_(world),
      camera_(camera),
      options_(options),
      run_(run),
      board_(boardOptions(mission, options)),
      navigator_(map, mission.start, missionStops(mission), navigatorOptions(mission, options), limits),
      map_module_(map, camera, missionStart(map, mission, navigator_.route()), mapOptions(mission, options)),
      vision_(missionPipeline(mission, options, map, navigator_.route()), mission.halt),
      motion_(execute, limits, options.navigator.steering.lookahead_m),
      odometry_only_(missionStart(map, mission, navigator_.route()), Mat3::Identity(), options.map.filter),
      truth_tracker_(densePath(navigator_.route().line, 0.25),
                     std::max(PathTracker::kDefaultWindowM, 4.0 * mission.speed_mps / mission.frame_rate_hz)) {
  run_.pipeline = vision_.pipelineName();
  run_.vehicle_width_m = options.vehicle_width_m;
  run_.route = navigator_.route();
  run_.start = missionStart(map, mission, navigator_.route());
  // The goal's lateral offset, like the start's, is where the vehicle should be: a car's lane.
  run_.goal = Pose2(toPose(map, mission.goal).translation(), run_.route.line.headingAt(run_.route.line.length()));
  run_.image_width = camera.width();
  run_.image_height = camera.height();
  board_.onPost([this](const Posting& p) { postings_.push_back(p); });
  board_.onDrop([this](const Drop& d) { drops_.push_back(Pending{postings_.size(), d}); });
  vision_.reset();
  replans_seen_ = 0;
}

void ModuleLoop::header(const std::string& log_dir) {
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

void ModuleLoop::observeTruth(const Vec2& position) {
  const PathOffset o = pathOffset(world_, position, options_.vehicle_width_m);
  if (!between_ || o.offset_m - o.allowed_m > between_->offset_m - between_->allowed_m) between_ = o;
}

VehicleCommand ModuleLoop::command(double t, const Pose2& truth) {
  observeTruth(truth.translation());
  return motion_.control(board_, t, options_.control_dt_s);
}

bool ModuleLoop::frame(const SourceFrame& frame) {
  const std::size_t index = frame.index;
  const double t = frame.t;
  flush();  // anything dropped between frames (Motion Control's reads) belongs before this frame
  // The operator hands control back once the halt has lasted its frames.
  if (board_.halt(Module::User) != nullptr && mission_.halt.resume_after_frames &&
      index - last_failure_ - 1 >= *mission_.halt.resume_after_frames) {
    board_.post(Module::User, Resume{t, index - halt_start_});
    vision_.reset();  // a new scene: what the pipeline learnt may no longer hold
  }
  if (options_.displace && options_.displace->frame == index)
    map_module_.displaceEstimate(options_.displace->forward_m, options_.displace->left_m);
  const bool halted_before = board_.halt(Module::User) != nullptr;
  odometry_only_.predict(frame.odometry);

  const Image& rgb = frame.rgb;
  const auto start = std::chrono::steady_clock::now();
  map_module_.predict(board_, t, frame.odometry);
  const auto vision_start = std::chrono::steady_clock::now();
  // The road region is outlined on every frame: the Map compares it with its prediction (recovery).
  const DetectedObject& detected =
      vision_.see(board_, VisionFrame{rgb.width, rgb.height, rgb.data.data(), &camera_, t, true});
  const auto vision_stop = std::chrono::steady_clock::now();
  if (frame.gnss) map_module_.observeGnss(*frame.gnss, frame.gnss_sigma_m);
  const CurrentPosition& position = map_module_.localize(board_, t);
  const MotionCommand& command = navigator_.plan(board_, t);
  const MotionCommand* taken = motion_.receive(board_, t);
  const auto stop = std::chrono::steady_clock::now();

  if (tracing()) {
    TraceFrame f;
    f.index = index;
    f.t = t;
    f.image = frame.image;
    f.odometry = frame.odometry;
    f.truth = frame.truth;
    f.truth_on_map = frame.truth_on_map;
    f.odometry_only = odometry_only_.pose();
    trace_.frame(f);
  }
  flush();
  if (navigator_.replans() != replans_seen_) {
    replans_seen_ = navigator_.replans();
    if (tracing()) trace_.route(t, navigator_.route(), "replanned");
  }
  if (tracing()) trace_.executing(t, taken, motion_.executing(), motion_.turningInPlace());

  FrameRecord r;
  r.index = index;
  r.t = t;
  r.truth = frame.truth;
  r.estimate = position.pose;
  r.covariance = position.covariance + position.map_covariance;  // in the world: the map's error on top
  r.status = position.status;
  r.position_uncertain = position.integrity == "uncertain";
  r.departed = position.integrity == "departed";
  r.observed_lateral = position.observed_lateral;
  r.observed_along = position.observed_along;
  r.observed_heading = position.observed_heading;
  r.lines_used = position.lines_used;
  r.landmarks_used = position.landmarks_used;
  r.step_used = position.step_used;
  r.along_cue = position.along_cue;
  r.odometry_only = odometry_only_.pose();
  r.gnss = frame.gnss;
  r.gnss_sigma_m = frame.gnss_sigma_m;
  r.vision_ok = detected.status == DetectedObject::Status::Ok;
  r.vision_reason = r.vision_ok ? "" : detected.reason;
  roads_.push_back(roadFound(detected));
  r.lines_detected = detected.lines.size();
  r.lines_labelled = static_cast<std::size_t>(std::count_if(
      detected.lines.begin(), detected.lines.end(), [](const DetectedLine& l) { return l.label.has_value(); }));
  r.halted = board_.halt(Module::User) != nullptr;
  r.command = command.kind;
  r.setpoint = command.setpoint;
  r.to_go_m = navigator_.status().to_go_m;
  r.arrived = navigator_.finished();
  r.latency_ms = std::chrono::duration<double, std::milli>(stop - start).count();
  r.vision_ms = std::chrono::duration<double, std::milli>(vision_stop - vision_start).count();
  if (frame.truth) evaluate(*frame.truth, r);
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

void ModuleLoop::evaluate(const Pose2& truth, FrameRecord& r) {
  const PathTracker::Closest c = truth_tracker_.update(truth.translation());
  r.route_s = c.s;
  double road = truth.heading();
  if (c.distance <= 2.0) {
    road = truth_tracker_.path()[c.segment].heading;
  } else if (const auto p = projectToRoad(world_, truth)) {
    road = truth.heading() - p->heading_error;
  }
  r.error = poseError(r.estimate, truth, road);
  r.road_heading_rad = road;
  r.odometry_error = poseError(r.odometry_only, truth, road);
  observeTruth(truth.translation());
  r.offset_from_centre_m = between_->offset_m;
  r.allowed_offset_m = between_->allowed_m;
}

void ModuleLoop::fault(const LogFault& f) {
  flush();
  if (tracing()) trace_.fault(run_.frames.empty() ? 0.0 : run_.frames.back().t, f);
  ++run_.metrics.log_faults[f.kind];
  run_.faults.push_back(f);
}

void ModuleLoop::finish(const TruthPoses& truth) {
  flush();
  run_.metrics.replans = navigator_.replans();
  run_.metrics.relocalisations = map_module_.relocalisations();
  run_.odometry_scale = map_module_.odometryScale();
  accumulateMetrics(run_.frames, run_.route, run_.metrics);
  if (!run_.frames.empty())
    run_.metrics.estimate_goal_distance_m = (run_.frames.back().estimate.translation() - run_.goal.translation()).norm();
  run_.path_options = options_.path_agreement;
  if (!run_.metrics.has_truth) return;
  run_.path_agreement.clear();
  for (std::size_t k = 0; k < run_.frames.size(); ++k)
    run_.path_agreement.push_back(pathAgreement(truth, run_.frames[k].index, roads_[k], camera_, options_.path_agreement));
  run_.metrics.path_agreement = summarizePathAgreement(run_.path_agreement, options_.path_agreement);
}

void ModuleLoop::writeTrace() {
  if (!tracing()) return;
  trace_.summary(run_);
  trace_.save(options_.trace);
}

void ModuleLoop::flush() {
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

}  // namespace mapnav::detail
