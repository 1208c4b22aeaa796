#pragma once
// Map matching (Wallace 1985, 2.2.3): "the Map module selects crossing lines in the detected objects
// and corresponding lines in the map data, and calculates coordinates transformation which can match
// them. [...] when only straight portion of the road is in the view frame, the measurement [...] can
// constrain the vehicle position and orientation only perpendicular to the road. In such case, the
// location along the road is calculated using the vehicle motion."
//
// Three layers, each usable on its own:
//   - fitPoseToLines: the pose (x, y, heading) that puts detected ground segments (vehicle frame) on
//     their map lines (world frame), by robust Gauss-Newton / Levenberg-Marquardt, with the
//     information matrix and the directions the lines do not constrain;
//   - PoseFilter: an extended Kalman filter over (x, y, heading) — odometry prediction with a noise
//     model, line-measurement updates with a Mahalanobis gate — so that unobserved directions
//     (along a straight road) are carried by odometry and corrected when crossing lines come into view;
//   - localize: the Map module's step — predict with odometry, match the labelled lines of a
//     DetectedObject to the Prediction (or, in park mode, the detected centre line to the nearest
//     road's), update — giving the CurrentPosition token.
//
// State and covariance are in world coordinates (x, y in m, heading in rad), the pose's heading
// wrapped into (-pi, pi]; differences of headings are wrapped before use.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mapnav/geometry/motion.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/geometry/types.h"

namespace mapnav {

class Camera;
class Map;
struct Prediction;
struct DetectedObject;

// ---------------------------------------------------------------------------------------------
// Pose from line correspondences

/// The robust loss applied to each normalised residual u = r / sigma.
enum class RobustLoss {
  None,    ///< plain least squares, u^2 / 2
  Huber,   ///< quadratic within `loss_scale`, linear beyond (convex: a unique minimum)
  Cauchy,  ///< scale^2/2 log(1 + (u/scale)^2): gross outliers get almost no weight. Started from
           ///< the Huber solution, so that its local minima do not trap the solve.
};
std::string_view toString(RobustLoss loss);
std::optional<RobustLoss> robustLossFromString(std::string_view text);

/// A detected ground segment and the map line it lies on. Its two end points are the sample points:
/// the point-to-line distance is linear along the segment, so interior points add no information
/// and would not be independent of the ends.
struct LineCorrespondence {
  std::string id;               ///< the interest segment id ("R1.left.0"), for reports
  Segment2 detected_vehicle;    ///< metres on the ground, vehicle frame (x forward, y left)
  Segment2 map_world;           ///< world frame; only its infinite line is used
  double sigma_m = 0.05;        ///< 1-sigma perpendicular error of each detected end point, m (> 0)
  /// The map lines (finite segments, world frame) the detected segment may lie on, for
  /// re-association: when not empty, the solvers pick `map_world` among them anew at every
  /// Gauss-Newton iterate — the candidate nearest to the detected segment's midpoint placed in the
  /// world by the iterate, among those within `LineMatchOptions::reassociate_max_angle_deg` of its
  /// direction (all of them when none is) — so that a piece whose prior-pose projection fell on the
  /// wrong segment of a bent or notched edge moves to the right one as the pose converges. Empty:
  /// `map_world` is fixed.
  std::vector<Segment2> candidates;
};

struct LineMatchOptions {
  /// The robust loss, and its scale in sigmas of the normalised residual. It only has to bring the
  /// solve near the inliers' pose: the inlier threshold below decides what is used.
  RobustLoss loss = RobustLoss::Cauchy;
  double loss_scale = 3.0;
  /// After the robust solve, a correspondence with an end point farther than this many sigmas from
  /// its line is an outlier; the pose is then re-solved by plain least squares on the inliers (so
  /// that the reported information matches the estimate's spread under Gaussian noise).
  double inlier_threshold = 4.0;
  /// Gauss-Newton / Levenberg-Marquardt iterations at most, per stage.
  int max_iterations = 50;
  /// Stop when a step is shorter than this (m and rad together).
  double step_tolerance = 1e-10;
  /// An eigen-direction of the information matrix with less information than this is unobserved
  /// (1/m^2 or 1/rad^2: a standard deviation above 1 m or 1 rad at the default). The solve leaves
  /// the pose unchanged along unobserved directions.
  double min_information = 1.0;
  /// Re-association (LineCorrespondence::candidates): a candidate whose line makes more than this
  /// angle with the detected segment placed in the world is only taken when no candidate is closer
  /// in angle, degrees (in (0, 90]).
  double reassociate_max_angle_deg = 30.0;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// Which directions a measurement constrains, from its information matrix. Along and lateral are
/// the vehicle's axes at `heading` (forward x and left y), so "along" is along the road while the
/// vehicle follows one. A direction is observed when it lies within 45° of the span of the
/// eigenvectors whose eigenvalue reaches `min_information`. (Line measurements leave unobserved
/// either nothing, one pure translation along parallel lines, or everything.)
struct Observability {
  bool lateral = false;
  bool along = false;
  bool heading = false;
  /// Unit eigenvectors (x, y, heading) of the unobserved directions, smallest eigenvalue first.
  std::vector<Vec3> unobserved;
};
Observability observability(const Mat3& information, double heading, double min_information = 1.0);

struct LineFit {
  Pose2 pose;                         ///< world frame
  /// J^T W J of the inliers' end points at `pose`, W = 1/sigma^2, over (x, y, heading). Singular
  /// when the lines leave a direction unobserved; its inverse, where it exists, is the covariance.
  Mat3 information = Mat3::Zero();
  int iterations = 0;                 ///< Gauss-Newton steps taken, all stages
  bool converged = false;             ///< the final least-squares stage reached a minimum within max_iterations
  double rms_m = 0;                   ///< RMS point-to-line distance of the inliers' end points, m
  int inliers = 0;                    ///< correspondences used in the final solve
  std::vector<std::string> outliers;  ///< ids of the correspondences rejected...
  std::vector<std::size_t> outlier_indices;  ///< ... and their indices in the input
  Observability observed;             ///< of `information`, at `pose`
  /// Per input correspondence: the map line it was matched against at `pose` (its `map_world`, or
  /// the candidate re-association chose).
  std::vector<Segment2> map_lines;
};

/// The pose that puts each detected segment on its map line, starting from `prior` (world frame).
/// Directions the lines leave unobserved keep the prior's value. Nothing when there is no
/// correspondence or none is an inlier.
std::optional<LineFit> fitPoseToLines(const Pose2& prior, const std::vector<LineCorrespondence>& lines,
                                      const LineMatchOptions& options = {});

/// The correspondences of `detected`'s labelled lines (not frame edges, at least `min_length_m`
/// long) whose label is an interest segment of `prediction`, with `sigma_m` each. Unknown labels
/// are skipped.
std::vector<LineCorrespondence> labelledCorrespondences(const Prediction& prediction, const DetectedObject& detected,
                                                        double sigma_m, double min_length_m = 0.0);

/// As labelledCorrespondences, but a line labelled with a road's edge segment ("R5.left.3") is
/// matched against the road's actual edge (`map`'s left or right edge polyline) instead of the
/// predicted segment's chord: it is cut into pieces at most `piece_m` long, and each piece, placed in
/// the world by `prior`, gets the edge polyline's segment nearest to its midpoint as its line, with
/// sigma_m * sqrt(pieces) so that the line carries the information of one. On a curve the chords of
/// the prediction and those of the image polygon break at different places, so end points measured
/// against the wrong chord's infinite line bias the pose (along the road and in heading); on a
/// straight edge this gives the same line as the chord. Pieces that fall beyond the stretch of edge
/// the predicted segment covers (+ 0.25 m) are left out: the edge does not go on where the prediction
/// cut it (inside a crossing road or an intersection). Intersection corners keep their segment.
std::vector<LineCorrespondence> edgeCorrespondences(const Map& map, const Prediction& prediction,
                                                    const DetectedObject& detected, const Pose2& prior,
                                                    double sigma_m, double min_length_m, double piece_m);

/// Park mode: the detected centre line against the centre line of the road nearest to it (its
/// midpoint placed in the world by `prior`, roads within `search_radius_m`). The detection is
/// straight and the road may curve: the detected line is cut back from its far end (to 1 m at the
/// least) until the map's chord between the points its ends project to is within sigma_m of the
/// road's centre line; the correspondence is that piece against that chord, with sigma_m combined
/// (root sum of squares) with the deviation left. When the ends project less than 0.5 m apart: the
/// whole line against the polyline's segment under its midpoint, with sigma_m. Nothing when no road
/// is that close.
std::optional<LineCorrespondence> centerlineCorrespondence(const Map& map, const Pose2& prior,
                                                           const Segment2& centerline_vehicle, double sigma_m,
                                                           double search_radius_m = 3.0);

// ---------------------------------------------------------------------------------------------
// The filter

/// Odometry noise (as AMCL's alphas): each step's standard deviations grow with the motion.
struct MotionNoiseOptions {
  double distance_sigma_per_m = 0.02;     ///< distance sigma per metre driven, m/m
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

/// What became of a measurement.
enum class PositionStatus {
  Corrected,     ///< lines were matched and fused
  OdometryOnly,  ///< no usable lines: the pose comes from odometry alone
  Rejected,      ///< the lines disagreed with the prior beyond the gate: odometry alone
};
std::string_view toString(PositionStatus status);
std::optional<PositionStatus> positionStatusFromString(std::string_view text);

/// The CurrentPosition token (Map → Navigator).
struct CurrentPosition {
  double timestamp = 0;                 ///< seconds, of the frame
  Pose2 pose;                           ///< world frame
  Mat3 covariance = Mat3::Zero();       ///< of (x, y, heading): m^2, m rad, rad^2
  /// Which directions this frame's lines observed (see Observability: the vehicle's axes). All
  /// false when the estimate comes from odometry alone.
  bool observed_lateral = false;
  bool observed_along = false;
  bool observed_heading = false;
  Mat3 information = Mat3::Zero();      ///< this frame's measurement information (zero: none)
  PositionStatus status = PositionStatus::OdometryOnly;
  std::string reason;                   ///< what was used, or why nothing was ("no labelled lines")
  int lines_used = 0;                   ///< correspondences fused
  std::vector<std::string> outliers;    ///< correspondences the robust fit rejected
  double mahalanobis_d2 = 0;            ///< the gate's statistic (0 when there was no measurement)
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

struct LocalizeOptions {
  double edge_sigma_m = 0.05;           ///< 1-sigma of a detected edge's end points across their line, m
  double centerline_sigma_m = 0.10;     ///< the same for a detected centre line (park mode), m
  double min_line_length_m = 0.3;       ///< shorter detected lines are ignored, m
  double centerline_search_m = 3.0;     ///< park mode: roads at most this far from the centre line, m
  /// > 0 (and a map given): labelled road edges are matched piecewise against the map's edge
  /// polylines, pieces at most this long (edgeCorrespondences), m; 0: against the predicted chord.
  double curve_piece_m = 0.0;
  /// > 0 (and a camera given): each edge correspondence's sigma also covers this many pixels of
  /// detection error across the line in the image, turned into metres on the ground where the line
  /// is seen: sigma = hypot(edge_sigma_m, edge_sigma_px * metres per pixel across it). A line
  /// across the road 10 m ahead is seen at 7 cm per pixel (Terregator camera) against 1 cm for a
  /// road edge beside it, so its along-road information is worth far less than edge_sigma_m says; 0:
  /// edge_sigma_m alone.
  double edge_sigma_px = 0.0;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// The Map module's step: predict `filter` with `motion`, match `detected`'s labelled lines to
/// `prediction`'s interest segments and update. Park mode: when no labelled line is usable and
/// `detected` has a centre line and `map` is given, that centre line against the nearest road's.
/// A failed DetectedObject, or nothing to match, leaves the pose to odometry and says so. `camera`:
/// the one the frame was taken with, for LocalizeOptions::edge_sigma_px.
CurrentPosition localize(PoseFilter& filter, const MotionIncrement& motion, const Prediction& prediction,
                         const DetectedObject& detected, const LocalizeOptions& options = {},
                         const Map* map = nullptr, const Camera* camera = nullptr);

/// Metres on the ground across `line` (vehicle frame) per pixel across its image in `camera`, at
/// the line's midpoint; nullopt when the camera does not see it.
std::optional<double> groundMetresPerPixel(const Camera& camera, const Segment2& line);

}  // namespace mapnav
