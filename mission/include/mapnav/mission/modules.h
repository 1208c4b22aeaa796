#pragma once
// The four modules of the road-following subsystem (Wallace 1985, 2.1.1 and 4), each talking only
// through the blackboard:
//
//   Map            — knows the map and the vehicle's position: dead-reckons, predicts what the camera
//                    will see (PredictedObject), matches what Vision found to the map (CurrentPosition).
//   Vision         — knows images: gets the frame and the PredictedObject, nothing else; answers with a
//                    DetectedObject, or a VisionFailure and a Halt.
//   Navigator      — knows the route: progress from the CURRENT ESTIMATED position (never the truth),
//                    replanning, and the steering plan (MotionCommand).
//   Motion Control — executes the newest steering plan on the vehicle between frames (closed loop),
//                    dead-reckoning from the CurrentPosition; in replay it only records the commands.
//
// Each module's step is callable on its own (tests), and the runners (runner.h) call them in the
// paper's order once a frame.
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/localization/filter_supervisor.h"
#include "mapnav/localization/integrity.h"
#include "mapnav/localization/localize.h"
#include "mapnav/localization/pose_filter.h"
#include "mapnav/localization/relocalize.h"
#include "mapnav/map/map.h"
#include "mapnav/map/predict.h"
#include "mapnav/mission/blackboard.h"
#include "mapnav/mission/mission_file.h"
#include "mapnav/navigator/progress.h"
#include "mapnav/navigator/route.h"
#include "mapnav/navigator/steering.h"
#include "mapnav/navigator/vehicle.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {

// ---------------------------------------------------------------------------------------------
// Map

struct MapModuleOptions {
  PredictOptions predict;  ///< the predicted view (interest segments)
  /// The pose filter: odometry noise, matching, gate (its defaults are the missions').
  FilterOptions filter;
  /// Edge and centre-line noise, shortest line used, road edges matched piecewise on curves, pixel
  /// noise across lines (its defaults are the missions').
  LocalizeOptions localize;
  /// 1-sigma of the start position in x and y, m (> 0): the user says where the robot is
  /// ("Robot is at road R1, 3 meters from I1") to about this.
  double initial_sigma_m = 0.10;
  /// 1-sigma of the start heading, degrees (> 0).
  double initial_heading_sigma_deg = 1.0;
  /// A prediction whose paved area covers fewer image pixels than this (>= 0) is announced as
  /// "no road in view": Vision is not asked to find what the camera can hardly see (looking over the
  /// corner in a 90 degree turn) and the Map dead-reckons. 2000 px is 0.8 % of 512 x 480; on a
  /// camera smaller than 480 x 360 it is scaled by its area (pixelScale() squared).
  double min_visible_px = 2000.0;
  /// Fuse the frames' GNSS fixes (a replay log's, MapModule::observeGnss) into the pose filter with
  /// their stated sigma, each gated (PoseFilter::updatePosition). Off by default: a receiver's error
  /// drifts slowly, and the filter takes each fix as independent of the last.
  bool use_gnss = false;
  /// The filter's supervisor (localization/filter_supervisor.h), shown park mode's frames: a centre
  /// line and no labelled line, or no crossing line predicted in view. A centre line or road edges
  /// observe lateral position and heading but not the position along the road; on a tight curve an
  /// along-road error of d gives a heading error of d / radius that the filter does not know of
  /// (docs/measurements.md), and out of the curve the gate then rejects every correct measurement
  /// while the estimate runs off the path on odometry. When the supervisor says so, the covariance
  /// is widened and the frame matched again; by default it never does (its after_rejections is 0).
  /// In the option table its options keep the names they
  /// had before it was a component: park_reset_ and theirs (park_reset_after_rejections, ...).
  FilterSupervisorOptions supervisor;
  /// Recovery: when Vision's road region disagrees with the map seen from the estimate, pose
  /// hypotheses around it are tried against the region (relocalize.h). The first frame with a clear
  /// winner makes the position Lost (the Navigator stops); the next frame's search, the vehicle
  /// standing, must find the same winner (across the road and in heading within a step of it) before
  /// the estimate moves there, with the ties' spread as its covariance. After max_lost_frames Lost
  /// frames without that, the search gives up until lines are fused or the region agrees again.
  RelocalizeOptions relocalize;
  /// Integrity (localization/integrity.h): the lines' innovations over a window against their
  /// chi-square bound ("position uncertain", said in the trace and counted), and the estimate's
  /// departure from a dead reckoning of odometry alone: beyond its bound the estimate is put back on
  /// the dead reckoning and the frame is Lost (the vehicle stops). In the option table as integrity_*.
  IntegrityOptions integrity;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// MapModuleOptions' own fields, the supervisor's (as park_reset_*) and integrity's (as
/// integrity_*); its other components have tables of their own.
const OptionTable<MapModuleOptions>& mapModuleOptionTable();

class MapModule {
 public:
  /// `map` and `camera` must outlive the module. Throws InvalidInput for bad options.
  MapModule(const Map& map, const Camera& camera, const Pose2& start, const MapModuleOptions& options = {});

  /// A frame's first step: dead-reckon the filter with `odometry` (the motion since the previous
  /// frame) and post the PredictedObject for the predicted pose ("Vision will see ..."); an empty
  /// one when less than min_visible_px of road would be in the image.
  void predict(Blackboard& board, double t, const MotionIncrement& odometry);

  /// After Vision: match this frame's DetectedObject (a failed one, or none: odometry only, "never
  /// jumps") and post the CurrentPosition.
  const CurrentPosition& localize(Blackboard& board, double t);

  /// This frame's GNSS fix (world frame, m, and its 1-sigma per axis), fused in localize() when
  /// MapModuleOptions::use_gnss; call it between predict() and localize().
  void observeGnss(const Vec2& fix, double sigma_m) { gnss_ = std::pair{fix, sigma_m}; }

  /// Fault injection: moves the estimate `forward_m` along its heading and `left_m` to its left,
  /// the covariance kept (the filter does not know).
  void displaceEstimate(double forward_m, double left_m);

  /// The last prediction with what only the Map knows (the pose, world coordinates).
  const Prediction& prediction() const { return prediction_; }
  const PoseFilter& filter() const { return filter_; }
  const CurrentPosition& position() const { return position_; }
  /// The filter's estimate of the odometry scale, 1 + e (1: as measured; MotionNoiseOptions::scale_sigma).
  double odometryScale() const { return 1 + filter_.scaleError(); }
  /// Times the estimate was re-localised (RelocalizeOptions).
  std::size_t relocalisations() const { return relocalisations_; }

 private:
  const Map& map_;
  const Camera& camera_;
  MapModuleOptions options_;
  ViewPredictor predictor_;  // of map_ with options_.predict
  PoseFilter filter_;
  MotionIncrement pending_;  // odometry of the frame being processed, as read
  std::optional<std::pair<Vec2, double>> gnss_;  // ... and its GNSS fix, with its sigma
  double pending_dt_s_ = 0;  // ... and the time it covers, s
  double last_t_ = 0;        // the previous frame's time (the start: 0), s
  Prediction prediction_;
  CurrentPosition position_;
  FilterSupervisor supervisor_;  // shown park mode's frames
  IntegrityMonitor integrity_;
  /// Recovery: the last search's clear winner, as an offset from the estimate it was searched
  /// around (the vehicle's own frame: it moves with the odometry as the estimate does).
  std::optional<Pose2> candidate_;
  std::size_t relocalisations_ = 0;
  int lost_frames_ = 0;             ///< consecutive Lost frames
  bool search_suspended_ = false;   ///< the search gave up: until lines are fused or the region agrees
  bool per_road_sigma_ = false;     ///< some road states its own position_sigma_m (mapSigmaAt)
  /// Recovery after this frame's localisation: the region's agreement, the search, Lost or re-localised.
  void recover(const DetectedObject& detected, double t);
  /// Integrity after recovery: the verdict in position_, and a departed estimate put back on odometry.
  void checkIntegrity(double t);
  /// The position_sigma_m of the road nearest `pose` (within 50 m), else the map's; without a road
  /// of its own figure, the map's without a search.
  double mapSigmaAt(const Pose2& pose) const;
};

// ---------------------------------------------------------------------------------------------
// Vision

class VisionModule {
 public:
  /// Throws InvalidInput when `pipeline` is null.
  VisionModule(std::unique_ptr<VisionPipeline> pipeline, const HaltPolicy& halt = {});

  /// Reads the PredictedObject (the only token Vision may read: it never sees the map, the route or
  /// the pose), runs the pipeline on the frame and posts the DetectedObject. A failure (the
  /// pipeline's, no prediction for this frame, or an exception from the pipeline) also posts a
  /// VisionFailure and a Halt: "the Vision system halts and signals the blackboard so that another
  /// module (or person) [can] take control". An empty PredictedObject (no road in view) is not
  /// looked for: the DetectedObject is Ok with nothing in it. The landmarks the prediction lists
  /// are looked for too (the registered LandmarkFinder), unless the pipeline reported them itself,
  /// and the step from the previous frame is measured against the ground (the registered
  /// StepMeasurer, from the prediction's motion), whatever the pipeline found.
  const DetectedObject& see(Blackboard& board, const VisionFrame& frame);

  /// Forgets what the pipeline learnt (a new scene: the start, or after a halt).
  void reset();
  std::string pipelineName() const;
  const DetectedObject& detected() const { return detected_; }

 private:
  std::optional<MeasuredStep> measureStep(const VisionFrame& frame, const PredictedObject* prediction) const;

  std::unique_ptr<VisionPipeline> pipeline_;
  HaltPolicy halt_;
  DetectedObject detected_;
  // The previous frame's pixels, for the ground's step.
  std::vector<std::uint8_t> previous_rgb_;
  VisionFrame previous_;
};

// ---------------------------------------------------------------------------------------------
// Navigator

struct NavigatorOptions {
  RouteOptions route;        ///< route costs (replanning uses them too)
  ProgressOptions progress;  ///< off-route tolerance (a replan beyond it)
  /// The steering law Motion Control runs on the plan (lookahead) and the cruise speed.
  PurePursuitOptions steering;
  /// The steering plan: the route's centre line from this far behind the estimated position ...
  double plan_behind_m = 1.0;
  /// ... to this far ahead, m (> 0). More than the vehicle drives between two frames.
  double plan_ahead_m = 20.0;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// NavigatorOptions' own fields (the plan's extent); its components have tables of their own.
const OptionTable<NavigatorOptions>& navigatorOptionTable();

class NavigatorModule {
 public:
  /// Plans the route from `start` through `stops` (via points, then the goal). `map` must outlive
  /// the module. Throws Unreachable when there is no route, NotFound / InvalidInput for bad positions.
  NavigatorModule(const Map& map, const RoadPosition& start, std::vector<RoadPosition> stops,
                  const NavigatorOptions& options = {}, const VehicleLimits& limits = {});
  ~NavigatorModule();
  NavigatorModule(NavigatorModule&&) noexcept;
  NavigatorModule& operator=(NavigatorModule&&) noexcept;

  /// Reads the CurrentPosition and the Halt, moves the progress along the route, replans when the
  /// estimate is off the route (through the stops not reached yet), and posts the MotionCommand:
  /// Drive with the steering plan, or Stop while halted, without a position or without a route.
  /// Returns the command posted.
  const MotionCommand& plan(Blackboard& board, double t);

  /// The route being followed (the newest after a replan).
  const Route& route() const;
  const ProgressStatus& status() const { return status_; }
  std::size_t replans() const { return replans_; }
  /// The estimate is within 0.5 m of the goal.
  bool finished() const { return status_.finished; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  ProgressStatus status_;
  std::size_t replans_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Motion Control

class MotionControlModule {
 public:
  /// `execute`: closed loop, drives the vehicle; false: replay, records the commands only.
  /// `limits` are the vehicle's (its dead-reckoning model uses them). Throws InvalidInput for bad
  /// limits or a lookahead that is not > 0.
  MotionControlModule(bool execute, const VehicleLimits& limits = {}, double lookahead_m = 1.5);

  /// Once a frame, after the Navigator: takes the newest command (a newer one has aborted the older
  /// ones) and the CurrentPosition it was planned from, which resets the dead reckoning. Returns the
  /// command taken, or null.
  const MotionCommand* receive(Blackboard& board, double t);

  /// Closed loop, every control step of `dt` s: the command for the vehicle at the dead-reckoned
  /// pose. Zero (stop) when the command is Stop, has expired (dropped by the blackboard), or its plan
  /// ended at the goal and the vehicle is there. Advances the dead reckoning by the command, as the
  /// wheel encoders would (the model has the vehicle's limits).
  VehicleCommand control(Blackboard& board, double t, double dt);

  bool executing() const { return execute_; }
  /// The plan ended at the goal, the vehicle reached its end and stands still.
  bool arrived() const { return arrived_; }
  /// The dead-reckoned pose (the last CurrentPosition moved by the commands since).
  const Pose2& pose() const { return model_.pose(); }
  const MotionCommand* current() const { return has_command_ ? &command_ : nullptr; }
  /// The command held is a Drive that starts by turning in place at the dead-reckoned pose (its
  /// plan lies behind the vehicle: back from a turnaround), or is in such a turn.
  bool turningInPlace() const { return has_command_ && pursuit_ && pursuit_->turnsInPlaceAt(model_.pose()); }

 private:
  bool execute_;
  VehicleLimits limits_;
  PurePursuitOptions pursuit_options_;
  SkidSteerVehicle model_;
  MotionCommand command_;
  bool has_command_ = false;
  std::unique_ptr<PurePursuit> pursuit_;
  bool arrived_ = false;
};

}  // namespace mapnav
