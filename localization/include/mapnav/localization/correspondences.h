#pragma once
// Line correspondences for map matching (Wallace 1985, 2.2.3): "the Map module selects crossing
// lines in the detected objects and corresponding lines in the map data". A detected ground segment
// (vehicle frame) paired with the map line (world frame) it lies on, and the three ways of making
// them: by label against the predicted interest segments, by label against the map's edge
// polylines piece by piece, and (park mode) the detected centre line against the nearest road's.
#include <optional>
#include <string>
#include <vector>

#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/segment2.h"

namespace mapnav {

class Map;
struct Prediction;
struct DetectedObject;

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

}  // namespace mapnav
