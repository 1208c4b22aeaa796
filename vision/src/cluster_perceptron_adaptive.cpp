// The cluster-perceptron's adaptive cluster management (beyond the paper, §9): track() watches each
// frame's reconstruction error against the recent frames' and, when the scene has changed, adds
// clusters for new colours, moves them all and retrains the perceptron on the last trusted road. See
// cluster_perceptron.h.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav {

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

int ClusterPerceptron::adaptClusters(const std::uint8_t* rgb, int width, int height, double threshold) {
  // A new colour: the mean of the 2 % of pixels the clusters explain worst, when it is itself
  // unexplained (its mean squared error per band to the nearest cluster above the threshold). Added
  // as a cluster, one at a time, before the clusters move, so that no cluster has to leave its own
  // colour for it (a colour nearest the road's cluster would share its output).
  int added = 0;
  while (static_cast<int>(means_.size()) < opt_.adaptive_max_clusters) {
    std::vector<std::pair<double, Vec3>> px;
    for (int v = 0; v < height; v += opt_.adaptive_stride)
      for (int u = 0; u < width; u += opt_.adaptive_stride) {
        const std::uint8_t* p = rgb + 3 * (static_cast<std::size_t>(v) * width + u);
        const Vec3 f = feature(p[0], p[1], p[2]);
        px.emplace_back((f - means_[static_cast<std::size_t>(nearest(f))]).squaredNorm(), f);
      }
    const std::size_t worst = std::max<std::size_t>(1, px.size() / 50);
    std::nth_element(px.begin(), px.begin() + static_cast<std::ptrdiff_t>(worst), px.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    Vec3 candidate = Vec3::Zero();
    for (std::size_t i = 0; i < worst; ++i) candidate += px[i].second / static_cast<double>(worst);
    const Vec3& near = means_[static_cast<std::size_t>(nearest(candidate))];
    if ((candidate - near).squaredNorm() / 3.0 <= threshold) break;
    means_.push_back(candidate);
    ++added;
  }
  clusterFrom(rgb, width, height);  // all moved from where they are to this frame's colours
  return added;
}

}  // namespace mapnav
