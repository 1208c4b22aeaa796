// The cluster-perceptron's construction and runtime (Jochem & Baluja 1993 §5-6): the members that
// set it up for frames (the options, the camera's row tables) and those that run one, keeping what
// goes from frame to frame. find() runs a frame's steps, every pixel classified and its road
// certainty summed per block (classifyFrame(), cluster_perceptron_classify.cpp), the Hough over
// (top-row intercept × angle × curvature step) with its sub-block refinement (houghCentre(),
// cluster_perceptron_hough.cpp), then the edge refinement of the centre model it found
// (cluster_perceptron_edges.cpp, cluster_perceptron_arc.cpp); track() adds the adaptive cluster
// management (§9) around it; advance() carries the ground edges to the next frame. The training
// members are in cluster_perceptron_training.cpp. See cluster_perceptron.h.
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

ClusterPerceptron::ClusterPerceptron(ClusterPerceptronOptions options) : opt_(std::move(options)) { opt_.validate(); }

void ClusterPerceptron::setThreads(int threads) {
  ClusterPerceptronOptions o = opt_;
  o.threads = threads;
  o.validate();
  opt_ = o;
}

void ClusterPerceptron::setCamera(const Camera& camera) {
  RowTables t = rowTablesOf(camera);
  row_x_ = std::move(t.x);
  row_a_ = std::move(t.a);
  row_b_ = std::move(t.b);
}

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
  const long long road_px = opt_.fast ? classifyFrame(*this, lutFor(rgb, width, height).view, rgb, width, height, scr)
                                      : classifyFrame(*this, LutView{}, rgb, width, height, scr);
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

RoadFinding ClusterPerceptron::track(const std::uint8_t* rgb, int width, int height, bool want_mask,
                                     const std::optional<Segment2>& prior) {
  if (!opt_.adaptive) return find(rgb, width, height, want_mask, prior);
  const double err = reconstructionError(rgb, width, height, opt_.adaptive_stride);
  // The reference: the median error of the training frame and the recent frames that fitted. Frames
  // differ from the one the clusters were trained on (another mix of surfaces and shadows), so the
  // typical runtime error, not the training error, is what a changed world stands out against.
  if (recent_errors_.empty()) recent_errors_.push_back(train_error_);
  std::vector<double> sorted = recent_errors_;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double reference = sorted[sorted.size() / 2];
  const bool fits = err <= opt_.adaptive_error_ratio * reference;
  bool retrained = false;
  int added = 0;
  if (!fits && trained_ && !trusted_curve_.empty() && static_cast<int>(row_widths_.size()) == height) {
    // §9: the clusters no longer describe the scene. Adapt them to this frame's colours and retrain
    // the perceptron on the road where it was last found.
    const Image outline = fillPolygonMask({roadBand(trusted_curve_, row_widths_, width)}, width, height);
    added = adaptClusters(rgb, width, height, opt_.adaptive_error_ratio * reference);
    trainPerceptron(rgb, width, height, outline.data.data());
    recent_errors_.assign(1, train_error_);
    retrained = true;
  } else if (fits) {
    recent_errors_.push_back(err);
    if (static_cast<int>(recent_errors_.size()) > opt_.adaptive_window + 1)  // + the training error
      recent_errors_.erase(recent_errors_.begin() + 1);
  }
  RoadFinding res = find(rgb, width, height, want_mask, prior);
  res.reconstruction_error = err;
  res.training_error = reference;
  res.retrained = retrained;
  res.clusters_added = added;
  if (res.ok && (fits || retrained)) trusted_curve_ = res.centerline_curve;
  return res;
}

void ClusterPerceptron::advance(const RoadFinding& last, const Pose2& motion) {
  if (opt_.carry_frames == 0) return;
  carried_.push_back(last.ground_edges);
  if (static_cast<int>(carried_.size()) > opt_.carry_frames) carried_.erase(carried_.begin());
  for (auto& frame : carried_) {
    for (RoadEdgePoint& e : frame) e.p = motion.inverseTransform(e.p);
    std::erase_if(frame, [](const RoadEdgePoint& e) { return !(e.p.x() >= 0.0); });
  }
}

}  // namespace mapnav
