#include "mapnav/mission/modules.h"

#include <algorithm>
#include <cmath>
#include <exception>

#include "mapnav/core/error.h"
#include "mapnav/core/option_table.h"
#include "mapnav/mission/mission_route.h"
#include "mapnav/navigator/path.h"

namespace mapnav {

// ---------------------------------------------------------------------------------------------
// Map

const OptionTable<MapModuleOptions>& mapModuleOptionTable() {
  using O = MapModuleOptions;
  static const OptionTable<O> table =
      OptionTable<O>("MapModuleOptions")
          .field("initial_sigma_m", &O::initial_sigma_m, above(0), "1-sigma of the start position in x and y, m")
          .field("initial_heading_sigma_deg", &O::initial_heading_sigma_deg, above(0),
                 "1-sigma of the start heading, degrees")
          .field("min_visible_px", &O::min_visible_px, atLeast(0),
                 "a prediction whose paved area covers fewer image pixels is \"no road in view\"")
          .field("use_gnss", &O::use_gnss, "fuse the frames' GNSS fixes with their stated sigma, each gated")
          .nest(&O::supervisor, filterSupervisorOptionTable(),
                {{"after_rejections", "park_reset_after_rejections"},
                 {"sigma_m", "park_reset_sigma_m"},
                 {"heading_sigma_deg", "park_reset_heading_sigma_deg"},
                 {"agreement_m", "park_reset_agreement_m"},
                 {"agreement_deg", "park_reset_agreement_deg"},
                 {"max_rms_m", "park_reset_max_rms_m"}})
          .nest(&O::integrity, integrityOptionTable(),
                {{"window_frames", "integrity_window_frames"},
                 {"probability", "integrity_probability"},
                 {"max_unobserved_m", "integrity_max_unobserved_m"},
                 {"min_observed_fraction", "integrity_min_observed_fraction"},
                 {"departure_probability", "integrity_departure_probability"},
                 {"anchor_every_m", "integrity_anchor_every_m"}});
  return table;
}

void MapModuleOptions::validate() const {
  predict.validate();
  filter.validate();
  localize.validate();
  relocalize.validate();
  mapModuleOptionTable().validate(*this);
}

namespace {

Mat3 initialCovariance(const MapModuleOptions& o) {
  o.validate();
  const double s = o.initial_sigma_m, h = degToRad(o.initial_heading_sigma_deg);
  return Vec3(s * s, s * s, h * h).asDiagonal();
}

// The image area (pixels) of the predicted paved regions: each ring projected with its edges cut
// into 0.25 m steps (so that a curved lens bends them), by the shoelace formula.
double visiblePixels(const PredictedObject& view, const Camera& camera) {
  double total = 0;
  for (const PredictedRegion& region : view.regions) {
    for (const Polygon2& ring : region.vehicle) {
      std::vector<Vec2> pixels;
      for (std::size_t i = 0; i < ring.size(); ++i) {
        const Vec2 a = ring[i], b = ring[(i + 1) % ring.size()];
        const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / 0.25)));
        for (int k = 0; k < steps; ++k) {
          if (const auto p = camera.projectGround(a + (b - a) * (static_cast<double>(k) / steps))) pixels.push_back(*p);
        }
      }
      double area = 0;
      for (std::size_t i = 0; i < pixels.size(); ++i) area += cross2(pixels[i], pixels[(i + 1) % pixels.size()]);
      total += std::abs(area) / 2;
    }
  }
  return total;
}

}  // namespace

MapModule::MapModule(const Map& map, const Camera& camera, const Pose2& start, const MapModuleOptions& options)
    : map_(map),
      camera_(camera),
      options_(options),
      predictor_(map, options.predict),
      filter_(start, initialCovariance(options), options.filter),
      supervisor_(options.supervisor),
      integrity_(filter_, options.integrity),
      per_road_sigma_(std::any_of(map.roads().begin(), map.roads().end(),
                                  [](const Road& r) { return r.position_sigma_m.has_value(); })) {
  position_ = filter_.current(0.0, "start");
}

double MapModule::mapSigmaAt(const Pose2& pose) const {
  const MapData& data = map_.data();
  if (!per_road_sigma_) return data.position_sigma_m;
  // The road under the estimate (the map's figure off every road).
  if (const auto p = projectToRoad(map_, pose, 50.0)) return positionSigma(data, map_.road(p->position.road));
  return data.position_sigma_m;
}

void MapModule::predict(Blackboard& board, double t, const MotionIncrement& odometry) {
  pending_ = odometry;
  pending_dt_s_ = std::max(0.0, t - last_t_);
  filter_.setMapSigma(mapSigmaAt(filter_.pose()));
  PoseFilter predicted = filter_;
  predicted.predict(pending_, pending_dt_s_);
  prediction_ = predictor_.predict(predicted.pose(), camera_);
  if (!prediction_.empty() && visiblePixels(prediction_.view, camera_) <
                                      options_.min_visible_px * std::pow(pixelScale(camera_.width(), camera_.height()), 2)) {
    Prediction nothing;  // "Vision will see no road from here"
    nothing.pose = prediction_.pose;
    nothing.footprint_world = prediction_.footprint_world;
    nothing.view.footprint = prediction_.view.footprint;
    prediction_ = std::move(nothing);
  }
  prediction_.view.timestamp = t;
  prediction_.view.motion = filter_.corrected(pending_, pending_dt_s_);
  // In the vehicle's frame (forward, left).
  prediction_.view.pose_covariance = rotatePoseCovariance(predicted.covariance(), predicted.pose().rotation().transpose());
  prediction_.view.map_sigma_m = filter_.mapSigma();
  board.post(Module::Map, PredictionToken{prediction_.view, predicted.pose()});
}

void MapModule::displaceEstimate(double forward_m, double left_m) {
  const Pose2& p = filter_.pose();
  filter_.moveTo(Pose2(p.translation() + p.rotation() * Vec2(forward_m, left_m), p.heading()));
}

const CurrentPosition& MapModule::localize(Blackboard& board, double t) {
  const DetectedObject* detected = board.detection(Module::Map, t);
  DetectedObject none;
  if (detected == nullptr || detected->timestamp != t) {
    none = DetectedObject::failed("no DetectedObject for this frame");
    none.timestamp = t;
    detected = &none;
  }
  position_ =
      mapnav::localize(filter_, pending_, prediction_, *detected, options_.localize, &map_, &camera_, pending_dt_s_);
  // Park mode: a centre line and no labelled line, or road edges with no crossing line in view. Either
  // way nothing observes the position along the road but its curvature, and on a tight curve an
  // along-road error the filter does not know of turns into a heading error (see the options).
  const bool centerline_only = detected->centerline_vehicle.has_value() &&
                               std::none_of(detected->lines.begin(), detected->lines.end(),
                                            [](const DetectedLine& l) { return l.label.has_value(); });
  const bool no_crossing =
      std::none_of(prediction_.view.relations.begin(), prediction_.view.relations.end(),
                   [](const SegmentRelation& r) { return r.type == SegmentRelation::Type::Crossing; });
  const bool park = centerline_only || no_crossing;
  // The supervisor is shown park mode's frames: another frame ends its run of rejections.
  if (!park) supervisor_.clear();
  if (const SupervisorDecision d = park ? supervisor_.observe(position_) : SupervisorDecision{}; d.widen) {
    // The gate has refused the centre line or the road edges too often, the same way each time:
    // the filter is surer than it should be.
    filter_.resetPoseCovariance(d.covariance);
    position_ = mapnav::localize(filter_, MotionIncrement{}, prediction_, *detected, options_.localize, &map_, &camera_);
    position_.reason += " (after " + std::to_string(d.rejections) + " rejected frames, the covariance widened)";
  }
  if (gnss_ && options_.use_gnss) {
    const bool fused = filter_.updatePosition(gnss_->first, gnss_->second);
    position_.pose = filter_.pose();
    position_.covariance = filter_.covariance();
    position_.map_covariance = filter_.mapCovariance();
    position_.reason += fused ? "; GNSS fix fused" : "; GNSS fix beyond the gate";
  }
  gnss_.reset();
  recover(*detected, t);
  checkIntegrity(t);
  position_.timestamp = t;
  pending_ = MotionIncrement{};
  pending_dt_s_ = 0;
  last_t_ = t;
  board.post(Module::Map, position_);
  return position_;
}

void MapModule::checkIntegrity(double t) {
  integrity_.predict(pending_, pending_dt_s_);
  const IntegrityVerdict v = integrity_.observe(position_, filter_);
  if (v.state != IntegrityVerdict::State::Departed) {
    position_.integrity = toString(v.state);
    if (v.state == IntegrityVerdict::State::Uncertain) position_.reason += "; " + v.reason;
    return;
  }
  // Lines, landmarks or a re-localisation have pulled the estimate where odometry says the vehicle
  // cannot be: back onto the dead reckoning, as uncertain as it is; the vehicle stops for the frame.
  const std::optional<double> agreement = position_.region_agreement;
  filter_.moveTo(v.dead_reckoned);
  filter_.resetPoseCovariance(v.dead_reckoned_covariance);
  candidate_.reset();
  position_ = filter_.current(t, "position lost: " + v.reason + "; the estimate put back on odometry");
  position_.status = PositionStatus::Lost;
  position_.region_agreement = agreement;
  position_.integrity = toString(v.state);
}

void MapModule::recover(const DetectedObject& detected, double t) {
  const RelocalizeOptions& o = options_.relocalize;
  const auto lost = [&](const std::string& why) {
    if (++lost_frames_ > o.max_lost_frames) {  // no winner confirmed in time: Vision's region, not the pose
      candidate_.reset();
      search_suspended_ = true;
      position_.reason += "; the search gave up after " + std::to_string(o.max_lost_frames) + " frames (" + why + ")";
      return;
    }
    position_.status = PositionStatus::Lost;
    position_.reason = "position lost: " + why;
  };
  const bool region = detected.status == DetectedObject::Status::Ok && detected.region_vehicle.size() >= 3 &&
                      !prediction_.empty();
  if (!region) {  // nothing to compare: a search under way waits for the next region
    if (candidate_) lost("waiting for a road region to confirm the winner");
    return;
  }
  const RegionAgreement agreement = regionAgreement(prediction_.view, detected.region_vehicle, o.cell_m);
  position_.region_agreement = agreement.iou;
  // The estimate holds when lines the gate accepted say so, whatever the region's shape (a dead
  // end's, a plaza's), or when the region gives no reason to search: it agrees, or it is not the
  // road's size (Vision's error). A search that gave up waits for that.
  const bool quiet = agreement.iou >= o.search_below || !agreement.roadSized(o.max_area_ratio);
  const bool holds = position_.status == PositionStatus::Corrected || (quiet && !candidate_);
  if (holds) search_suspended_ = false;
  if (o.search_below <= 0 || search_suspended_ || holds) {
    candidate_.reset();
    lost_frames_ = 0;
    return;
  }
  const Pose2 estimate = filter_.pose();
  const RelocalizeResult r = relocalize(predictor_, camera_, estimate, detected.region_vehicle, o);
  if (!r.clear) {  // no pose explains the region clearly: drive on (Vision's region, most likely)
    candidate_.reset();
    lost_frames_ = 0;
    return;
  }
  const Pose2 offset = estimate.inverse() * r.pose;
  const bool confirmed = candidate_ && std::abs(offset.translation().y() - candidate_->translation().y()) <= o.step_m &&
                         std::abs(normalizeAngle(offset.heading() - candidate_->heading())) <= degToRad(o.heading_step_deg);
  if (!confirmed) {  // stop and look again
    candidate_ = offset;
    lost("a winner to confirm on the next frame: " + r.reason);
    return;
  }
  filter_.moveTo(r.pose);
  filter_.resetPoseCovariance(r.covariance);
  candidate_.reset();
  lost_frames_ = 0;
  ++relocalisations_;
  position_ = filter_.current(t, "re-localised: " + r.reason);
  position_.status = PositionStatus::Corrected;
  position_.region_agreement = agreement.iou;
}

// ---------------------------------------------------------------------------------------------
// Vision

VisionModule::VisionModule(std::unique_ptr<VisionPipeline> pipeline, const HaltPolicy& halt)
    : pipeline_(std::move(pipeline)), halt_(halt) {
  if (!pipeline_) throw InvalidInput("VisionModule: no pipeline");
}

const DetectedObject& VisionModule::see(Blackboard& board, const VisionFrame& frame) {
  const double t = frame.timestamp;
  const PredictedObject* prediction = board.prediction(Module::Vision, t);
  if (prediction == nullptr || prediction->timestamp != t) {
    detected_ = DetectedObject::failed("no PredictedObject for this frame");
  } else if (prediction->empty()) {
    detected_ = DetectedObject{};  // nothing to look for is not a failure
    detected_.reason = "nothing predicted in view: nothing to look for";
  } else {
    try {
      detected_ = pipeline_->detect(frame, *prediction);
      // The landmarks, looked for by the Vision module itself unless the pipeline did.
      if (detected_.status == DetectedObject::Status::Ok && detected_.landmarks.empty() && !prediction->landmarks.empty()) {
        if (const LandmarkFinder find = landmarkFinder()) detected_.landmarks = find(frame, *prediction);
      }
    } catch (const std::exception& e) {
      detected_ = DetectedObject::failed(std::string("the pipeline failed: ") + e.what());
    }
  }
  detected_.step = measureStep(frame, prediction);
  previous_rgb_.assign(frame.rgb, frame.rgb + static_cast<std::size_t>(frame.width) * frame.height * 3);
  previous_ = frame;
  previous_.rgb = previous_rgb_.data();
  detected_.timestamp = t;
  board.post(Module::Vision, detected_);
  if (detected_.status != DetectedObject::Status::Ok) {
    board.post(Module::Vision, VisionFailure{t, detected_.reason});
    Halt halt;
    halt.timestamp = t;
    halt.reason = "vision failed: " + detected_.reason;
    halt.resume_after_frames = halt_.resume_after_frames;
    board.post(Module::Vision, halt);
  }
  return detected_;
}

std::optional<MeasuredStep> VisionModule::measureStep(const VisionFrame& frame, const PredictedObject* prediction) const {
  const StepMeasurer measure = stepMeasurer();
  if (!measure || previous_.rgb == nullptr || prediction == nullptr || !prediction->motion) return std::nullopt;
  try {
    return measure(previous_, frame, *prediction->motion);
  } catch (const std::exception& e) {
    MeasuredStep failed;
    failed.reason = std::string("the step measurer failed: ") + e.what();
    return failed;
  }
}

void VisionModule::reset() { pipeline_->reset(); }

std::string VisionModule::pipelineName() const { return pipeline_->name(); }

// ---------------------------------------------------------------------------------------------
// Navigator

const OptionTable<NavigatorOptions>& navigatorOptionTable() {
  using O = NavigatorOptions;
  static const OptionTable<O> table =
      OptionTable<O>("NavigatorOptions")
          .field("plan_behind_m", &O::plan_behind_m, atLeast(0),
                 "the steering plan starts this far behind the estimated position, m")
          .field("plan_ahead_m", &O::plan_ahead_m, above(0), "... and ends this far ahead of it, m");
  return table;
}

void NavigatorOptions::validate() const {
  route.validate();
  progress.validate();
  steering.validate();
  navigatorOptionTable().validate(*this);
}

struct NavigatorModule::Impl {
  const Map& map;
  RoadGraph graph;
  NavigatorOptions options;
  VehicleLimits limits;
  std::vector<RoadPosition> remaining;  // stops not reached yet (the goal last)
  std::vector<double> remaining_s;      // their arc lengths along `route`
  Route route;
  std::optional<RouteProgress> progress;
  std::vector<double> drive_end_s;      // per leg: the arc length at which the leg ends
  std::uint64_t sequence = 0;
  std::string last_road;
  MotionCommand last;

  Impl(const Map& m, const NavigatorOptions& o, const VehicleLimits& l) : map(m), graph(m), options(o), limits(l) {}

  void adopt(Route r) {
    route = std::move(r);
    progress.emplace(route, options.progress);
    drive_end_s.clear();
    double s = 0;
    for (const Leg& leg : route.legs) {
      if (leg.action == LegAction::Drive) s += leg.meters;
      drive_end_s.push_back(s);
    }
  }

  void plan(const RoadPosition& from) {
    adopt(planThrough(graph, from, remaining, "route from " + toString(from), &remaining_s, options.route));
  }

  // Where the vehicle is as a road position, facing the way it heads (a replan's start).
  std::optional<RoadPosition> here(const Pose2& pose) const {
    auto p = projectToRoad(map, pose);
    if (!p) return std::nullopt;
    RoadPosition r = p->position;
    r.lateral = 0;
    if (std::abs(p->heading_error) > kPi / 2) {  // facing the road's `from` end
      const Road& road = map.road(r.road);
      r.node = road.to;
      r.meters = std::max(0.0, road.centerline.length() - r.meters);
    }
    return r;
  }
};

NavigatorModule::NavigatorModule(const Map& map, const RoadPosition& start, std::vector<RoadPosition> stops,
                                 const NavigatorOptions& options, const VehicleLimits& limits)
    : impl_(std::make_unique<Impl>(map, options, limits)) {
  options.validate();
  limits.validate();
  if (stops.empty()) throw InvalidInput("NavigatorModule: no goal");
  impl_->remaining = std::move(stops);
  impl_->plan(start);
  status_.to_go_m = impl_->route.length_m;
}

NavigatorModule::~NavigatorModule() = default;
NavigatorModule::NavigatorModule(NavigatorModule&&) noexcept = default;
NavigatorModule& NavigatorModule::operator=(NavigatorModule&&) noexcept = default;

const Route& NavigatorModule::route() const { return impl_->route; }

const MotionCommand& NavigatorModule::plan(Blackboard& board, double t) {
  Impl& m = *impl_;
  MotionCommand c;
  c.sequence = ++m.sequence;
  c.timestamp = t;
  auto post = [&]() -> const MotionCommand& {
    m.last = c;
    board.post(Module::Navigator, c);
    return m.last;
  };
  auto stop = [&](std::string reason) -> const MotionCommand& {
    c.kind = CommandKind::Stop;
    c.reason = std::move(reason);
    c.speed_mps = 0;
    return post();
  };
  if (const Halt* halt = board.halt(Module::Navigator)) {
    return stop("halted (" + halt->reason + "); control is with the " + halt->control_to);
  }
  const CurrentPosition* position = board.position(Module::Navigator, t);
  if (position == nullptr) return stop("no current position");
  if (position->status == PositionStatus::Lost) return stop(position->reason);
  const Pose2& pose = position->pose;

  status_ = m.progress->update(pose);
  // Via points behind us are done: a replan goes through the rest only.
  while (m.remaining.size() > 1 && status_.along_m >= m.remaining_s.front() - 0.5) {
    m.remaining.erase(m.remaining.begin());
    m.remaining_s.erase(m.remaining_s.begin());
  }
  if (needsReplan(status_, m.route, m.options.route.blocked)) {
    const auto from = m.here(pose);
    if (!from) return stop("off the route and more than 5 m from every road");
    try {
      m.plan(*from);
    } catch (const Unreachable& e) {
      return stop(e.what());
    }
    ++replans_;
    status_ = m.progress->update(pose);
  }

  // The dialogue: "Drive on it 2.5 meters and turn to right 90 degrees".
  const Route& route = m.route;
  const std::size_t leg = std::min(status_.leg, route.legs.size() - 1);
  c.road = route.legs[leg].road;
  c.drive_m = std::max(0.0, m.drive_end_s[leg] - status_.along_m);
  if (leg + 1 < route.legs.size() && route.legs[leg + 1].action == LegAction::Turn) c.next_turn = route.legs[leg + 1];
  c.same_road = c.road == m.last_road;
  m.last_road = c.road;

  // The steering plan: the route's centre line around and ahead of the estimate, within the stretch
  // between turnarounds under way (the line comes back over itself at a turnaround).
  const double length = route.line.length();
  // (A turnaround's plan ends a micrometre before it: never a hair of the way back, whose reversed
  // heading would make the follower think it has passed the end.)
  const double end = status_.stretch_end_m < length ? status_.stretch_end_m - 1e-6 : length;
  const double s1 = std::min(end, status_.along_m + m.options.plan_ahead_m);
  const double s0 = std::max(status_.stretch_begin_m, std::min(status_.along_m - m.options.plan_behind_m, s1 - 0.5));
  const Polyline2 piece = route.line.slice(s0, s1);
  c.path = piece.points();
  c.path_ends_at_goal = s1 >= length - 1e-9;
  c.path_ends_at_turn = !c.path_ends_at_goal && s1 >= end - 1e-9;
  c.speed_mps = m.options.steering.speed_mps;
  if (piece.size() >= 2 && piece.length() > 1e-6) {
    PurePursuit pursuit(densePath(piece, 0.25), m.options.steering, m.limits);
    c.setpoint = pursuit.command(pose);
    c.lookahead_point = pursuit.goal();
  } else {
    return stop("no route left to drive");
  }
  return post();
}

// ---------------------------------------------------------------------------------------------
// Motion Control

MotionControlModule::MotionControlModule(bool execute, const VehicleLimits& limits, double lookahead_m)
    : execute_(execute), limits_(limits), model_(Pose2(), limits) {
  pursuit_options_.lookahead_m = lookahead_m;
  pursuit_options_.validate();
}

const MotionCommand* MotionControlModule::receive(Blackboard& board, double t) {
  const MotionCommand* c = board.command(Module::MotionControl, t);
  if (c == nullptr) {
    has_command_ = false;
    pursuit_.reset();
    return nullptr;
  }
  if (!has_command_ || c->sequence != command_.sequence) {
    command_ = *c;
    has_command_ = true;
    const bool turning = pursuit_ && pursuit_->turningInPlace();  // a turn around goes on to its end
    pursuit_.reset();
    if (command_.kind == CommandKind::Drive && command_.path.size() >= 2) {
      PurePursuitOptions o = pursuit_options_;
      o.speed_mps = std::max(1e-3, command_.speed_mps);
      pursuit_ = std::make_unique<PurePursuit>(densePath(Polyline2(command_.path), 0.25), o, limits_);
      pursuit_->continueTurningInPlace(turning);
    }
  }
  if (const CurrentPosition* p = board.position(Module::MotionControl, t)) model_.setPose(p->pose);
  return &command_;
}

VehicleCommand MotionControlModule::control(Blackboard& board, double t, double dt) {
  VehicleCommand out;
  const MotionCommand* c = board.command(Module::MotionControl, t);
  if (c == nullptr) {  // expired: the blackboard dropped it; stand still
    has_command_ = false;
    pursuit_.reset();
  } else if (!has_command_ || c->sequence != command_.sequence) {
    receive(board, t);
  }
  if (has_command_ && command_.kind == CommandKind::Drive && pursuit_) {
    if (command_.path_ends_at_turn && pursuit_->finished(model_.pose())) {
      // at the turnaround: stand until the next plan, back the way it came
    } else if (command_.path_ends_at_goal && pursuit_->finished(model_.pose())) {
      arrived_ = arrived_ || model_.speed() <= 1e-9;
    } else {
      out = pursuit_->command(model_.pose());
    }
  }
  model_.step(out, dt);
  return out;
}

}  // namespace mapnav
