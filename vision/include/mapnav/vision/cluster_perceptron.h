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
#include <functional>
#include <memory>
#include <string>
#include <optional>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/image/image.h"
#include "mapnav/tokens/predicted_object.h"

namespace mapnav {

/// The road model of the Hough (§5): the paper's straight trapezoid, or (§9, "beyond": "a road model
/// based on the turn radius of the road ahead") an arc on the ground, so that curves are not cut:
/// the centre line's lateral offset y(x) = y0 + θ·x + κ·x²/2 in the vehicle frame (x ahead), κ the
/// curvature (1/m, left positive). A pin-hole over flat ground sees one ground distance x_r in each
/// image row r and maps lateral offsets to columns affinely there, u = a_r + b_r·y(x_r), so for a
/// fixed κ the centre line's column is an image line plus a known per-row offset: the Hough over
/// (intercept, angle) runs for each κ of a grid and the best is kept (the per-row x_r and b_r come
/// from the camera: ClusterPerceptron::setCamera()). The edge refinement then fits the exact circle
/// to the road's edges on the ground (the parabola is its small-angle form, and cuts 15 m bends by
/// decimetres at 8 m), and keeps the straight line instead where the curvature does not pay for its
/// parameter (BIC), so straight paths get the straight answer. Every fit must keep the vehicle on the
/// road (the centre line within half the road's width of it); when none does, find() fails.
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
  RoadModel road_model = RoadModel::Line;  ///< straight (the paper) or arc (bends; needs setCamera())
  /// Arc model: the largest curvature searched, 1/m (the park's tightest bends have a 15 m radius).
  double max_curvature = 0.07;
  /// Arc model: the Hough tries the curvatures k·max_curvature/curvature_steps, |k| ≤ curvature_steps,
  /// then refines the best continuously.
  int curvature_steps = 10;
  /// Beyond the paper (§9, adaptive cluster management): track() watches each frame's reconstruction
  /// error (the clusters' mean squared error per band, on every adaptive_stride-th pixel each way)
  /// and, when it exceeds adaptive_error_ratio × the median error of the recent frames (the last
  /// adaptive_window that fitted, and the training error), adapts the clusters to that frame: adds
  /// a cluster at the mean colour of the 2 % of pixels they explain worst for as long as that colour
  /// is itself unexplained (its error above the same threshold: a new surface in view), up to
  /// adaptive_max_clusters, then moves them all (isodata from where they are) and retrains the
  /// perceptron there, bootstrapped from the last road it trusted.
  bool adaptive = false;
  double adaptive_error_ratio = 3.0;   ///< > 1
  int adaptive_stride = 4;             ///< in [1, 64]
  int adaptive_window = 9;             ///< recent frames whose median error is the reference, in [1, 1000]
  int adaptive_max_clusters = 30;      ///< in [1, 30]
  /// Beyond the paper: refine the Hough line to the pixel from the road's edges (robust fit).
  bool refine_edges = true;
  /// Beyond the paper (§9): the perceptron's inputs are the pixel's R, G, B (scaled to [-1, 1])
  /// instead of the clusters' winner-take-all code. The clusters are still trained (reconstruction).
  bool raw_rgb = false;
  /// Beyond the paper, from Wallace et al. 1985 §3.4.3: the clusters and the perceptron see every
  /// colour normalised, (R, G, B) · 255 / (R + G + B), instead of (R, G, B). A shadow scales a colour
  /// by k (C1 = k·C2), which the normalised colour does not see: shaded grass stays green instead of
  /// joining the dark asphalt's cluster. Brightness is lost with it (black counts as grey), so
  /// surfaces that differ in brightness alone (gravel and asphalt) merge. The lookup table stays exact:
  /// the pixels nearer one normalised mean than another form a half-space through black in RGB.
  /// Use it with about 8 clusters: the paper's 5 are too few to part the grass, dirt and asphalt
  /// chromaticities (docs/measurements.md). The clusters' means, reconstruction errors and raw_rgb's
  /// inputs are then in normalised levels.
  bool normalized_color = false;
  /// Beyond the paper: the clusters and the perceptron see every channel in log colour,
  /// 255 ln(c + 1) / ln 256 (0..255), instead of (R, G, B). A shadow scales a colour by k, which in
  /// log colour moves every channel by the same 255 ln k / ln 256 wherever the colour is, so the
  /// clusters part surfaces by their colours' ratios more than by their light. Brightness is kept,
  /// unlike normalized_color, which replaces it when both are set. The clusters' means,
  /// reconstruction errors and raw_rgb's inputs are then in log levels; the lookup table stays exact.
  /// Not the default: the log spreads dark pixels' noise over the clusters (docs/measurements.md).
  /// The pipeline uses it on streets (log_color_when_gated).
  bool log_color = false;
  /// Beyond the paper: the perceptron's bootstrap counts the road (inside the outline) and the rest
  /// equally, each road pixel weighted by (pixels outside) / (pixels inside). Without it a cluster is
  /// road only when most of its pixels lie inside the outline, which fails when the road is a small
  /// part of the frame (a level camera: kitti_vo_seq1's trapezoid is 8.8 % of the frame).
  bool balance_classes = false;
  /// Beyond the paper: when the paper's bootstrap cannot separate the road from the rest (below), the
  /// perceptron is trained again with "not road" only on the pixels outside the outline whose colour
  /// (the clusters' feature) lies more than this many σ (Mahalanobis, under the outline's own mean and
  /// covariance, +1 level² on the diagonal) from the road's; the pixels outside but nearer train
  /// nothing. On a real street "everything outside the outline" is mostly more road and pavement (a
  /// bootstrap trapezoid is a tenth of a CamVid photo). Default 16 σ (docs/measurements.md); 0 =
  /// never (the paper).
  double nonroad_gate_sigma = 16;
  /// The gate (nonroad_gate_sigma) is used only when the paper's bootstrap (every pixel outside the
  /// outline "not road") leaves less than this fraction of the outline's pixels road: the outside then
  /// holds the road's own colours. Where the outline is the road (a map's prediction), the colours
  /// outside it that are near the road's are the negatives the paper's bootstrap needs
  /// (docs/measurements.md). A fraction in [0, 1]; 1 = gate whenever any pixel of the outline is
  /// classed not road.
  double nonroad_gate_below = 0.5;
  bool fast = true;                     ///< colour lookup table (true) or per-pixel reference path
  /// Runtime threads: bands of rows classified in parallel (1 = this thread only, 0 = every core).
  /// The answer does not depend on it.
  int threads = 1;
  double min_road_fraction = 0.02;      ///< fewer road pixels than this fraction: Failed
  /// Beyond the paper (the runtime tracking of §6 with a prior, as the map's prediction gives Wallace
  /// et al.'s tracker its interest segments): when find() or track() is given a prior centre line
  /// and this is > 0, the Hough and the edge consensus consider only centre lines whose columns on
  /// the top and the bottom road rows lie within this many pixels of the prior's. 0 = the whole
  /// image (the paper), the default: in a mission the prediction comes from the Map's estimate, and
  /// where that is off the road by more than the window the finder cannot show it
  /// (docs/measurements.md). `mapnav log track`, whose prediction is the road the finder itself found
  /// a frame before, sets 20 px (its --prior-px; docs/kitti.md).
  double prior_px = 0;
  /// Arc model, beyond the paper (as Wallace 1985 §3.2 carries the last frame's edges into the new
  /// one with the vehicle's motion): the ground fit also uses the road edges that the fits of the
  /// last carry_frames frames used, moved by ClusterPerceptron::advance(). A frame's edges are its
  /// mask's pixel boundaries, so that one frame leaves its centre line's column at the bottom row,
  /// where the road fills the image and the circle is extrapolated from edges 5-8 m ahead, a
  /// quantisation error of pixels (RoadFinding::bottom_column_sd); edges seen from other poses fall at
  /// other sub-pixel phases, and those seen far ahead a few frames ago lie near the vehicle now. The
  /// odometry's error goes into the carried edges. 0 = each frame alone (the paper), in [0, 64].
  int carry_frames = 0;
  /// Arc model, beyond the paper: each road edge the ground fit uses is placed within the pair of
  /// pixels either side of the class change by their colours. A camera integrates light over the
  /// pixel, so the pair holds between them as much road as the edge leaves them; each pixel's share
  /// is its place on the colour line from the pure pixels beside the pair (two and three away).
  /// Without it (or where those colours differ by under 16 levels) an edge is the pixel boundary,
  /// a quantisation error of ±0.5 px. On point-sampled frames (WorldOptions::paved_edge_samples 1)
  /// the pair holds one pixel of each class and the colours add their texture's noise.
  bool subpixel_edges = false;
  /// clusterPerceptronOptionTable()'s rules. Throws InvalidInput naming the first bad field.
  void validate() const;
};
/// Its table: each option's name (the member's; road_model "line" or "arc"), rule and description.
/// The pipeline's table (clusterPerceptronPipelineOptionTable()) shares its rows, rules and all.
const OptionTable<ClusterPerceptronOptions>& clusterPerceptronOptionTable();

/// A road edge on the ground as the arc model's fit used it: vehicle frame (m, x ahead, y left), the
/// road side it bounds (+1 left, −1 right) and its image row's columns per metre of lateral offset
/// (its weight: the pixel quantisation is the same in every row, its ground size is not).
struct RoadEdgePoint {
  Vec2 p = Vec2::Zero();
  int side = 1;
  double px_per_m = 0;
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
  double curvature = 0;      ///< arc model: κ of the ground arc, 1/m (left positive); 0 on the line model
  /// track() with the adaptive option: this frame's reconstruction error (mean squared, per band,
  /// averaged over the bands), the training error it was compared with, and whether it retrained.
  double reconstruction_error = 0;
  double training_error = 0;   ///< the reference: the recent frames' median error (and the training error)
  bool retrained = false;
  int clusters_added = 0;       ///< clusters the retraining added (a new colour in view)
  bool refined = false;      ///< the edge refinement found enough edge rows and moved the line
  int edge_rows = 0;         ///< rows with an edge that the refinement used
  /// Arc model, refined: the standard error (pixels) of the centre line's column at the bottom row that
  /// the edges' pixel quantisation alone leaves (σ = 1/√12 px per edge, least squares on the edges the
  /// fit used). Where the mask shows the road's edges only far ahead it is pixels: the bottom row's
  /// column is extrapolated. 0 when not refined.
  double bottom_column_sd = 0;
  /// Arc model, refined: this frame's road edges that the ground fit used (not the carried ones).
  std::vector<RoadEdgePoint> ground_edges;
  int carried_edges = 0;     ///< arc model: of the carried edges (options().carry_frames), those the fit used
  Image mask;                ///< 1 channel, 255 = perceptron output > 0
  /// With want_mask: 1 channel, each pixel's road certainty, the perceptron's output y quantised to
  /// 16 levels 16 apart (0 = y −1, 240 = y +1; above 127 ⇔ mask).
  Image certainty;
};

struct LutTables;  // cluster_perceptron_internal.h
struct LutView;
class ChannelTables;

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
  /// §4: trains the perceptron; `road` is 1 channel, non-zero = road (the bootstrap outline). Beyond
  /// the paper, trains it again under the non-road gate where the paper's bootstrap cannot separate
  /// (options().nonroad_gate_below; nonroadGated()). Returns the mean |target − output| after each
  /// iteration of the training that stands.
  std::vector<double> trainPerceptron(const std::uint8_t* rgb, int width, int height, const std::uint8_t* road);
  /// §5 bootstrap: per image row, the road's width in pixels (0 above the road) from a 1-channel
  /// outline mask of the road, extrapolated linearly where the outline meets the image sides
  /// (see trapezoidRowWidths()).
  void setRowWidths(std::vector<double> widths);
  const std::vector<double>& rowWidths() const { return row_widths_; }
  /// The arc model's per-row geometry from the camera (the image size must match the frames'): the
  /// ground distance each row sees along the principal column and the columns per metre of lateral
  /// offset there. Exact for a pin-hole without distortion, yaw or roll (each row then sees one
  /// ground distance); an approximation for other cameras.
  void setCamera(const Camera& camera);

  /// §3.2: every pixel replaced by its cluster's mean (debugging); with normalized_color, by the
  /// mean's chromaticity at the pixel's own brightness R + G + B.
  Image reconstruct(const std::uint8_t* rgb, int width, int height) const;
  const std::vector<Vec3>& means() const { return means_; }
  /// Per cluster, then the bias; with raw_rgb: R, G, B, bias.
  const std::vector<double>& weights() const { return weights_; }
  bool trained() const { return trained_; }
  /// Whether the last trainPerceptron() used the non-road gate (options().nonroad_gate_below).
  bool nonroadGated() const { return gated_; }

  /// Perceptron output in [-1, 1] of one colour, reference arithmetic.
  double outputReference(std::uint8_t r, std::uint8_t g, std::uint8_t b) const;
  /// §6: classifies a frame and finds the centre line (fast or reference path per options). With
  /// options().prior_px > 0 and a `prior` (an image line, any two distinct rows), only near it. The
  /// fast path computes the lookup table's cells as frames first need them (the first frame after
  /// training its own, the second the rest), under a lock: calls from several threads are safe
  /// and give the same answer.
  RoadFinding find(const std::uint8_t* rgb, int width, int height, bool want_mask = true,
                   const std::optional<Segment2>& prior = std::nullopt) const;
  /// find(), and with the adaptive option the §9 cluster management: when the frame's reconstruction
  /// error exceeds adaptive_error_ratio × the recent frames' median error, moves and adds clusters
  /// (see ClusterPerceptronOptions::adaptive), retrains the perceptron on this frame from the last
  /// trusted road (the centre curve and the row widths) and finds the road again. Without the option,
  /// the same as find(). `prior` as find()'s.
  RoadFinding track(const std::uint8_t* rgb, int width, int height, bool want_mask = true,
                    const std::optional<Segment2>& prior = std::nullopt);
  /// The mean squared reconstruction error per band, averaged over the bands, on every stride-th
  /// pixel in each direction (the last clustering's is trainingError()).
  double reconstructionError(const std::uint8_t* rgb, int width, int height, int stride) const;
  double trainingError() const { return train_error_; }
  /// Arc model with options().carry_frames > 0: carries `last`'s ground edges (the frame find() or
  /// track() just returned) and the ones carried before into the next frame, `motion` being the
  /// vehicle's pose at the next frame in its frame at the last one (odometry). Edges now behind the
  /// vehicle, and frames older than carry_frames, are dropped. Does nothing with carry_frames 0.
  void advance(const RoadFinding& last, const Pose2& motion);
  /// Forgets the carried edges (a new road, a jump in the pose).
  void clearCarried() { carried_.clear(); }
  /// The carried edges, oldest frame first.
  const std::vector<std::vector<RoadEdgePoint>>& carried() const { return carried_; }

 private:
  /// The colour the clusters and the perceptron see (options().normalized_color).
  Vec3 feature(double r, double g, double b) const;
  /// The cluster whose mean is nearest a feature(), by float distance (ties: the first).
  int nearest(const Vec3& f) const;
  int nearest(double r, double g, double b) const { return nearest(feature(r, g, b)); }
  /// The current means' channel tables, where the feature is channel by channel (RGB and log
  /// colour): a colour's nearest cluster by table lookups, the same as nearest(). None in normalised colour.
  std::optional<ChannelTables> channelTables() const;
  /// The perceptron's training class of each pixel the stride samples: +1 road (inside `road`), −1 not
  /// road (outside; `gated`: and beyond options().nonroad_gate_sigma of the road's colour), 0 unused.
  std::vector<std::int8_t> trainingClasses(const std::uint8_t* rgb, int width, int height, const std::uint8_t* road,
                                           bool gated) const;
  /// One LMS training on the classes (trainingClasses()) over the clusters' code or, with raw_rgb, the
  /// colours; the mean error per iteration, and the share of the road-class pixels it calls road.
  struct Trained {
    std::vector<double> history;
    double road_share = 0;
  };
  Trained trainClusterPerceptron(const std::uint8_t* rgb, const std::vector<std::int8_t>& cls);
  Trained trainRgbPerceptron(const std::uint8_t* rgb, const std::vector<std::int8_t>& cls);
  /// The LMS loop both perceptrons share: `pass` adds one iteration's gradient (Σ (target − output)
  /// · input, over the pixels) into its argument and returns the summed absolute error; the weights
  /// (`inputs` of them, from 0) move by rate · gradient / total until the mean error has been calm for
  /// 3 iterations. Starts a new lookup table (resetLut()). Returns the mean error per iteration.
  std::vector<double> runLms(std::size_t inputs, double total, const std::function<double(std::vector<double>&)>& pass);
  /// The lookup table of the model just trained, every cell still to be computed (cluster_perceptron_lut.cpp).
  void resetLut();
  /// The table for a frame's classification: the first frame after training computes only the
  /// cells its pixels fall in (a photo's colours fill about 6 % of them), the next one every cell
  /// left, so that a sequence's frames find the table whole; `lock` holds its mutex while cells are
  /// being filled by this call's frame (released once the table is whole).
  struct LutAccess;
  LutAccess lutFor(const std::uint8_t* rgb, int width, int height) const;
  std::optional<std::uint8_t> uniformCell(LutTables& t, int r, int g, int b) const;
  void exactCell(LutTables& t, int r, int g, int b) const;
  void fillCell(LutTables& t, int cell) const;
  ClusterPerceptronOptions opt_;
  std::vector<Vec3> clusterFrom(const std::uint8_t* rgb, int width, int height);
  std::vector<Vec3> means_;
  double train_error_ = 0;
  // arc model: per image row, the ground distance (m), the column of lateral offset 0 and du/dy (px/m)
  std::vector<double> row_x_, row_a_, row_b_;
  std::vector<Vec2> trusted_curve_;    // track(): the last centre curve found under a fitting model
  std::vector<double> recent_errors_;  // track(): the training error, then the frames that fitted
  std::vector<std::vector<RoadEdgePoint>> carried_;  // advance(): earlier frames' edges, this frame's vehicle frame
  /// track()'s cluster adaptation to a frame: adds clusters for colours whose error exceeds
  /// `threshold`, then moves them all; returns the clusters added.
  int adaptClusters(const std::uint8_t* rgb, int width, int height, double threshold);
  std::vector<double> weights_;
  std::vector<double> row_widths_;
  std::shared_ptr<LutTables> lut_;  // 32³ cells of 8³ colours, filled as frames need them
  bool trained_ = false;
  bool gated_ = false;
};

/// The road band of a centre curve (image points, top to bottom): each point ± half its row's
/// width (clamped to the image's columns), right side down then left side up.
Polygon2 roadBand(const std::vector<Vec2>& centre, const std::vector<double>& row_widths, int width);
/// Per-row road widths (pixels) of a 1-channel road outline mask: the extent of each row inside it, fitted by a line in v (a flat road of constant width) over the rows where the outline
/// does not touch the image sides, and extrapolated to every row below its top.
std::vector<double> trapezoidRowWidths(const Image& outline_mask);
/// A 1-channel mask of the polygons (pixels), filled.
Image fillPolygonMask(const std::vector<Polygon2>& polygons, int width, int height);
/// The road outline of a prediction in the image: its regions' ground polygons projected (edges
/// densified), filled; empty when the prediction has no region in view.
Image predictedRoadMask(const PredictedObject& prediction, const Camera& camera);

/// Beyond the paper, for grey frames, whose colours all lie on the grey axis so that the clusters
/// cannot tell asphalt from grass or paving of the same grey: a 3-channel image that stands in for
/// R, G, B, per pixel, over the `window` × `window` box around it (clamped at the image sides):
///   0: the grey level's mean,
///   1: 4 × the mean absolute 4-neighbour Laplacian, clamped to 255 (fine grain),
///   2: 4 × the grey level's standard deviation, clamped to 255 (coarse texture: leaves, paving
///      joints, kerbs and shadow edges are high).
/// Each channel in grey levels, 0..255 (values measured on real frames: docs/measurements.md).
/// `window` is odd, in [3, 63].
Image greyTextureFeatures(const std::uint8_t* rgb, int width, int height, int window);

/// The "cluster-perceptron" pipeline's options: the road finder's (the option "arc" picks
/// RoadModel::Arc; carry_frames is not an option of the pipeline) and the grey frames' features.
struct ClusterPerceptronPipelineOptions : ClusterPerceptronOptions {
  /// Beyond the paper: a grey frame (R = G = B everywhere) is clustered on greyTextureFeatures()
  /// instead of (R, G, B), so that texture can separate asphalt from grass and paving.
  bool grey_features = true;
  int texture_window = 7;  ///< greyTextureFeatures()' window side, pixels: odd, in [3, 63]
  /// Beyond the paper: a grey frame's perceptron is trained with balance_classes. The non-road gate
  /// parts the road from the rest by the distance of their features, which a grey frame's texture
  /// features barely have, so there the gated perceptron calls the whole ground road; balanced, a
  /// cluster is road when it holds more of the outline than of the rest. Colour frames keep
  /// balance_classes as set (balanced, colour photos lose the road beyond the trapezoid;
  /// docs/measurements.md).
  bool grey_balance_classes = true;
  /// Beyond the paper: every frame clusters its own colours and retrains the perceptron on its own
  /// bootstrap (the frame's prediction, else the trapezoid). Without it the pipeline trains on the
  /// first frame and freezes (the paper's park mode), except that a perceptron the non-road gate
  /// trained (nonroad_gate_below: the paper's bootstrap could not separate; a model of that frame's
  /// colours) is trained again on every frame: on real photos the light and the surfaces change from
  /// one street to the next. Not the default because a sequence whose prediction is the last frame's
  /// road, as `mapnav log track` carries it, feeds each frame's error into the next training (the
  /// figures and the cost: docs/measurements.md).
  bool retrain_each_frame = false;
  /// Beyond the paper: train again (clusters and perceptron, bootstrapped from the prediction) on the
  /// first frame whose prediction names a surface (the road's, or a shoulder's beside an edge in view)
  /// that the frame of the last training did not: the surroundings changed, and colours the model
  /// never saw as "not road" are not to be judged by it (docs/measurements.md, park loop).
  bool retrain_on_new_surface = true;
  /// Beyond the paper: a frame that the model trained on an earlier frame fails on is trained on
  /// (bootstrapped from the prediction) and tried again, instead of failing: a halted vehicle sees the
  /// same frame again and again, and a frozen model fails it for good (park_loop's 15 m hairpin).
  bool retrain_on_failure = true;
  /// Beyond the paper: with normalized_color, a training whose prediction puts a shoulder's mean colour
  /// within this distance of the road's in normalised colour (255 (R, G, B) / (R + G + B)) is done in
  /// log colour (log_color) instead, which keeps the brightness that parts them. Normalised levels,
  /// default 16 (docs/measurements.md, park loop); 0: never.
  double min_normalised_separation = 16;
  /// Arc model: the centre line reported (DetectedObject::centerline_vehicle, which the Map takes for
  /// straight) is the chord of the curve's near part that stays within this of the curve, m (> 0).
  /// 5 cm, half the Map's centre-line sigma: on a 15 m bend a 2.4 m chord, on a 35 m one 3.7 m.
  double chord_tolerance_m = 0.05;
  /// Beyond the paper: the road region (perceptronRegion()) and the per-pixel confidence come from the
  /// certainty averaged over the (2 r + 1)² box around each pixel (smoothCertainty()), so that lane
  /// markings and speckle do not cut holes and tongues into the road (docs/measurements.md). r in
  /// pixels, in [0, 64].
  int smooth_px = 8;
  /// Beyond the paper: when the perceptron needed the non-road gate (nonroad_gate_below: the paper's
  /// bootstrap could not part the road from the rest, as on a street whose road and pavements run on
  /// beyond the outline in sun and shade), cluster and train again in log colour (log_color;
  /// docs/measurements.md). Where the bootstrap separates (a path among grass: the simulator's
  /// park, where the gate is not used) the paper's RGB stays. Colour frames only (not grey ones'
  /// texture features, not normalized_color).
  bool log_color_when_gated = true;

  /// The table's rules, then clusterPerceptronOptionTable()'s (carry_frames, not an option of the
  /// pipeline). Throws InvalidInput naming the field.
  void validate() const;
};
/// Its table: the options' names, rules and descriptions (the finder's rows as
/// clusterPerceptronOptionTable() has them, but "arc" for road_model and no carry_frames), and the
/// presets ("park-shadows").
const OptionTable<ClusterPerceptronPipelineOptions>& clusterPerceptronPipelineOptionTable();

/// The pipeline's road region (beyond the paper, whose answer is the centre line): the perceptron's
/// road pixels (certainty > 127, RoadFinding::certainty) where the camera sees the ground (`ground`,
/// 255 there), 8-connected, and of their components the one that the `seed` mask (the bootstrap
/// outline; 1 channel, non-zero inside) overlaps most: `mask` it, holes and all (255), `outline` its
/// outer boundary (pixel centres, simplified to 1 px). Nothing when no road pixel lies in the seed.
struct PerceptronRegion {
  Image mask;
  Polygon2 outline;
};
std::optional<PerceptronRegion> perceptronRegion(const Image& certainty, const Image& ground, const Image& seed);
/// The certainty image (RoadFinding::certainty) averaged over the (2 radius + 1)² box around each
/// pixel (the image's edge pixels repeated beyond it), rounded; radius 0 = unchanged.
Image smoothCertainty(const Image& certainty, int radius);
/// The per-pixel road confidence (DetectedObject::road_confidence) of a certainty image: in the
/// region's road pixels (`region` non-zero, certainty ≥ 128) 129 + round(126 (c − 128) / 112), 129..255;
/// elsewhere round(64 c / 240), 0..64 (road-coloured pixels off the region rank above the rest, below
/// everything the region holds); 0 where `ground` is 0. Monotone in the perceptron's output either way.
Image perceptronConfidence(const Image& certainty, const Image& ground, const Image& region);

class VisionPipeline;
/// The "cluster-perceptron" pipeline (registered by registerBuiltinPipelines()).
std::unique_ptr<VisionPipeline> createClusterPerceptronPipeline();

}  // namespace mapnav
