// The cluster-perceptron's options (validation, the road model's names) and its construction. See
// cluster_perceptron.h.
#include <cmath>
#include <string>
#include <utility>

#include "mapnav/core/error.h"
#include "mapnav/core/options.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav {

void ClusterPerceptronOptions::validate() const {
  const char* o = "ClusterPerceptronOptions";
  requireOption(clusters >= 1 && clusters <= 30, o, "clusters", clusters, "in [1, 30]");
  requireOption(max_cluster_iterations >= 1 && max_cluster_iterations <= 1000, o, "max_cluster_iterations",
                max_cluster_iterations, "in [1, 1000]");
  requireOption(std::isfinite(cluster_slope_threshold) && cluster_slope_threshold >= 0, o, "cluster_slope_threshold",
                cluster_slope_threshold, ">= 0");
  requireOption(max_perceptron_iterations >= 1, o, "max_perceptron_iterations", max_perceptron_iterations, ">= 1");
  requireOption(std::isfinite(perceptron_rate) && perceptron_rate > 0, o, "perceptron_rate", perceptron_rate, "> 0");
  requireOption(std::isfinite(perceptron_tolerance) && perceptron_tolerance >= 0, o, "perceptron_tolerance",
                perceptron_tolerance, ">= 0");
  requireOption(train_stride >= 1 && train_stride <= 64, o, "train_stride", train_stride, "in [1, 64]");
  requireOption(block_size >= 1 && block_size <= 256, o, "block_size", block_size, "in [1, 256]");
  requireOption(max_shift_blocks >= 0 && max_shift_blocks <= 1024, o, "max_shift_blocks", max_shift_blocks,
                "in [0, 1024]");
  requireOption(trapezoid_top >= 0 && trapezoid_top < 1, o, "trapezoid_top", trapezoid_top, "in [0, 1)");
  requireOption(trapezoid_top_width > 0 && trapezoid_top_width <= 10, o, "trapezoid_top_width", trapezoid_top_width,
                "in (0, 10]");
  requireOption(trapezoid_bottom_width > 0 && trapezoid_bottom_width <= 10, o, "trapezoid_bottom_width",
                trapezoid_bottom_width, "in (0, 10]");
  requireOption(std::isfinite(max_curvature) && max_curvature > 0 && max_curvature <= 1, o, "max_curvature",
                max_curvature, "in (0, 1] (1/m)");
  requireOption(curvature_steps >= 1 && curvature_steps <= 100, o, "curvature_steps", curvature_steps, "in [1, 100]");
  requireOption(std::isfinite(adaptive_error_ratio) && adaptive_error_ratio > 1, o, "adaptive_error_ratio",
                adaptive_error_ratio, "> 1");
  requireOption(adaptive_stride >= 1 && adaptive_stride <= 64, o, "adaptive_stride", adaptive_stride, "in [1, 64]");
  requireOption(adaptive_window >= 1 && adaptive_window <= 1000, o, "adaptive_window", adaptive_window, "in [1, 1000]");
  requireOption(adaptive_max_clusters >= 1 && adaptive_max_clusters <= 30, o, "adaptive_max_clusters",
                adaptive_max_clusters, "in [1, 30]");
  requireOption(std::isfinite(nonroad_gate_sigma) && nonroad_gate_sigma >= 0, o, "nonroad_gate_sigma",
                nonroad_gate_sigma, ">= 0");
  requireOption(nonroad_gate_below >= 0 && nonroad_gate_below <= 1, o, "nonroad_gate_below", nonroad_gate_below,
                "in [0, 1]");
  requireOption(threads >= 0 && threads <= 256, o, "threads", threads, "in [0, 256] (0 = every core)");
  requireOption(min_road_fraction >= 0 && min_road_fraction <= 1, o, "min_road_fraction", min_road_fraction,
                "in [0, 1]");
  requireOption(std::isfinite(prior_px) && prior_px >= 0, o, "prior_px", prior_px, ">= 0");
  requireOption(carry_frames >= 0 && carry_frames <= 64, o, "carry_frames", carry_frames, "in [0, 64]");
}

std::string toString(RoadModel model) { return model == RoadModel::Arc ? "arc" : "line"; }

RoadModel roadModelFromString(const std::string& text) {
  if (text == "line") return RoadModel::Line;
  if (text == "arc") return RoadModel::Arc;
  throw InvalidInput("unknown road model \"" + text + "\" (expected line or arc)");
}

ClusterPerceptron::ClusterPerceptron(ClusterPerceptronOptions options) : opt_(std::move(options)) { opt_.validate(); }

void ClusterPerceptron::setThreads(int threads) {
  ClusterPerceptronOptions o = opt_;
  o.threads = threads;
  o.validate();
  opt_ = o;
}

}  // namespace mapnav

