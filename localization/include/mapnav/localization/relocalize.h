#pragma once
// Re-localisation when the estimate is lost (beyond Wallace 1985, whose Map module halts and waits):
// the road Vision found, as a region on the ground, is compared with the map's paved area seen from
// pose hypotheses around the estimate; the pose that explains it clearly best is taken, with a
// covariance from the spread of the hypotheses that explain it as well (on a straight road they
// spread along it: the along-road ambiguity stays in the covariance instead of being guessed).
//
// Frames: poses in the world frame (m, rad); regions on the ground in the vehicle frame (x forward,
// y left, m), as PredictedObject and DetectedObject carry them.
#include <cstddef>
#include <string>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/map/predict.h"
#include "mapnav/tokens/predicted_object.h"

namespace mapnav {

struct RelocalizeOptions {
  /// A frame whose detected region agrees with the predicted paved area by less than this IoU
  /// (in [0, 1]) sets off a search; 0: never search (docs/measurements.md).
  double search_below = 0.75;
  /// ... and whose area within the footprint is within this ratio (>= 1) of the predicted paved
  /// area's, either way: a shifted or turned road keeps its area, a region that swallowed the verge
  /// or lost half the road is Vision's error, not the pose's.
  double max_area_ratio = 1.25;
  /// The hypotheses: the estimate moved along its heading by up to +-along_m ...
  double along_m = 3.0;
  /// ... and across it by up to +-across_m ...
  double across_m = 1.5;
  /// ... in steps of step_m (> 0) ...
  double step_m = 0.25;
  /// ... and turned by up to +-heading_deg in steps of heading_step_deg (> 0; 0 range: the estimate's heading).
  double heading_deg = 6.0;
  double heading_step_deg = 3.0;
  /// The winner must explain the region with at least this IoU, in (0, 1] ...
  double min_agreement = 0.85;
  /// ... and by at least this much more than the estimate does (else the estimate is as good as any:
  /// Vision's region is poor, the pose is not lost), in (0, 1].
  double min_gain = 0.15;
  /// Hypotheses within this IoU of the best explain the region as well: their spread is the
  /// re-localised covariance, in [0, 1).
  double tie = 0.03;
  /// The winner is clear when the ties spread across the road by at most this (1-sigma, m) ...
  double max_across_sigma_m = 0.4;
  /// ... and in heading by at most this (1-sigma, degrees); along the road they may spread.
  double max_heading_sigma_deg = 5.0;
  /// The Map module (MapModule::recover): the vehicle stands at most this many frames (>= 1) for a
  /// winner to be confirmed; then the search gives up until a frame fuses lines or the region agrees.
  int max_lost_frames = 4;
  /// The ground grid the regions are compared on, m (> 0).
  double cell_m = 0.1;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

const OptionTable<RelocalizeOptions>& relocalizeOptionTable();

/// How the detected road region (vehicle frame) compares with a view's predicted paved area
/// (view.regions), both within the view's footprint, on a grid of `cell_m` cells.
struct RegionAgreement {
  double iou = 0;         ///< 0 when either is empty
  double area_ratio = 0;  ///< the region's area over the paved area's (0 when the paved area is empty)
  /// The region is the road's size: its area within `max_ratio` (>= 1) of the paved area's, either way.
  bool roadSized(double max_ratio) const { return area_ratio <= max_ratio && area_ratio * max_ratio >= 1; }
};
RegionAgreement regionAgreement(const PredictedObject& view, const Polygon2& detected, double cell_m);

struct RelocalizeResult {
  bool clear = false;           ///< a clear winner: `pose` and `covariance` are the re-localised estimate
  Pose2 pose;                   ///< the ties' mean (world frame)
  Mat3 covariance = Mat3::Zero();  ///< of (x, y, heading): the ties' spread and the grid's resolution
  double best = 0;              ///< the best hypothesis's IoU
  RegionAgreement estimate;     ///< the estimate's
  std::size_t hypotheses = 0;   ///< tried
  std::size_t ties = 0;         ///< within `tie` of the best
  Vec3 spread = Vec3::Zero();   ///< 1-sigma of the ties along, across (m) and in heading (rad), estimate's axes
  std::string reason;           ///< what was found, or why nothing clear was
};

/// Tries the hypotheses of `options` around `estimate` (its own heading's axes) against `detected`
/// (the road region Vision found, vehicle frame), predicting each with `predictor` and `camera`.
RelocalizeResult relocalize(ViewPredictor& predictor, const Camera& camera, const Pose2& estimate,
                            const Polygon2& detected, const RelocalizeOptions& options = {});

}  // namespace mapnav
