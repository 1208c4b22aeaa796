// The cluster-perceptron's options (the finder's table and the pipeline's, which share the finder's
// rows and so their rules; the road model's names). See cluster_perceptron.h.
#include <string>

#include "mapnav/core/error.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav {

namespace {

/// The finder's rows before the road model (clustering, perceptron, Hough, bootstrap trapezoid), onto
/// the table of the finder's options or of a struct made of them.
template <class T>
void addTrainingRows(OptionTable<T>& table) {
  using O = ClusterPerceptronOptions;
  table.field("clusters", &O::clusters, inRange(1, 30), "colour clusters (competitive learning units), 1..30")
      .field("seed", &O::seed, inRange(0, 1e15), "seed of the random initial cluster means")
      .field("max_cluster_iterations", &O::max_cluster_iterations, inRange(1, 1000), "clustering iterations at most")
      .field("cluster_slope_threshold", &O::cluster_slope_threshold, inRange(0, 1e9),
             "clustering stops when every band's mean squared reconstruction error changes by less than this "
             "(levels^2)")
      .field("max_perceptron_iterations", &O::max_perceptron_iterations, inRange(1, 1e6),
             "perceptron LMS iterations at most")
      .field("perceptron_rate", &O::perceptron_rate, aboveUpTo(0, 100), "perceptron LMS learning rate")
      .field("perceptron_tolerance", &O::perceptron_tolerance, inRange(0, 1),
             "perceptron training stops when the mean error changes by less")
      .field("train_stride", &O::train_stride, inRange(1, 64), "training uses every n-th pixel in each direction")
      .field("block_size", &O::block_size, inRange(1, 256), "side of a road-certainty block, pixels")
      .field("max_shift_blocks", &O::max_shift_blocks, inRange(0, 1024),
             "Hough: largest shift of the bottom road row, blocks")
      .field("trapezoid_top", &O::trapezoid_top, OptionRule{.min = 0, .max = 1, .max_open = true},
             "default bootstrap trapezoid (no predicted road): top row, fraction of the height")
      .field("trapezoid_top_width", &O::trapezoid_top_width, aboveUpTo(0, 10),
             "default trapezoid: top width, fraction of the image width")
      .field("trapezoid_bottom_width", &O::trapezoid_bottom_width, aboveUpTo(0, 10),
             "default trapezoid: bottom width, fraction of the image width");
}

/// The finder's rows after the road model (the arc model's, the adaptive clusters', the colour's, the
/// non-road gate's, the runtime's), as addTrainingRows.
template <class T>
void addRuntimeRows(OptionTable<T>& table) {
  using O = ClusterPerceptronOptions;
  table.field("max_curvature", &O::max_curvature, aboveUpTo(0, 1), "arc model: largest curvature searched, 1/m")
      .field("curvature_steps", &O::curvature_steps, inRange(1, 100),
             "arc model: curvatures tried on each side of 0 before refining")
      .field("subpixel_edges", &O::subpixel_edges,
             "arc model: each road edge placed within its pair of pixels by their colours (for cameras that "
             "integrate over the pixel)")
      .field("adaptive", &O::adaptive,
             "beyond the paper (9): add clusters for new colours, move them and retrain the perceptron when a "
             "frame's reconstruction error exceeds adaptive_error_ratio x the recent frames' median, "
             "bootstrapped from the last trusted road")
      .field("adaptive_error_ratio", &O::adaptive_error_ratio, OptionRule{.min = 1, .max = 1e6, .min_open = true},
             "adaptive: retrain above this multiple of the recent frames' median error")
      .field("adaptive_stride", &O::adaptive_stride, inRange(1, 64),
             "adaptive: the reconstruction error uses every n-th pixel each way")
      .field("adaptive_window", &O::adaptive_window, inRange(1, 1000),
             "adaptive: the reference is the median error of this many recent frames")
      .field("adaptive_max_clusters", &O::adaptive_max_clusters, inRange(1, 30), "adaptive: clusters at most after additions")
      .field("refine_edges", &O::refine_edges,
             "beyond the paper: refine the Hough centre line to the pixel from the road edges (robust fit)")
      .field("raw_rgb", &O::raw_rgb,
             "beyond the paper (9): the perceptron's inputs are the pixel's R, G, B instead of the clusters' "
             "winner code")
      .field("normalized_color", &O::normalized_color,
             "beyond the paper (Wallace et al. 1985, 3.4.3): clusters and perceptron see (R, G, B) / (R + G + "
             "B), which a shadow (C1 = k C2) does not change, so that shaded grass is not taken for asphalt; "
             "brightness is lost")
      .field("log_color", &O::log_color,
             "beyond the paper: clusters and perceptron see each channel as 255 ln(c + 1) / ln 256, where a "
             "shadow moves every colour by the same step along the grey axis; brightness is kept; "
             "normalized_color replaces it when both are set; false = (R, G, B) (the paper)")
      .field("balance_classes", &O::balance_classes,
             "beyond the paper: the bootstrap weighs the road (inside the outline) and the rest equally, for "
             "frames where the road is a small part")
      .field("nonroad_gate_sigma", &O::nonroad_gate_sigma, inRange(0, 1e6),
             "beyond the paper: the bootstrap trains \"not road\" only on pixels outside the outline whose colour "
             "is more than this many sigma (Mahalanobis) from the outline's, where the paper's bootstrap cannot "
             "separate (nonroad_gate_below); 0 = never (the paper)")
      .field("nonroad_gate_below", &O::nonroad_gate_below, inRange(0, 1),
             "beyond the paper: the non-road gate is used only when the paper's bootstrap (every pixel outside "
             "the outline not road) leaves less than this fraction of the outline road")
      .field("threads", &O::threads, inRange(0, 256), "runtime threads (0 = every core); the answer does not depend on it")
      .field("fast", &O::fast,
             "runtime through a 32x32x32 colour lookup table (exact: boundary cells are classified per pixel); "
             "false = per-pixel reference path")
      .field("min_road_fraction", &O::min_road_fraction, inRange(0, 1),
             "fewer road pixels than this fraction of the frame: Failed")
      .field("prior_px", &O::prior_px, inRange(0, 1e6),
             "beyond the paper: the Hough and the edge consensus keep to centre lines whose columns on the top "
             "and bottom road rows are within this many pixels of the predicted road's centre line (the middle "
             "of the prediction's road region, row by row); 0 = the whole image (the paper)");
}

}  // namespace

const OptionTable<ClusterPerceptronOptions>& clusterPerceptronOptionTable() {
  using O = ClusterPerceptronOptions;
  static const OptionTable<O> table = [] {
    OptionTable<O> t("ClusterPerceptronOptions");
    addTrainingRows(t);
    t.choice("road_model", &O::road_model, {{RoadModel::Line, "line"}, {RoadModel::Arc, "arc"}},
             "the Hough's road model: \"line\" (the paper's straight trapezoid) or \"arc\" (9: ground arcs, so that "
             "curves are not cut; needs setCamera())");
    addRuntimeRows(t);
    t.field("carry_frames", &O::carry_frames, inRange(0, 64),
            "arc model: the ground fit also uses the road edges of the fits of this many frames before, moved by "
            "advance(); 0 = each frame alone (the paper)");
    return t;
  }();
  return table;
}

void ClusterPerceptronOptions::validate() const { clusterPerceptronOptionTable().validate(*this); }

const OptionTable<ClusterPerceptronPipelineOptions>& clusterPerceptronPipelineOptionTable() {
  using O = ClusterPerceptronPipelineOptions;
  static const OptionTable<O> table = [] {
    OptionTable<O> t("ClusterPerceptronPipelineOptions");
    addTrainingRows(t);
    t.computed(
        "arc", [](const O& o) { return o.road_model == RoadModel::Arc; },
        [](O& o, bool arc) { o.road_model = arc ? RoadModel::Arc : RoadModel::Line; },
        "beyond the paper (9): the Hough searches ground arcs y = y0 + theta x + kappa x^2 / 2 too, so that "
        "curves are not cut");
    addRuntimeRows(t);
    t.field("grey_features", &O::grey_features,
            "beyond the paper: a grey frame (R = G = B everywhere) is clustered on (local mean, 4 x mean "
            "|Laplacian|, 4 x local standard deviation) instead of (R, G, B), so that texture can separate "
            "asphalt from grass and paving; colour frames are not affected")
        .field("texture_window", &O::texture_window, oddIn(inRange(3, 63)),
               "grey_features: side of the box of the local mean, Laplacian and deviation, pixels (odd)")
        .field("grey_balance_classes", &O::grey_balance_classes,
               "beyond the paper: a grey frame's perceptron is trained with balance_classes (the non-road gate "
               "cannot part grey textures); colour frames keep balance_classes as set")
        .field("retrain_each_frame", &O::retrain_each_frame,
               "beyond the paper: every frame clusters its colours and retrains the perceptron on its own bootstrap "
               "(the prediction, else the trapezoid); false = train on the first frame and freeze (the paper), "
               "except after a training under the non-road gate, which is redone on every frame")
        .field("chord_tolerance_m", &O::chord_tolerance_m, above(0),
               "arc model: the centre line reported is the chord of the curve's near part within this of the "
               "curve (the Map takes a centre line for straight), m")
        .field("min_normalised_separation", &O::min_normalised_separation, atLeast(0),
               "with normalized_color: a training whose prediction puts a shoulder within this distance of the "
               "road's colour in normalised colour (255 (R, G, B) / (R + G + B)) is done in log colour instead "
               "(gravel beside asphalt: 11; dirt 37, grass 55); 0: never")
        .field("retrain_on_failure", &O::retrain_on_failure,
               "beyond the paper: a frame the model of an earlier frame fails on is trained on (bootstrapped from "
               "the prediction) and tried again instead of failing")
        .field("retrain_on_new_surface", &O::retrain_on_new_surface,
               "beyond the paper: train again on the first frame whose prediction names a surface (the road's or "
               "a shoulder's beside an edge in view) the last training's frame did not: the surroundings changed "
               "(park_loop's dirt shoulder after R1's grass)")
        .field("log_color_when_gated", &O::log_color_when_gated,
               "beyond the paper: when the non-road gate was needed (the paper's bootstrap could not part the road "
               "from the rest: a street, its road and pavements running on beyond the outline in sun and shade), "
               "cluster and train again in log colour (log_color), where a shadow is one step along the grey axis")
        .field("smooth_px", &O::smooth_px, inRange(0, 64),
               "beyond the paper: the road region and confidence come from the per-pixel certainty averaged over "
               "a (2 r + 1)^2 box, so that markings and speckle do not cut the road")
        .preset("park-shadows", R"({"arc": true, "normalized_color": true, "clusters": 8})",
                "park paths with bends and tree shadows: the arc model, so that bends are not cut, in normalised "
                "colour, which a shadow does not change, with the 8 clusters that normalised colour needs to part "
                "grass, dirt and asphalt (5 took park_loop's dirt shoulder for road)");
    return t;
  }();
  return table;
}

void ClusterPerceptronPipelineOptions::validate() const {
  clusterPerceptronPipelineOptionTable().validate(*this);
  // The finder's own table for carry_frames, which the pipeline does not take (the rows the two
  // tables share hold here already).
  clusterPerceptronOptionTable().validate(*this);
}

std::string toString(RoadModel model) { return model == RoadModel::Arc ? "arc" : "line"; }

RoadModel roadModelFromString(const std::string& text) {
  if (text == "line") return RoadModel::Line;
  if (text == "arc") return RoadModel::Arc;
  throw InvalidInput("unknown road model \"" + text + "\" (expected line or arc)");
}

}  // namespace mapnav
