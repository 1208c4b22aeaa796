#pragma once
// Map matching, the Map module's step (Wallace 1985, 2.2.3): "the Map module selects crossing lines
// in the detected objects and corresponding lines in the map data, and calculates coordinates
// transformation which can match them." localize() predicts the pose filter with odometry, matches
// the labelled lines of a DetectedObject to the Prediction (or, in park mode, the detected centre
// line to the nearest road's) and updates, giving the CurrentPosition token.
//
// The layers it uses are usable on their own: correspondences.h (which lines), line_fit.h (the pose
// they give), pose_filter.h (the filter), observability.h (what they constrain).
#include <optional>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/localization/pose_filter.h"
#include "mapnav/tokens/current_position.h"

namespace mapnav {

class Camera;
class Map;
struct Prediction;
struct DetectedObject;

struct LocalizeOptions {
  double edge_sigma_m = 0.05;           ///< 1-sigma of a detected edge's end points across their line, m
  double centerline_sigma_m = 0.10;     ///< the same for a detected centre line (park mode), m
  double min_line_length_m = 0.3;       ///< shorter detected lines are ignored, m
  double centerline_search_m = 3.0;     ///< park mode: roads at most this far from the centre line, m
  /// > 0 (and a map given): labelled road edges are matched piecewise against the map's edge
  /// polylines, pieces at most this long (edgeCorrespondences), m; 0: against the predicted chord.
  /// 1 m: on the campus' curves (R5, R6: 35 m radius) the predicted chords bias the pose along the
  /// road and in heading (docs/measurements.md).
  double curve_piece_m = 1.0;
  /// > 0 (and a camera given): each edge correspondence's sigma also covers this many pixels of
  /// detection error across the line in the image, turned into metres on the ground where the line
  /// is seen: sigma = hypot(edge_sigma_m, edge_sigma_px * metres per pixel across it). A line
  /// across the road 10 m ahead is seen at 7 cm per pixel (Terregator camera) against 1 cm for a
  /// road edge beside it, so its along-road information is worth far less than edge_sigma_m says; 0:
  /// edge_sigma_m alone. 2 px: with one 5 cm sigma for every line, one badly placed crossing line
  /// collapses the along-road sigma and the gate then refuses the good ones (docs/measurements.md).
  double edge_sigma_px = 2.0;
  /// Landmarks: the detected base pixel's covariance is widened by this many pixels in
  /// each direction (the detector's own covariance plus the map's survey error and the landmark's
  /// lean, seen from the camera), px. 1 px: a pole's base seen 10 m ahead by the Terregator camera is
  /// 1-2 cm across and 5-7 cm along the line of sight per pixel.
  double landmark_sigma_px = 1.0;
  /// Fuse the ground's step (DetectedObject::step; PoseFilter::updateStep). False: the
  /// odometry's scale is learnt from lines and landmarks alone (to compare, or where the ground is
  /// known to move: a conveyor, a ferry's deck).
  bool use_ground_step = true;
  /// The ground's step: Vision's 1-sigma is widened by this, m,
  /// in quadrature: the camera's pitch and height as the vehicle rocks and the ground's slope move
  /// the patch Vision registers. 5 mm: half Vision's own (GroundStepOptions::sigma_m).
  double step_sigma_m = 0.005;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// The options' names, rules and descriptions; validate() checks them.
const OptionTable<LocalizeOptions>& localizeOptionTable();

/// The Map module's step: predict `filter` with `motion`, match `detected`'s labelled lines to
/// `prediction`'s interest segments and update. Park mode: when no labelled line is usable and
/// `detected` has a centre line and `map` is given, that centre line against the nearest road's.
/// Then the landmarks `detected` found, matched by id to the prediction's, as range and bearing
/// updates (PoseFilter::updateLandmarks; they need `camera`). A failed DetectedObject, or nothing to
/// match, leaves the pose to odometry and says so. `camera`: the one the frame was taken with, for
/// LocalizeOptions::edge_sigma_px and the landmarks. `dt_s`: the time `motion` covers
/// (PoseFilter::predict). The result's along_cue says what observed the along-road position.
CurrentPosition localize(PoseFilter& filter, const MotionIncrement& motion, const Prediction& prediction,
                         const DetectedObject& detected, const LocalizeOptions& options = {},
                         const Map* map = nullptr, const Camera* camera = nullptr, double dt_s = 0);

/// A detected landmark's base pixel, with its covariance (px^2), as range and bearing on the ground
/// from `camera`'s optical centre (the covariance carried through the ground back-projection);
/// nullopt when the pixel does not see the ground. `map_world` is the landmark's place in the map.
std::optional<LandmarkObservation> landmarkObservation(const Camera& camera, const std::string& id, const Vec2& image_base,
                                                       const Mat2& pixel_covariance, const Vec2& map_world);

/// Metres on the ground across `line` (vehicle frame) per pixel across its image in `camera`, at
/// the line's midpoint; nullopt when the camera does not see it.
std::optional<double> groundMetresPerPixel(const Camera& camera, const Segment2& line);

}  // namespace mapnav
