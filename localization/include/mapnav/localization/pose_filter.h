#pragma once
// The pose filter (Wallace 1985, 2.2.3: "the location along the road is calculated using the
// vehicle motion"): an extended Kalman filter over (x, y, heading), the odometry's scale error
// and gyro bias and a GNSS receiver's slowly drifting bias — odometry prediction with its error model, line-measurement updates (an iterated
// EKF, a frame's lines sharing an error) with a Mahalanobis gate — so that unobserved directions
// (along a straight road) are carried by odometry and corrected when crossing lines come into view,
// with a covariance that covers the error. Its output is the CurrentPosition token.
//
// State and covariance are in world coordinates (x, y in m, heading in rad; then e, relative, b,
// rad/s, and the receiver's bias gx, gy, m), the pose's heading wrapped into (-pi, pi]; differences
// of headings are wrapped before use.
#include <optional>
#include <string>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/motion.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/localization/correspondences.h"
#include "mapnav/localization/line_fit.h"
#include "mapnav/tokens/current_position.h"

namespace mapnav {

/// The odometry's error model. Two errors are systematic and are states of the filter, estimated
/// online in every mode from the corrections the lines make: the encoders' scale (the true distance
/// is (1 + e) times the reading; a wheel radius error) and the gyro's bias (the true heading change
/// is the reading minus b dt). Their a priori sigmas make the along-road variance grow with the
/// square of the distance driven (sigma_e^2 d^2, the growth of a systematic error) and the heading
/// variance with the square of the elapsed time (sigma_b^2 t^2), standing or driving, until the
/// lines observe them. The rest is random: per step it grows with the motion (as AMCL's alphas)
/// and with the elapsed time (the gyro's angle random walk).
struct MotionNoiseOptions {
  /// A priori 1-sigma of the encoders' relative scale error, the state e (0: not estimated).
  /// 0.02: a pneumatic or rubber tyre's rolling radius changes 1-2 % with pressure, load and wear,
  /// and a factory wheel-radius calibration is no better.
  double scale_sigma = 0.02;
  /// A priori 1-sigma of the gyro's bias, the state b, deg/s (0: not estimated). 0.1 deg/s: a
  /// consumer MEMS gyro's in-run bias after its start-up zeroing, over temperature and time
  /// (datasheets: +-0.5-3 deg/s uncalibrated, 0.05-0.2 deg/s after zeroing).
  double gyro_bias_sigma_deg_s = 0.1;
  /// Angle random walk, deg per sqrt(s): the heading variance grows by this^2 per second, also
  /// when standing. 0.1: the rate noise of a consumer MEMS gyro (0.005-0.015 deg/s/sqrt(Hz)) with
  /// the vibration of a small vehicle on paving and the encoders' heading quantisation on top.
  double gyro_noise_deg_per_sqrt_s = 0.1;
  /// Random distance error per metre driven, m/m (wheel slip, uneven paving; the scale error is
  /// the state e, not this). 0.02: AMCL's default translational alpha order.
  double distance_sigma_per_m = 0.02;
  double heading_sigma_per_rad = 0.02;    ///< heading sigma per radian turned, rad/rad
  double heading_sigma_per_m = 0.002;     ///< heading sigma per metre driven (wheel slip), rad/m
  double base_sigma_m = 0.001;            ///< added to x and y every step, m
  double base_heading_sigma_rad = 0.0002; ///< added to the heading every step, rad

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// The options' names, rules and descriptions; validate() checks them.
const OptionTable<MotionNoiseOptions>& motionNoiseOptionTable();

struct FilterOptions {
  LineMatchOptions match;
  MotionNoiseOptions motion;
  /// Measurements whose innovation has a Mahalanobis distance beyond the chi-square quantile of
  /// this probability (degrees of freedom: the directions observed) are rejected.
  double gate_probability = 0.999;
  /// The error all lines of one frame share, as a pose error: the camera's attitude and height as
  /// the vehicle rocks and the map's survey error move every line of a frame together, so that a
  /// frame's many lines are not independent measurements. Each update's information I is reduced to
  /// (I^-1 + R)^-1, R = diag(frame_sigma_m^2, frame_sigma_m^2, frame_heading_sigma^2), and the gate
  /// adds R to the fit's covariance; m and degrees. 1 cm: a surveyed map's edges (a total-station or
  /// RTK survey, 1-3 cm; docs/measurements.md); 0.3 deg: the camera's yaw mounting calibration and the
  /// roll of a small vehicle on paving. 0: lines independent.
  double frame_sigma_m = 0.01;
  double frame_heading_sigma_deg = 0.3;
  /// Iterated EKF: relinearisations of the update at most (1: a plain EKF update).
  int update_iterations = 5;
  /// How far along a road the map's error stays alike, m (> 0): the correlation length of a
  /// centre line's offset from its true place (PoseFilter::setMapSigma). 30 m: OpenStreetMap's and
  /// hand-drawn centre lines are straight pieces between vertices 10-50 m apart, each off by its
  /// own offset and a degree or two of direction.
  double map_correlation_m = 30.0;
  /// The GNSS receiver's error that drifts slowly (multipath, the atmosphere, the satellites in
  /// view): the states gx, gy, a first-order Gauss-Markov process per axis of this steady 1-sigma, m
  /// (0: fixes taken as independent, no bias state), forgetting itself to 1/e over gnss_bias_time_s.
  /// Fixes a second apart share it: taken as independent, ten of them would pull the estimate to
  /// the bias as if it were the truth. 1.5 m over 60 s: a consumer receiver's (1.5-3 m horizontal
  /// accuracy, most of it a bias that changes over minutes); an RTK receiver's is centimetres.
  double gnss_bias_sigma_m = 1.5;
  double gnss_bias_time_s = 60.0;  ///< its correlation time, s (> 0)

  /// Throws InvalidInput naming match's, then motion's, then this table's first broken rule.
  void validate() const;
};

/// The options' own fields (match and motion have their tables); validate() checks them.
const OptionTable<FilterOptions>& filterOptionTable();

/// The filter's full state: x, y (m), heading (rad), the odometry scale error e (relative), the
/// gyro bias b (rad/s) and the GNSS receiver's bias gx, gy (m, world frame), in that order.
inline constexpr int kStateSize = 7;
using StateVector = Eigen::Matrix<double, kStateSize, 1>;
using StateMatrix = Eigen::Matrix<double, kStateSize, kStateSize>;

/// A landmark seen in one frame: where the map has it and where the camera saw it, as
/// range and bearing on the ground from the camera's optical centre. Unlike a road edge it fixes
/// the position along the road as well as across it.
struct LandmarkObservation {
  std::string id;                       ///< the map's landmark id
  Vec2 map_world = Vec2::Zero();        ///< its ground contact point in the map, world frame, m
  Vec2 origin_vehicle = Vec2::Zero();   ///< the optical centre's ground point, vehicle frame, m
  double range_m = 0;                   ///< measured distance on the ground from the origin, m
  double bearing_rad = 0;               ///< measured direction from the vehicle's x axis, CCW, rad
  Mat2 covariance = Mat2::Identity();   ///< of (range m, bearing rad)
};

/// What a frame's landmark observations did to the filter.
struct LandmarkUpdateResult {
  std::vector<std::string> used;      ///< ids fused, in the order given
  std::vector<std::string> rejected;  ///< ids beyond the gate (Mahalanobis, 2 degrees of freedom)
  Mat3 information = Mat3::Zero();    ///< the fused observations' information over (x, y, heading)
};

/// An extended Kalman filter over the pose (x, y, heading) in the world, with the odometry's scale
/// error and gyro bias as two more states (MotionNoiseOptions) and the GNSS receiver's bias as two
/// more (FilterOptions::gnss_bias_sigma_m).
class PoseFilter {
 public:
  /// Throws InvalidInput for bad options or a covariance that is not symmetric positive definite.
  PoseFilter(const Pose2& pose, const Mat3& covariance, const FilterOptions& options = {});

  const Pose2& pose() const { return pose_; }
  /// The pose's covariance (x, y, heading): the top-left block of fullCovariance().
  const Mat3& covariance() const { return covariance_; }
  /// The covariance of the full state (x, y, heading, e, b, gx, gy).
  const StateMatrix& fullCovariance() const { return full_; }
  /// The estimated odometry scale error e: the true distance is (1 + e) times the reading.
  double scaleError() const { return scale_error_; }
  /// The estimated gyro bias b, rad/s: the true heading change is the reading minus b dt.
  double gyroBias() const { return gyro_bias_; }
  /// The estimated bias of the GNSS receiver's fixes, world frame, m: a fix is the true position
  /// plus this plus white noise.
  const Vec2& gnssBias() const { return gnss_bias_; }
  const FilterOptions& options() const { return options_; }

  /// `motion`, the odometry's reading over `dt_s` seconds, corrected by the estimated scale and bias.
  MotionIncrement corrected(const MotionIncrement& motion, double dt_s = 0) const;

  /// Dead reckoning: correct `motion` (the odometry's reading over `dt_s` seconds) by the estimated
  /// scale and bias, move by it (along the mid-step heading) and grow the covariance.
  void predict(const MotionIncrement& motion, double dt_s = 0);

  /// Replaces the pose's covariance (a widened search); the scale, the biases keep their estimates
  /// and variances, their correlation with the pose is dropped. Throws InvalidInput as the constructor.
  void resetPoseCovariance(const Mat3& covariance);

  /// Moves the estimate to `pose`; the covariances and the scale and bias estimates stay (a
  /// re-localisation sets the covariance after with resetPoseCovariance; a fault injection keeps it).
  void moveTo(const Pose2& pose) { pose_ = pose; }

  /// Fuses line correspondences: a robust fit finds the inliers, the gate compares the fitted pose
  /// with the prior in the observed directions, and an iterated EKF update uses the inliers' stacked
  /// point-to-line distances as the measurement, so that unobserved directions get no correction.
  /// The returned position's status says whether the pose changed; on Rejected / OdometryOnly the
  /// filter is left as it was.
  CurrentPosition update(const std::vector<LineCorrespondence>& lines, double timestamp = 0);

  /// Fuses landmark observations one after another, each an EKF update of the full state with the range and bearing of the landmark from the optical centre: an
  /// observation along the road also estimates the odometry's scale, through its correlation with
  /// the position. Each is gated by its Mahalanobis distance (2 dof, FilterOptions::gate_probability)
  /// and skipped when beyond the gate. Throws InvalidInput for a covariance that is not positive
  /// definite or a non-finite measurement.
  LandmarkUpdateResult updateLandmarks(const std::vector<LandmarkObservation>& observations);

  /// Fuses a measurement of the distance driven over the last predict() (the ground's step,
  /// independent of the wheels), m, with its variance, m²: it observes the scale error e, and
  /// through the step's own random distance error (MotionNoiseOptions::distance_sigma_per_m) the
  /// position, exactly as the step moved it. Call it right after predict(), before any other
  /// update; false when there is no such step (none since the last update) or the measurement is
  /// beyond the gate (Mahalanobis, 1 degree of freedom). Throws InvalidInput for a non-finite
  /// measurement or a variance that is not > 0.
  bool updateStep(double measured_m, double variance);

  /// Fuses a fix of the position (a GNSS receiver's, world frame, m) with its stated 1-sigma per
  /// axis, m: z = (x, y) + (gx, gy) + white noise, an EKF update of the full state, gated by the
  /// Mahalanobis distance (2 dof, FilterOptions::gate_probability); false when beyond the gate. The
  /// stated sigma is the fix's whole error; the bias state holds gnss_bias_sigma_m of it, the white
  /// noise the rest, sqrt(sigma² - bias²), and no less than half the stated sigma (a receiver that
  /// states better than the bias model: the fix is still used, the bias partly). Clears the step as
  /// every update does. Throws InvalidInput for a non-finite fix or a sigma that is not > 0.
  bool updatePosition(const Vec2& fix, double sigma_m);

  /// How well the map's roads are placed where the vehicle drives: 1-sigma per axis of a centre
  /// line's position, m (>= 0; 0, the default: an exact map). The lines fix the pose relative to the
  /// map, so the state is that pose; the map's own error is slowly varying along the road (over
  /// FilterOptions::map_correlation_m, L): driving d metres, the map-relative heading takes a random
  /// change of variance 2 (sigma / L)^2 (1 - exp(-d / L)) (a first-order Gauss-Markov direction error
  /// of sigma / L rad, the slope of a smooth offset of sigma over L) that odometry does not see, so
  /// that the estimate follows the map's bends. And the map's stretch: two points of its roads d
  /// apart are off by a difference of variance 2 sigma^2 (1 - exp(-d^2 / (2 L^2))) along the way
  /// (the squared-exponential field of sim/map_error.h), which odometry, measuring the ground, does
  /// not see either: driving from d0 to d1 metres past the last fix of the along-road position (lines
  /// that observe it, a landmark) adds the difference of that at d1 and d0 to the along-road
  /// variance of the pose, and nothing to the scale's (a stretched map is not a wrong odometer).
  /// Throws InvalidInput for a negative or non-finite sigma.
  void setMapSigma(double sigma_m);
  double mapSigma() const { return map_sigma_m_; }
  /// The map's own error over (x, y, heading) where the vehicle is: diag(sigma^2, sigma^2,
  /// (sigma / L)^2). The pose in the world is uncertain by covariance() + mapCovariance().
  Mat3 mapCovariance() const;

  /// The filter's state as a CurrentPosition (status OdometryOnly, nothing observed).
  CurrentPosition current(double timestamp, std::string reason) const;

 private:
  /// The end of a Kalman update whose posterior covariance the caller has put in full_: full_
  /// symmetrised, covariance_ from it, the state moved by `change`.
  void applyUpdate(const StateVector& change);

  Pose2 pose_;
  Mat3 covariance_;  // full_'s top-left block
  StateMatrix full_;
  double scale_error_ = 0;
  double gyro_bias_ = 0;
  Vec2 gnss_bias_ = Vec2::Zero();
  double map_sigma_m_ = 0;
  double along_since_fix_m_ = 0;  // driven since the along-road position was last observed (the map's stretch)
  FilterOptions options_;
  // The last predict()'s distance reading, its random error's variance and that error's effect on
  // the state (updateStep); cleared by every update.
  struct Step {
    double reading_m = 0, variance = 0;
    StateVector effect = StateVector::Zero();
  };
  std::optional<Step> step_;
};

}  // namespace mapnav
