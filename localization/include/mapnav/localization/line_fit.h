#pragma once
// The pose from line correspondences (Wallace 1985, 2.2.3: "calculates coordinates transformation
// which can match them"): the pose (x, y, heading) that puts detected ground segments (vehicle
// frame) on their map lines (world frame), by robust Gauss-Newton / Levenberg-Marquardt, with the
// information matrix and the directions the lines do not constrain.
//
// Poses are in the world frame (x, y in m, heading in rad wrapped into (-pi, pi]); differences of
// headings are wrapped before use.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/localization/correspondences.h"
#include "mapnav/localization/observability.h"

namespace mapnav {

/// The robust loss applied to each normalised residual u = r / sigma.
enum class RobustLoss {
  None,    ///< plain least squares, u^2 / 2
  Huber,   ///< quadratic within `loss_scale`, linear beyond (convex: a unique minimum)
  Cauchy,  ///< scale^2/2 log(1 + (u/scale)^2): gross outliers get almost no weight. Started from
           ///< the Huber solution, so that its local minima do not trap the solve.
};
std::string_view toString(RobustLoss loss);
std::optional<RobustLoss> robustLossFromString(std::string_view text);

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
  /// the pose unchanged along unobserved directions (why 1: docs/measurements.md).
  double min_information = 1.0;
  /// Re-association (LineCorrespondence::candidates): a candidate whose line makes more than this
  /// angle with the detected segment placed in the world is only taken when no candidate is closer
  /// in angle, degrees (in (0, 90]).
  double reassociate_max_angle_deg = 30.0;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// The options' names, rules and descriptions; validate() checks them.
const OptionTable<LineMatchOptions>& lineMatchOptionTable();

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

}  // namespace mapnav
