#pragma once
// The pose filter (Wallace 1985, 2.2.3: "the location along the road is calculated using the
// vehicle motion"): an extended Kalman filter over (x, y, heading) — odometry prediction with a
// noise model, line-measurement updates (an iterated EKF) with a Mahalanobis gate — so that
// unobserved directions (along a straight road) are carried by odometry and corrected when crossing
// lines come into view. Its output is the CurrentPosition token.
//
// State and covariance are in world coordinates (x, y in m, heading in rad), the pose's heading
// wrapped into (-pi, pi]; differences of headings are wrapped before use.
#include <string>
#include <vector>

#include "mapnav/geometry/motion.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/localization/correspondences.h"
#include "mapnav/localization/line_fit.h"
#include "mapnav/tokens/current_position.h"

namespace mapnav {

/// Odometry noise (as AMCL's alphas): each step's standard deviations grow with the motion.
struct MotionNoiseOptions {
  /// Distance sigma per metre driven, m/m. 5 %, more than the encoders' random error: the
  /// filter's random-walk model must cover an encoder scale error of 1-1.5 % (systematic) over the
  /// 40-60 m between intersections, or the crossing lines of the next intersection fail the
  /// Mahalanobis gate and the estimate is lost (measured on campus_dialogue at I2: d^2 = 27-45
  /// with 2 %).
  double distance_sigma_per_m = 0.05;
  double heading_sigma_per_rad = 0.02;    ///< heading sigma per radian turned, rad/rad
  double heading_sigma_per_m = 0.002;     ///< heading sigma per metre driven (slip, gyro drift), rad/m
  double base_sigma_m = 0.001;            ///< added to x and y every step, m
  double base_heading_sigma_rad = 0.0002; ///< added to the heading every step, rad

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

struct FilterOptions {
  LineMatchOptions match;
  MotionNoiseOptions motion;
  /// Measurements whose innovation has a Mahalanobis distance beyond the chi-square quantile of
  /// this probability (degrees of freedom: the directions observed) are rejected.
  double gate_probability = 0.999;
  /// Iterated EKF: relinearisations of the update at most (1: a plain EKF update).
  int update_iterations = 5;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// An extended Kalman filter over the pose (x, y, heading) in the world.
class PoseFilter {
 public:
  /// Throws InvalidInput for bad options or a covariance that is not symmetric positive definite.
  PoseFilter(const Pose2& pose, const Mat3& covariance, const FilterOptions& options = {});

  const Pose2& pose() const { return pose_; }
  const Mat3& covariance() const { return covariance_; }
  const FilterOptions& options() const { return options_; }

  /// Dead reckoning: move by `motion` (along the mid-step heading) and grow the covariance.
  void predict(const MotionIncrement& motion);

  /// Fuses line correspondences: a robust fit finds the inliers, the gate compares the fitted pose
  /// with the prior in the observed directions, and an iterated EKF update uses the inliers' stacked
  /// point-to-line distances as the measurement, so that unobserved directions get no correction.
  /// The returned position's status says whether the pose changed; on Rejected / OdometryOnly the
  /// filter is left as it was.
  CurrentPosition update(const std::vector<LineCorrespondence>& lines, double timestamp = 0);

  /// The filter's state as a CurrentPosition (status OdometryOnly, nothing observed).
  CurrentPosition current(double timestamp, std::string reason) const;

 private:
  Pose2 pose_;
  Mat3 covariance_;
  FilterOptions options_;
};

}  // namespace mapnav
