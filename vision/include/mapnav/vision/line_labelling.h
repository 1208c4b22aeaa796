#pragma once
// Polygon fitting and line labelling (Wallace 1985, 2.2.2): the region's boundary is approximated
// by a polygon within a tolerance (CGAL Polyline_simplification_2), its edges are the straight
// lines; those along the image border (or the edge of the ground in the image) are frame edges and
// are never labelled; the others are matched to the predicted interest segments by angle and
// position on the ground, then checked against the predicted relations (parallel separations).
#include <optional>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/image/image.h"
#include "mapnav/tokens/detected_object.h"
#include "mapnav/tokens/predicted_object.h"

namespace mapnav {

struct LineOptions {
  double simplify_tolerance_px = 3.0;  ///< polygon fit tolerance, pixels. > 0
  double min_length_px = 12.0;         ///< shorter polygon edges are dropped. ≥ 0
  double frame_edge_px = 4.0;          ///< within this of the image border / ground edge = frame edge. ≥ 0
  double max_angle_deg = 10.0;         ///< a match is within this angle on the ground. > 0
  double max_distance_m = 0.4;         ///< ... and both end points within this of the predicted line. > 0
  /// ... or within this many sigma of it, where the prediction's pose covariance (the Map's estimate,
  /// PredictedObject::pose_covariance) puts the predicted line's sigma across itself at that point
  /// higher (max_distance_m is then the gate's floor, for pixel noise and the map's own error). The
  /// wider gate stops halfway to the neighbouring predicted segment (near-parallel, beside the
  /// point), so that it never takes a line that lies nearer another road edge: a gate wider than
  /// half a road's width labelled lines with the wrong edge before it stopped there. 0 (the
  /// default) = the fixed max_distance_m alone, on a map that states no error: there 3 made one run
  /// of the random-campus suite's 30 leave the path (docs/suite.md). >= 0
  double gate_sigma = 0.0;
  /// gate_sigma where the prediction's map states an error (PredictedObject::map_sigma_m > 0): the
  /// map's stretch then puts the next intersection's crossing lines more than max_distance_m from
  /// where they are predicted, and the estimate's along-road sigma says by how much (on the suite's
  /// maps 0.5 m wrong, 3 against 0: 24 of 30 runs within 0.5 m of the goal against 22, 3 runs off
  /// the path against 9; docs/suite.md). >= 0
  double gate_sigma_uncertain_map = 3.0;
  double min_overlap = 0.5;            ///< ... and this fraction of the line overlaps the segment. [0, 1]
  double relation_tolerance_m = 0.5;   ///< parallel pairs: separation within this of the predicted. > 0
  /// The reference implementations (CGAL's simplification; a distance transform of `valid` for the
  /// frame edges) instead of the fast ones with the same answers (tested).
  bool reference = false;

  /// lineOptionTable()'s rules. Throws InvalidInput naming the first bad field.
  void validate() const;
};
/// Its table: each option's name (the member's), rule and description.
const OptionTable<LineOptions>& lineOptionTable();

/// The closed `contour` (pixels) as straight lines with image and ground coordinates; frame edges
/// marked (`valid`: 1 channel, non-zero where pixels see the ground). The same as
/// polygonLines(contourPolygon(contour, options.simplify_tolerance_px, options.reference), ...).
std::vector<DetectedLine> fitLines(const std::vector<Vec2>& contour, const Camera& camera, const Image& valid,
                                   const LineOptions& options = {});

/// The closed `contour` (a ring of pixel centres without repeated closing point) simplified within
/// `tolerance_px` to a polygon (no repeated closing point either); the contour's start, an arbitrary
/// point, is dropped when it lies on a straight edge. `reference`: CGAL's simplification, else the
/// pixel-chain one (the same answer). Fewer than 3 contour points: empty.
std::vector<Vec2> contourPolygon(const std::vector<Vec2>& contour, double tolerance_px, bool reference);

/// A region's contour simplified for its lines and for its outline.
struct ContourPolygons {
  std::vector<Vec2> lines;    ///< contourPolygon(contour, lines_tolerance_px, reference)
  std::vector<Vec2> outline;  ///< the closed contour within outline_tolerance_px, without its closing point
};
/// Both in one simplification pass (simplifyPixelChainAt: the larger tolerance goes on from where
/// the smaller stopped); the outline only when outline_tolerance_px is given. An empty contour: both empty.
ContourPolygons contourPolygons(const std::vector<Vec2>& contour, double lines_tolerance_px,
                                std::optional<double> outline_tolerance_px, bool reference);

/// The edges of `polygon` (closed, image pixels) as lines, the second half of fitLines: edges shorter
/// than options.min_length_px dropped, frame edges marked, ground coordinates from `camera`.
std::vector<DetectedLine> polygonLines(const std::vector<Vec2>& polygon, const Camera& camera, const Image& valid,
                                       const LineOptions& options = {});

/// Labels the lines that are not frame edges with the best-matching predicted interest segment.
void labelLines(std::vector<DetectedLine>& lines, const PredictedObject& prediction, const LineOptions& options = {});

}  // namespace mapnav
