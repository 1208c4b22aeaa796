// The cluster-perceptron's runtime (Jochem & Baluja 1993 §5-6): find() runs a frame's steps, every
// pixel classified and its road certainty summed per block (classifyFrame(),
// cluster_perceptron_classify.cpp), the Hough over (top-row intercept × angle × curvature step) with
// its sub-block refinement (houghCentre(), cluster_perceptron_hough.cpp), then the edge refinement of
// the centre model it found (cluster_perceptron_edges.cpp, cluster_perceptron_arc.cpp). See
// cluster_perceptron.h.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cluster_perceptron_internal.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav {

namespace {

/// Per-thread scratch of find(), reused from frame to frame so that a frame costs no allocation.
FrameScratch& scratch() {
  thread_local FrameScratch s;
  return s;
}

/// The road mask of the certainties: 255 where the certainty is above 127.
Image roadMask(const std::vector<std::uint8_t>& cert, int width, int height) {
  Image mask(width, height, 1);
  for (std::size_t i = 0; i < cert.size(); ++i) mask.data[i] = cert[i] > 127 ? 255 : 0;
  return mask;
}

/// The centre line sampled every block row from v_top down to the bottom row: the image model's, or
/// the arc model's ground circle taken to the image where it has not turned back.
std::vector<Vec2> centreCurve(const CentreModel& model, const std::optional<GroundArc>& ground, const RowGeometry& rows,
                              int v_top, int height, int bs) {
  std::vector<Vec2> curve;
  for (int v = v_top;; v = std::min(height - 1, v + bs)) {
    if (!ground) {
      curve.emplace_back(model.u(v), v);
    } else if (const double y = ground->at(rows.x[v]); std::isfinite(y)) {
      curve.emplace_back(rows.a[v] + rows.b[v] * y, v);
    }
    if (v >= height - 1) break;
  }
  return curve;
}

RoadFinding failed(RoadFinding res, const char* reason) {
  res.reason = reason;
  return res;
}

}  // namespace

RoadFinding ClusterPerceptron::find(const std::uint8_t* rgb, int width, int height, bool want_mask,
                                    const std::optional<Segment2>& prior) const {
  RoadFinding res;
  if (!trained_) return failed(std::move(res), "not trained");
  if (static_cast<int>(row_widths_.size()) != height)
    return failed(std::move(res), "frame height differs from the bootstrap frame's");
  // §6: every pixel's road certainty, summed per block.
  FrameScratch& scr = scratch();
  const long long road_px =
      classifyFrame(*this, LutView{lut_.data(), sub_offset_.data(), sub_.data()}, rgb, width, height, scr);
  if (want_mask) {
    res.mask = roadMask(scr.cert, width, height);
    res.certainty = Image(width, height, 1);
    std::copy(scr.cert.begin(), scr.cert.end(), res.certainty.data.begin());
  }
  if (static_cast<double>(road_px) < opt_.min_road_fraction * width * height)
    return failed(std::move(res), "no road-coloured pixels");
  // §5: the Hough over the road block rows.
  const RowGeometry geo{row_x_, row_a_, row_b_};
  HoughAnswer hough = houghCentre(scr.bsum, row_widths_, geo, width, height, opt_, prior);
  if (hough.failure != nullptr) return failed(std::move(res), hough.failure);
  res.intercept_col = hough.intercept_col;
  res.shift = hough.shift;
  res.confidence = hough.confidence;
  CentreModel& model = hough.model;
  const PriorWindow& window = hough.window;
  const bool arc = opt_.road_model == RoadModel::Arc;
  const int bs = opt_.block_size;

  // Beyond the paper: the Hough answer is good to about a block; the road's edges put it to the pixel
  // (the image model, or the arc model's circle on the ground).
  const int v_top = hough.v_top;
  std::optional<GroundArc> ground;
  if (opt_.refine_edges) {
    const int degree = arc ? 2 : 1;
    model = edgeConsensusModel(scr.cert.data(), width, height, v_top, row_widths_, model, degree, opt_,
                               [&](const CentreModel& m) { return window.admits(m.u(m.v0), m.u(m.v1)); });
    if (arc) ground = refineOnGround(scr.cert.data(), rgb, width, height, v_top, model, geo, row_widths_, opt_, carried_, res);
    if (!ground) fitModelToEdges(scr.cert.data(), width, height, v_top, row_widths_, degree, opt_.max_curvature, model, res);
  }
  // No ground fit: the image fit stands, unless its centre line, taken to the ground, leaves the
  // vehicle off the road: then the road-coloured area holds no road the vehicle could be on
  // (shoulders classed as road, no edge of the road in view), and the frame fails rather than steer by it.
  if (arc && !ground && leavesTheVehicleOffRoad(model, geo, row_widths_, v_top, height, opt_.max_curvature))
    return failed(std::move(res), "arc model: no centre line within half the road's width of the vehicle");
  res.centerline_curve = centreCurve(model, ground, geo, v_top, height, bs);
  if (res.centerline_curve.size() < 2) return failed(std::move(res), "arc model: the circle turns back above the bottom rows");
  res.centerline_image = Segment2{res.centerline_curve.front(), res.centerline_curve.back()};
  res.curvature = ground ? ground->k : arc ? model.p[2] : 0.0;
  res.ok = true;
  return res;
}

}  // namespace mapnav
