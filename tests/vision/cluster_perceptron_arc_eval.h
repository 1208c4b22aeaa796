#pragma once
// The arc model's evaluation against the simulator's truth, shared by the cluster-perceptron's arc
// and circle tests: the true centre curve, the found curve's column and angle errors, the best any
// circle can do, the true edges the mask shows, and the arc and straight models run side by side.
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "cluster_perceptron_test_util.h"

namespace mapnav::visiontest {

/// The road's true centre line projected into the image, from 2 m behind the pose to 16 m ahead,
/// every 5 cm (the points the camera sees).
std::vector<Vec2> truthCurve(const RoadPose& sp);

/// The column where `curve` first crosses row v (linear between its points); nullopt when it does not.
std::optional<double> columnAt(const std::vector<Vec2>& curve, double v);

/// The worst column error of a found centre curve against the truth (the road's centre line
/// projected, sampled densely), over the curve's points whose true column is in the image.
double worstCurveError(const RoadFinding& r, const RoadPose& sp);

/// The image angle error at the bottom of a found centre curve, degrees: the direction (du/dv) of its
/// last segment against the truth's (the road's centre line projected) between the same two rows.
double bottomAngleError(const RoadFinding& r, const RoadPose& sp);

/// The least worst column error any single circle on the ground can have on a frame, bounded from
/// above: the circle fitted to the true centre line (algebraic least squares, x² + y² + Dx + Ey + F =
/// 0, each point weighted by its row's pixels per metre) over the rows the image sees, evaluated like
/// a found curve (worstCurveError()) on the rows from `v_top` down, every 8. Where the road's
/// curvature changes in view (a straight running into a bend) or its polyline's 1.5 m chords leave
/// the circle by their sagitta (1.8 cm on 15 m bends: 7 px at the bottom row's 2 m), no circle
/// reaches 2 px.
double bestCircleError(const RoadPose& sp, double v_top);

/// How many rows of the mask show the road's true edges: rows where a true edge (the centre line
/// ±1.5 m, projected) is in the image and the mask changes class within 3 px of it, over both
/// edges (`shown`); in how many rows a true edge is in the image (`in_image`); and the ground distance
/// ahead of the nearest edge shown (`nearest_m`, infinite when none is).
struct EdgeRows {
  int shown = 0, in_image = 0;
  double nearest_m = std::numeric_limits<double>::infinity();
};

EdgeRows trueEdgeRowsInMask(const Image& mask, const RoadPose& sp);

/// The column error of a found centre curve at its first (top) row against the truth (the road's
/// centre line projected); 0 where the true centre is outside the image on that row (on tight bends
/// it leaves the image's side), as in worstCurveError(); 1e9 when the truth does not cross that row.
double topRowError(const RoadFinding& r, const RoadPose& sp);

/// Per frame, the worst column error of the arc model's and of the straight model's centre curve
/// (each retrained on the first frame of each road, frozen along it), the arc's curvature, its
/// angle error at the bottom row, the first row of its curve, and whether it found a centre line
/// (failed frames count as an error of 1e9 px); the top-row offsets (topRowError()) of both models
/// and the straight model's bottom angle error.
struct ArcVsLine {
  std::vector<double> arc, line, curvature, angle, v_top, top, line_top, line_angle;
  std::vector<double> bottom_sd;  // the arc model's RoadFinding::bottom_column_sd
  std::vector<EdgeRows> edge_rows;  // trueEdgeRowsInMask() of the arc model's mask
  std::vector<std::size_t> failed;
  std::vector<std::string> failed_reason;
  std::vector<double> edge_px;  // the arc fit's ground edges: each one's offset from the true edge, px
};

/// With `bootstrap_s`, each road's models are trained on the frame at that arc length of the road (on
/// its centre line, looking along it) instead of on the road's first pose.
/// `world_options`: the renderer's; `arc_options`: the arc model's (road_model set to Arc here).
ArcVsLine arcVsLine(const std::vector<RoadPose>& poses, const Map& map = parkScenery(),
                    std::optional<double> bootstrap_s = std::nullopt, const WorldOptions& world_options = parkWorld(),
                    ClusterPerceptronOptions arc_options = {});

/// The q-quantile of v: the element at q·(n − 1) of v sorted.
double quantile(std::vector<double> v, double q);

}  // namespace mapnav::visiontest
