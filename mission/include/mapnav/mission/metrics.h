#pragma once
// What a mission run measured, frame by frame and in total: the estimate and odometry alone against
// the truth (lateral and along the road at the true pose, heading), vision failures, halts, replans,
// and the module loop's latency.
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/map/map.h"
#include "mapnav/mission/blackboard.h"
#include "mapnav/mission/path_agreement.h"
#include "mapnav/navigator/route.h"
#include "mapnav/tokens/current_position.h"

namespace mapnav {

/// An estimate's error against the truth, in the road's frame at the true pose (estimate − truth).
struct PoseError {
  double lateral_m = 0;    ///< across the road, left positive
  double along_m = 0;      ///< along the road, forward positive
  double heading_rad = 0;  ///< wrapped into (-pi, pi]
  double distance_m = 0;   ///< |position error|
};

/// One frame of a run.
struct FrameRecord {
  std::size_t index = 0;
  double t = 0;                   ///< s
  std::optional<Pose2> truth;     ///< when the log (or the simulator) knows it
  // The Map's CurrentPosition.
  Pose2 estimate;
  Mat3 covariance = Mat3::Zero();
  PositionStatus status = PositionStatus::OdometryOnly;
  bool observed_lateral = false, observed_along = false, observed_heading = false;
  int lines_used = 0;
  int landmarks_used = 0;
  bool step_used = false;               ///< the ground's step was fused (CurrentPosition::step_used)
  AlongCue along_cue = AlongCue::None;  ///< what observed the along-road position
  /// Integrity (CurrentPosition::integrity): the lines' innovations beyond their bound ...
  bool position_uncertain = false;
  /// ... or the estimate departed from odometry and was put back on it (the status is Lost).
  bool departed = false;
  Pose2 odometry_only;            ///< dead reckoning alone from the start, same motion model
  /// A GNSS fix the log recorded with this frame (world frame, m) and its 1-sigma error: drawn in the
  /// report beside the truth, not used by the Map module.
  std::optional<Vec2> gnss;
  double gnss_sigma_m = 0;
  // Vision.
  bool vision_ok = true;
  std::string vision_reason;      ///< when it failed
  std::size_t lines_detected = 0, lines_labelled = 0;
  bool halted = false;            ///< a halt was in force after this frame's modules ran
  // The Navigator's command.
  CommandKind command = CommandKind::Stop;
  VehicleCommand setpoint;
  double to_go_m = 0;             ///< the Navigator's estimate of the distance left
  bool arrived = false;           ///< the Navigator believed the vehicle at the goal after this frame
  /// Loop latency: Map + Vision + Map + Navigator + Motion Control for this frame, ms (steady_clock;
  /// not rendering, not image decoding, not the trace).
  double latency_ms = 0;
  double vision_ms = 0;           ///< the Vision module's part of latency_ms
  // Against the truth (meaningful when `truth`).
  double route_s = 0;             ///< the truth's arc length along the planned route, m
  PoseError error;                ///< estimate − truth
  /// The road's heading at the truth, rad: `error` is measured along it and across it.
  double road_heading_rad = 0;
  PoseError odometry_error;       ///< odometry_only − truth
  /// "On the path": the largest |lateral offset| of the TRUE position from the centre line
  /// of the road nearest to it, over the frame period ending at this frame (closed loop: at every
  /// control step since the previous frame; replay: this frame's truth), m ...
  double offset_from_centre_m = 0;
  /// ... and the most it may be: half that road's width less half the vehicle's (PathOffset).
  double allowed_offset_m = 0;
  /// The vehicle's side went over the path's edge during this frame period.
  bool offPath() const { return truth.has_value() && offset_from_centre_m > allowed_offset_m; }
};

/// Where a true position is across the path: its offset from the nearest road's centre line, and
/// the most that offset may be while the whole vehicle stays on the paved path.
struct PathOffset {
  double offset_m = 0;   ///< |distance from the centre line|, m; kOffMap when no road is within 5 m
  double allowed_m = 0;  ///< that road's width / 2 − vehicle_width / 2 (0 off the map)
  static constexpr double kOffMap = 5.0;
};

/// The PathOffset of `position` on `map` for a vehicle `vehicle_width_m` wide.
PathOffset pathOffset(const Map& map, const Vec2& position, double vehicle_width_m);

/// RMS and maximum of a set of pose errors.
struct ErrorStats {
  double lateral_rms_m = 0, lateral_max_m = 0;
  double along_rms_m = 0, along_max_m = 0;
  double heading_rms_deg = 0, heading_max_deg = 0;
  double max_error_m = 0;  ///< largest |position error|
};

/// What can be wrong with a recorded log that a replay skips or repairs (docs/replay-log-format.md,
/// "Faults in replay").
enum class LogFaultKind {
  MissingImage,   ///< a frame's image (or mask) file is not in the log folder: the frame is skipped
  CorruptImage,   ///< a frame's PNG does not decode: the frame is skipped
  ImageSize,      ///< a frame's image is not the camera's size: the frame is skipped
  TimeOrder,      ///< a repeated or backwards `t`: the line is skipped (its odometry with it)
  OdometrySpike,  ///< odometry faster than RunOptions allows: replaced by the previous rate
  Truncated,      ///< the last line is cut short (the recording stopped mid-line): skipped
  BadLine,        ///< any other unreadable line (not JSON, a field missing, a bad path): skipped
};
inline constexpr std::size_t kLogFaultKinds = 7;

/// "missing_image", "corrupt_image", "image_size", "time_order", "odometry_spike", "truncated",
/// "bad_line".
std::string toString(LogFaultKind kind);
std::optional<LogFaultKind> logFaultKindFromString(std::string_view text);

/// How many faults of each kind a replay met.
struct LogFaultCounts {
  std::array<std::size_t, kLogFaultKinds> by_kind{};
  std::size_t& operator[](LogFaultKind kind) { return by_kind[static_cast<std::size_t>(kind)]; }
  std::size_t operator[](LogFaultKind kind) const { return by_kind[static_cast<std::size_t>(kind)]; }
  std::size_t total() const;
};

/// Whether the filter's covariance covers its true error (a consistent filter's does): per axis,
/// the fraction of frames with truth whose error lies within 2 sigma of the reported covariance
/// (expected 0.954 for a consistent Gaussian estimate), and the mean normalised estimation error
/// squared, NEES = e' P^-1 e over (x, y, heading) (expected 3, the state's dimension).
struct FilterConsistency {
  std::size_t frames = 0;           ///< frames with truth
  double within_2sigma_along = 0;   ///< fraction of `frames` with |along error| <= 2 sqrt(a' P a)
  double within_2sigma_lateral = 0; ///< ... across the road
  double within_2sigma_heading = 0; ///< ... |heading error| <= 2 sqrt(P(2,2))
  std::size_t nees_frames = 0;      ///< frames whose covariance is positive definite (NEES defined)
  double nees_mean = 0;             ///< mean NEES over them (0 when none)
};

/// One frame's part of FilterConsistency: its error within 2 sigma on each axis, and its NEES.
struct FrameConsistency {
  bool along = false, lateral = false, heading = false;
  std::optional<double> nees;  ///< nothing when `covariance` is not positive definite
};

/// `error` (estimate − truth along and across the road of heading `road_heading`, and in heading)
/// against the world-frame `covariance` of (x, y, heading).
FrameConsistency frameConsistency(const PoseError& error, const Mat3& covariance, double road_heading);

struct MissionMetrics {
  std::size_t frames = 0;
  bool has_truth = false;         ///< the errors below mean something
  /// The Navigator arrived (its estimate within 0.5 m of the goal) and: in closed loop the vehicle
  /// (the truth when known) ended within 0.5 m of the goal; in replay, where the log's recorded
  /// path goes where it went whatever the estimate did, the estimate was right to 0.5 m when the
  /// Navigator arrived (so the vehicle was then within 1 m of the goal).
  bool reached_goal = false;
  /// The vehicle (truth, else estimate) to the goal, m: at the end in closed loop; in replay at
  /// arrived_frame, or at the log's end when the Navigator never arrived.
  double goal_distance_m = 0;
  /// The first frame after which the Navigator believed the vehicle at the goal (FrameRecord::
  /// arrived); nothing: it never did.
  std::optional<std::size_t> arrived_frame;
  double estimate_goal_distance_m = 0;  ///< the Map's estimate at the end to the goal, m
  ErrorStats estimate;            ///< the Map's CurrentPosition
  ErrorStats odometry_only;       ///< dead reckoning alone
  FilterConsistency consistency;  ///< the estimate's covariance against its true error
  /// The largest |along-road error| within 2 m after each intersection of the route
  /// (truth between the intersection's centre and 2 m past it), m; 0 when no frame fell there.
  double along_after_intersection_max_m = 0;
  std::size_t intersections_checked = 0;  ///< intersections with at least one frame in that window
  /// "Stays on the path", from the truth: the largest offset of the true position from
  /// the nearest road's centre line over the run, m (FrameRecord::offset_from_centre_m) ...
  double max_offset_from_centre_m = 0;
  /// ... the least room left between the vehicle's side and the path's edge, m (negative: over it) ...
  double min_path_clearance_m = 0;
  /// ... and the frames in whose period the vehicle's side went over the path's edge.
  std::size_t left_path_frames = 0;
  /// There was truth and no frame left the path.
  bool stayedOnPath() const { return has_truth && left_path_frames == 0; }
  std::size_t vision_failures = 0;
  std::size_t halts = 0;          ///< halt periods (consecutive failures count once)
  std::size_t replans = 0;
  /// Recovery (RelocalizeOptions): frames whose position was Lost (the vehicle stopped) and the
  /// times the estimate was re-localised.
  std::size_t lost_frames = 0;
  std::size_t relocalisations = 0;
  /// Integrity (IntegrityOptions): frames whose position was uncertain, and the frames whose
  /// estimate had departed from odometry (put back on it; these are Lost frames too).
  std::size_t uncertain_frames = 0;
  std::size_t departures = 0;
  /// Frames whose distance driven since the previous one was measured from the ground and fused
  /// (the ground's step observes the odometry's scale).
  std::size_t ground_steps_used = 0;
  LogFaultCounts log_faults;      ///< replay: the log's faults met, by kind (MissionRun::faults)
  double latency_ms_median = 0, latency_ms_p99 = 0, latency_ms_max = 0;
  double vision_ms_median = 0;    ///< the Vision module's part (the pipeline)
  /// Path agreement (path_agreement.h) of each frame's detection with the vehicle's true future
  /// path, summed up (summarizePathAgreement of MissionRun::path_agreement); nothing without truth:
  /// not measured.
  std::optional<PathAgreementSummary> path_agreement;
};

/// The error of `estimate` against `truth` with the road heading `road_heading` at the truth.
PoseError poseError(const Pose2& estimate, const Pose2& truth, double road_heading);

/// Totals over `frames` (errors already filled in), arrived_frame too; reached_goal and the goal
/// distances (they need the goal), replans, halts and relocalisations are the caller's and are left
/// as they are in `into`.
void accumulateMetrics(const std::vector<FrameRecord>& frames, const Route& route, MissionMetrics& into);

/// Nearest-rank percentile (0..100) of `values`; 0 when empty.
double percentile(std::vector<double> values, double p);

}  // namespace mapnav
