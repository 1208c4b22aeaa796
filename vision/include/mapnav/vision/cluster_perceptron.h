#pragma once
// The park-mode road finder of Jochem & Baluja 1993 ("A massively parallel road follower"):
//   3. colour clustering by competitive learning (isodata, learning rate 1, empty-cluster heuristic,
//      stop on the slope of the per-band reconstruction error),
//   4. one tanh perceptron over the clusters' winner-take-all code (+1 winner, -1 others) and a bias,
//      LMS averaged over all pixels, bootstrapped from a trapezoid road outline in the first frame,
//   5. road finder: per-block road certainty (0..255), per-row road width from the bootstrap
//      trapezoid, per-row horizontal summation kernel, Hough over (top-row intercept column × angle)
//      by shifting rows and summing columns,
//   6. runtime: clusters and perceptron frozen; every frame is classified and its centre line found.
// The fast runtime path collapses clusters + perceptron into a 32×32×32 colour lookup table; the
// reference path classifies every pixel by float distance and std::tanh.
#include <cstdint>
#include <memory>
#include <string>
#include <optional>
#include <vector>

#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/sim/image.h"
#include "mapnav/vision_iface/predicted_object.h"

namespace mapnav {

/// The road model of the Hough (§5): the paper's straight trapezoid, or (§9, "beyond") one that
/// bends, so that curves are not cut: the centre line u(t) = a + b t + c t² in the image.
/// EXPERIMENTAL: the image quadratic follows a bend where its edges are seen but extrapolates badly
/// where the road fills the image (see the disabled test ArcModelFollowsCurves); a ground-plane
/// arc is the planned replacement.
enum class RoadModel { Line, Arc };
std::string toString(RoadModel model);
/// "line" or "arc"; throws InvalidInput otherwise.
RoadModel roadModelFromString(const std::string& text);

struct ClusterPerceptronOptions {
  int clusters = 5;                     ///< colour clusters, 1..30 (paper: 5)
  std::uint64_t seed = 1;               ///< random initial cluster means in the RGB cube
  int max_cluster_iterations = 30;      ///< clustering stops after this many iterations at the latest
  /// Clustering stops when every band's mean squared reconstruction error changed by less than this
  /// (levels²) since the previous iteration.
  double cluster_slope_threshold = 0.5;
  int max_perceptron_iterations = 2000;  ///< LMS iterations at most (each costs O(clusters²))
  double perceptron_rate = 0.3;         ///< LMS learning rate (average adjustment × rate)
  /// Perceptron training stops when the mean |target − output| changed by less than this.
  double perceptron_tolerance = 1e-6;
  /// Training uses every `train_stride`-th pixel in each direction (1 = all, as in the paper).
  int train_stride = 1;
  int block_size = 8;                   ///< side of a road-certainty block, pixels (the paper's processor)
  /// Largest Hough shift: the bottom row moves up to this many blocks east and west.
  int max_shift_blocks = 32;
  /// Default trapezoid when the prediction has no road region: top row (fraction of the height),
  /// top and bottom widths (fractions of the image width, may exceed 1), centred.
  double trapezoid_top = 0.0;
  double trapezoid_top_width = 0.45;
  double trapezoid_bottom_width = 1.6;
  RoadModel road_model = RoadModel::Line;  ///< straight (the paper) or arc (bends)
  /// Arc model: the largest bend searched, blocks at mid-height of the road rows.
  int max_bend_blocks = 8;
  /// Beyond the paper: refine the Hough line to the pixel from the road's edges (robust fit).
  bool refine_edges = true;
  /// Beyond the paper (§9): the perceptron's inputs are the pixel's R, G, B (scaled to [-1, 1])
  /// instead of the clusters' winner-take-all code. The clusters are still trained (reconstruction).
  bool raw_rgb = false;
  bool fast = true;                     ///< colour lookup table (true) or per-pixel reference path
  /// Runtime threads: bands of rows classified in parallel (1 = this thread only, 0 = every core).
  /// The answer does not depend on it.
  int threads = 1;
  double min_road_fraction = 0.02;      ///< fewer road pixels than this fraction: Failed
  void validate() const;
};

/// The result of one runtime frame.
struct RoadFinding {
  bool ok = false;
  std::string reason;
  /// The centre line in the image (a: top of the road rows, b: bottom of the image), pixels.
  Segment2 centerline_image;
  double intercept_col = 0;  ///< Hough: column where the centre line meets the top road row, blocks
  int shift = 0;             ///< Hough: columns the bottom row was shifted (east positive), blocks
  double confidence = 0;     ///< 0..1
  /// The centre line sampled every block row from the top road row down (the arc model's curve;
  /// on the line model, points of the line).
  std::vector<Vec2> centerline_curve;
  double bend = 0;           ///< arc model: the curve's offset from its chord at mid-height, pixels
  bool refined = false;      ///< the edge refinement found enough edge rows and moved the line
  int edge_rows = 0;         ///< rows with an edge that the refinement used
  Image mask;                ///< 1 channel, 255 = perceptron output > 0
};

class ClusterPerceptron {
 public:
  explicit ClusterPerceptron(ClusterPerceptronOptions options = {});
  const ClusterPerceptronOptions& options() const { return opt_; }
  void setFast(bool fast) { opt_.fast = fast; }
  /// Runtime threads (0 = every core); the answer does not depend on it.
  void setThreads(int threads);

  /// §3: clusters the colours of an RGB frame. Returns the mean squared reconstruction error per
  /// band (R, G, B) after each iteration; the first entry is that of the random initial means.
  std::vector<Vec3> trainClusters(const std::uint8_t* rgb, int width, int height);
  /// §4: trains the perceptron; `road` is 1 channel, non-zero = road (the bootstrap outline).
  /// Returns the mean |target − output| after each iteration.
  std::vector<double> trainPerceptron(const std::uint8_t* rgb, int width, int height, const std::uint8_t* road);
  /// §5 bootstrap: per image row, the road's width in pixels (0 above the road) from a 1-channel
  /// outline mask of the road, extrapolated linearly where the outline meets the image sides
  /// (see trapezoidRowWidths()).
  void setRowWidths(std::vector<double> widths);
  const std::vector<double>& rowWidths() const { return row_widths_; }

  /// §3.2: every pixel replaced by its cluster's mean (debugging).
  Image reconstruct(const std::uint8_t* rgb, int width, int height) const;
  const std::vector<Vec3>& means() const { return means_; }
  /// Per cluster, then the bias; with raw_rgb: R, G, B, bias.
  const std::vector<double>& weights() const { return weights_; }
  bool trained() const { return trained_; }

  /// Perceptron output in [-1, 1] of one colour, reference arithmetic.
  double outputReference(std::uint8_t r, std::uint8_t g, std::uint8_t b) const;
  /// §6: classifies a frame and finds the centre line (fast or reference path per options).
  RoadFinding find(const std::uint8_t* rgb, int width, int height, bool want_mask = true) const;

 private:
  int nearest(float r, float g, float b) const;
  std::vector<double> trainRgbPerceptron(const std::uint8_t* rgb, int width, int height, const std::uint8_t* road);
  void buildLut();
  ClusterPerceptronOptions opt_;
  std::vector<Vec3> means_;
  std::vector<double> weights_;
  std::vector<double> row_widths_;
  std::vector<std::uint8_t> lut_;  // 32³ cells of 8³ colours: road certainty 0..240, 255 = ambiguous
  std::vector<std::uint32_t> sub_offset_;  // ambiguous cell → its 8³ table in sub_
  std::vector<std::uint8_t> sub_;          // exact certainties of the ambiguous cells' colours
  bool trained_ = false;
};

/// Per-row road widths (pixels) of a 1-channel road outline mask: the extent of each row inside it, fitted by a line in v (a flat road of constant width) over the rows where the outline
/// does not touch the image sides, and extrapolated to every row below its top.
std::vector<double> trapezoidRowWidths(const Image& outline_mask);
/// A 1-channel mask of the polygons (pixels), filled.
Image fillPolygonMask(const std::vector<Polygon2>& polygons, int width, int height);
/// The road outline of a prediction in the image: its regions' ground polygons projected (edges
/// densified), filled; empty when the prediction has no region in view.
Image predictedRoadMask(const PredictedObject& prediction, const Camera& camera);

class VisionPipeline;
struct OptionInfo;
/// The "cluster-perceptron" pipeline and its documented options (registered by
/// registerBuiltinPipelines()).
std::unique_ptr<VisionPipeline> createClusterPerceptronPipeline();
std::vector<OptionInfo> clusterPerceptronOptionInfos();

}  // namespace mapnav
