#pragma once
// CurrentPosition: Map → Navigator (Wallace 1985, 2.2.3): the vehicle's estimated pose for one
// frame, its covariance, which directions the frame's lines observed and what became of the
// measurement. Made by localization's PoseFilter / localize(); read by the Navigator and Motion
// Control through the blackboard.
//
// World frame: x, y in m, heading in rad wrapped into (-pi, pi]; the covariance over (x, y, heading).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/types.h"

namespace mapnav {

/// What became of a measurement.
enum class PositionStatus {
  Corrected,     ///< lines were matched and fused
  OdometryOnly,  ///< no usable lines: the pose comes from odometry alone
  Rejected,      ///< the lines disagreed with the prior beyond the gate: odometry alone
  /// The road Vision found disagrees with the map seen from the estimate and no pose explains it
  /// clearly yet (RelocalizeOptions): the estimate is odometry's, and the vehicle stops.
  Lost,
};
std::string_view toString(PositionStatus status);
std::optional<PositionStatus> positionStatusFromString(std::string_view text);

/// What fixed the position along the road in a frame: lines across the road (an
/// intersection's or a corner's), landmarks, or nothing (odometry carries it).
enum class AlongCue { None, Intersection, Landmark };
/// "none", "intersection", "landmark".
std::string_view toString(AlongCue cue);

/// The CurrentPosition token (Map → Navigator).
struct CurrentPosition {
  double timestamp = 0;                 ///< seconds, of the frame
  Pose2 pose;                           ///< world frame
  /// Of (x, y, heading): m^2, m rad, rad^2, relative to the map (what the lines observe).
  Mat3 covariance = Mat3::Zero();
  /// The map's own error where the vehicle is (its position_sigma_m; PoseFilter::mapCovariance):
  /// the pose in the world is uncertain by covariance + map_covariance. Zero for an exact map.
  Mat3 map_covariance = Mat3::Zero();
  /// Which directions this frame's lines observed (see localization's Observability: the vehicle's
  /// axes). All false when the estimate comes from odometry alone.
  bool observed_lateral = false;
  bool observed_along = false;
  bool observed_heading = false;
  Mat3 information = Mat3::Zero();      ///< this frame's measurement information (zero: none)
  PositionStatus status = PositionStatus::OdometryOnly;
  std::string reason;                   ///< what was used, or why nothing was ("no labelled lines")
  int lines_used = 0;                   ///< correspondences fused
  int landmarks_used = 0;               ///< landmark observations fused
  std::vector<std::string> landmarks_rejected;  ///< landmark observations beyond the gate
  bool step_used = false;               ///< the ground's step since the last frame was fused
  AlongCue along_cue = AlongCue::None;  ///< what observed the along-road position, if anything
  std::vector<std::string> outliers;    ///< correspondences the robust fit rejected
  double mahalanobis_d2 = 0;            ///< the gate's statistic (0 when there was no measurement)
  int gate_dof = 0;                     ///< ... and its degrees of freedom, the directions observed
  /// When the gate rejected the lines: the pose they alone give (world frame), which the estimate
  /// was not moved to. Park mode widens its covariance only after several such fits agree.
  std::optional<Pose2> rejected_fit;
  /// ... and how well those lines fit together there: the RMS distance of their end points from
  /// their map lines at rejected_fit, m (0 when there is no rejected fit).
  double rejected_fit_rms_m = 0;
  /// IoU on the ground of Vision's road region and the predicted paved area (regionAgreement);
  /// nothing when there was no region to compare.
  std::optional<double> region_agreement;
  /// The Map module's check of its own consistency (localization/integrity.h): "ok", "uncertain"
  /// (the lines' innovations beyond their bound) or "departed" (the estimate was where odometry
  /// says the vehicle cannot be, and was put back on odometry: the status is then Lost); empty
  /// when nothing checked it.
  std::string integrity;
};

}  // namespace mapnav
