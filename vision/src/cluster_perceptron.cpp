// Jochem & Baluja 1993: colour clustering by competitive learning, a perceptron combiner and a
// Hough road finder over (top-row intercept column × angle). See cluster_perceptron.h.
#include "mapnav/vision/cluster_perceptron.h"

#include <algorithm>
#include <functional>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <unordered_map>

#include <Eigen/Dense>
#ifdef __SSE2__
#include <emmintrin.h>
#endif
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "mapnav/core/error.h"
#include "mapnav/core/options.h"
#include "mapnav/vision_iface/pipeline.h"

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

Vec3 ClusterPerceptron::feature(double r, double g, double b) const {
  if (!opt_.normalized_color) return Vec3(r, g, b);
  const double sum = r + g + b;
  return sum > 0 ? Vec3(Vec3(r, g, b) * (255.0 / sum)) : Vec3::Constant(85.0);
}

int ClusterPerceptron::nearest(const Vec3& f) const {
  const auto r = static_cast<float>(f.x()), g = static_cast<float>(f.y()), b = static_cast<float>(f.z());
  int best = 0;
  float bd = std::numeric_limits<float>::max();
  for (std::size_t k = 0; k < means_.size(); ++k) {
    const float dr = r - static_cast<float>(means_[k].x()), dg = g - static_cast<float>(means_[k].y()),
                db = b - static_cast<float>(means_[k].z());
    const float d = dr * dr + dg * dg + db * db;
    if (d < bd) {
      bd = d;
      best = static_cast<int>(k);
    }
  }
  return best;
}

// --- §3 clustering ---------------------------------------------------------------------------------

std::vector<Vec3> ClusterPerceptron::trainClusters(const std::uint8_t* rgb, int width, int height) {
  if (rgb == nullptr || width <= 0 || height <= 0) throw InvalidInput("trainClusters: empty frame");
  const int n = opt_.clusters;
  std::mt19937_64 rng(opt_.seed);
  std::uniform_real_distribution<double> uni(0.0, 255.0);
  recent_errors_.clear();
  means_.assign(static_cast<std::size_t>(n), Vec3::Zero());
  for (Vec3& m : means_) {
    m = Vec3(uni(rng), uni(rng), uni(rng));
    m = feature(m.x(), m.y(), m.z());
  }
  return clusterFrom(rgb, width, height);
}

std::vector<Vec3> ClusterPerceptron::clusterFrom(const std::uint8_t* rgb, int width, int height) {
  const int n = static_cast<int>(means_.size());
  trained_ = false;
  const int st = opt_.train_stride;

  // One pass: each pixel's winner; counts, difference sums and the reconstruction error per band.
  std::vector<double> cnt(n), dr(n), dg(n), db(n);
  auto pass = [&]() {
    std::fill(cnt.begin(), cnt.end(), 0.0);
    std::fill(dr.begin(), dr.end(), 0.0);
    std::fill(dg.begin(), dg.end(), 0.0);
    std::fill(db.begin(), db.end(), 0.0);
    Vec3 err = Vec3::Zero();
    double total = 0;
    for (int v = 0; v < height; v += st)
      for (int u = 0; u < width; u += st) {
        const std::uint8_t* p = rgb + 3 * (static_cast<std::size_t>(v) * width + u);
        const Vec3 f = feature(p[0], p[1], p[2]);
        const int k = nearest(f);
        const double er = f.x() - means_[k].x(), eg = f.y() - means_[k].y(), eb = f.z() - means_[k].z();
        cnt[k] += 1;
        dr[k] += er;
        dg[k] += eg;
        db[k] += eb;
        err += Vec3(er * er, eg * eg, eb * eb);
        total += 1;
      }
    return Vec3(err / total);
  };

  std::vector<Vec3> history;
  history.push_back(pass());
  for (int it = 0; it < opt_.max_cluster_iterations; ++it) {
    // The adjustments are computed from the current means before any is applied.
    std::vector<Vec3> next = means_;
    for (int k = 0; k < n; ++k) {
      if (cnt[k] > 0) {
        next[k] += Vec3(dr[k], dg[k], db[k]) / cnt[k];  // learning rate 1: isodata
      } else {
        // Empty cluster: move it toward the nearest cluster that classified pixels (the paper's
        // heuristic; a nearest one that is empty too would leave both stranded). A small offset per
        // cluster keeps two empty clusters from landing on the same point, which would tie forever.
        int best = -1;
        double bd = std::numeric_limits<double>::max();
        for (int j = 0; j < n; ++j) {
          if (j == k || cnt[j] == 0) continue;
          const double d = (means_[j] - means_[k]).squaredNorm();
          if (d < bd) {
            bd = d;
            best = j;
          }
        }
        if (best >= 0) {
          const double off = (k % 2 == 0 ? 1.0 : -1.0) * (1.0 + 0.5 * k);
          next[k] = means_[best] + Vec3(off, -off, off);
        }
      }
    }
    means_ = next;
    history.push_back(pass());
    const Vec3 slope = history.back() - history[history.size() - 2];
    if (slope.cwiseAbs().maxCoeff() < opt_.cluster_slope_threshold) break;
  }
  train_error_ = history.back().mean();
  return history;
}

double ClusterPerceptron::reconstructionError(const std::uint8_t* rgb, int width, int height, int stride) const {
  if (means_.empty() || rgb == nullptr || width <= 0 || height <= 0 || stride < 1) return 0;
  double err = 0, total = 0;
  for (int v = 0; v < height; v += stride)
    for (int u = 0; u < width; u += stride) {
      const std::uint8_t* p = rgb + 3 * (static_cast<std::size_t>(v) * width + u);
      const Vec3 f = feature(p[0], p[1], p[2]);
      err += (f - means_[static_cast<std::size_t>(nearest(f))]).squaredNorm();
      total += 1;
    }
  return err / (3.0 * total);
}

Image ClusterPerceptron::reconstruct(const std::uint8_t* rgb, int width, int height) const {
  Image out(width, height, 3);
  if (means_.empty()) return out;
  for (std::size_t i = 0; i < static_cast<std::size_t>(width) * height; ++i) {
    const std::uint8_t* p = rgb + 3 * i;
    Vec3 c = means_[static_cast<std::size_t>(nearest(p[0], p[1], p[2]))];
    // Normalised colour: the cluster's chromaticity at the pixel's own brightness.
    if (opt_.normalized_color) c *= (p[0] + p[1] + p[2]) / 255.0;
    for (int b = 0; b < 3; ++b)
      out.data[3 * i + b] = static_cast<std::uint8_t>(std::clamp(std::lround(c[b]), 0L, 255L));
  }
  return out;
}

// --- §4 perceptron ---------------------------------------------------------------------------------

namespace {
/// Net input for a pixel won by cluster k: +w_k, -w_j for every other j, + bias.
double netFor(const std::vector<double>& w, int k) {
  const int n = static_cast<int>(w.size()) - 1;
  double net = w[static_cast<std::size_t>(n)];
  for (int j = 0; j < n; ++j) net += (j == k ? 1.0 : -1.0) * w[static_cast<std::size_t>(j)];
  return net;
}
/// A pixel's road certainty: the perceptron output y in [-1, 1] quantised to 16 levels, 16 apart
/// (0 = surely not road, 240 = surely road; > 127 ⇔ y > 0 but for y within 1/15 of 0). Coarser
/// than a byte on purpose: clusters of almost the same output (two shades of lit asphalt at 0.99
/// and 0.995) share a level, so the lookup table's cells between them are not boundary cells.
constexpr int kCertaintyMax = 240;
std::uint8_t certaintyOf(double y) {
  return static_cast<std::uint8_t>(16 * std::lround(std::clamp((y + 1.0) * 7.5, 0.0, 15.0)));
}
constexpr std::uint8_t kAmbiguous = 255;  // LUT cell spanning a cluster boundary: classify exactly
}  // namespace

std::vector<double> ClusterPerceptron::trainPerceptron(const std::uint8_t* rgb, int width, int height,
                                                       const std::uint8_t* road) {
  if (opt_.raw_rgb) return trainRgbPerceptron(rgb, width, height, road);
  if (means_.empty()) throw InvalidInput("trainPerceptron: the clusters are not trained");
  const int n = static_cast<int>(means_.size());
  // Every pixel won by the same cluster has the same inputs, so the per-pixel LMS sums reduce exactly
  // to per-cluster counts of road and non-road pixels.
  std::vector<double> pos(n, 0.0), neg(n, 0.0);
  double total = 0;
  const int st = opt_.train_stride;
  for (int v = 0; v < height; v += st)
    for (int u = 0; u < width; u += st) {
      const std::size_t i = static_cast<std::size_t>(v) * width + u;
      const int k = nearest(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
      (road[i] != 0 ? pos : neg)[k] += 1;
      total += 1;
    }
  if (opt_.balance_classes) {
    double inside = 0, outside = 0;
    for (int k = 0; k < n; ++k) {
      inside += pos[k];
      outside += neg[k];
    }
    if (inside > 0 && outside > 0) {
      for (double& p : pos) p *= outside / inside;
      total = 2 * outside;
    }
  }
  return runLms(static_cast<std::size_t>(n) + 1, total, [&](std::vector<double>& grad) {
    double err = 0;
    for (int k = 0; k < n; ++k) {
      const double y = std::tanh(netFor(weights_, k));
      const double e = pos[k] * (1.0 - y) + neg[k] * (-1.0 - y);  // Σ (target − output)
      err += pos[k] * std::abs(1.0 - y) + neg[k] * std::abs(-1.0 - y);
      for (int j = 0; j < n; ++j) grad[j] += e * (j == k ? 1.0 : -1.0);
      grad[n] += e;  // bias input 1
    }
    return err;
  });
}

std::vector<double> ClusterPerceptron::runLms(std::size_t inputs, double total,
                                              const std::function<double(std::vector<double>&)>& pass) {
  weights_.assign(inputs, 0.0);
  std::vector<double> history;
  double prev = std::numeric_limits<double>::max();
  int calm = 0;
  for (int it = 0; it < opt_.max_perceptron_iterations; ++it) {
    std::vector<double> grad(inputs, 0.0);
    const double err = pass(grad) / total;
    history.push_back(err);
    for (std::size_t j = 0; j < grad.size(); ++j) weights_[j] += opt_.perceptron_rate * grad[j] / total;
    // Stop when the mean error has changed by less than the tolerance for 3 iterations running
    // (a single small change can be a plateau while the bias settles).
    calm = std::abs(prev - err) < opt_.perceptron_tolerance ? calm + 1 : 0;
    if (calm >= 3) break;
    prev = err;
  }
  buildLut();
  trained_ = !row_widths_.empty();
  return history;
}

namespace {
/// The raw-RGB perceptron's input for one band of a feature: the level scaled to [-1, 1].
double rgbInput(double x) { return x / 127.5 - 1.0; }
double netRgb(const std::vector<double>& w, const Vec3& f) {
  return w[0] * rgbInput(f.x()) + w[1] * rgbInput(f.y()) + w[2] * rgbInput(f.z()) + w[3];
}
}  // namespace

std::vector<double> ClusterPerceptron::trainRgbPerceptron(const std::uint8_t* rgb, int width, int height,
                                                          const std::uint8_t* road) {
  // Pixels of the same colour have the same inputs: the LMS sums reduce exactly to per-colour counts.
  std::unordered_map<std::uint32_t, std::pair<double, double>> counts;  // colour → (road, not road)
  double total = 0;
  const int st = opt_.train_stride;
  for (int v = 0; v < height; v += st)
    for (int u = 0; u < width; u += st) {
      const std::size_t i = static_cast<std::size_t>(v) * width + u;
      const std::uint32_t key = (std::uint32_t{rgb[3 * i]} << 16) | (std::uint32_t{rgb[3 * i + 1]} << 8) | rgb[3 * i + 2];
      auto& c = counts[key];
      (road[i] != 0 ? c.first : c.second) += 1;
      total += 1;
    }
  if (opt_.balance_classes) {
    double inside = 0, outside = 0;
    for (const auto& [key, c] : counts) {
      inside += c.first;
      outside += c.second;
    }
    if (inside > 0 && outside > 0) {
      for (auto& [key, c] : counts) c.first *= outside / inside;
      total = 2 * outside;
    }
  }
  std::vector<std::pair<std::uint32_t, std::pair<double, double>>> colours(counts.begin(), counts.end());
  std::sort(colours.begin(), colours.end());  // a fixed summation order: the same weights every run
  return runLms(4, total, [&](std::vector<double>& grad) {
    double err = 0;
    for (const auto& [key, pn] : colours) {
      const Vec3 f = feature(key >> 16, (key >> 8) & 255, key & 255);
      const double y = std::tanh(netRgb(weights_, f));
      const double e = pn.first * (1.0 - y) + pn.second * (-1.0 - y);
      err += pn.first * std::abs(1.0 - y) + pn.second * std::abs(-1.0 - y);
      grad[0] += e * rgbInput(f.x());
      grad[1] += e * rgbInput(f.y());
      grad[2] += e * rgbInput(f.z());
      grad[3] += e;
    }
    return err;
  });
}

double ClusterPerceptron::outputReference(std::uint8_t r, std::uint8_t g, std::uint8_t b) const {
  if (opt_.raw_rgb) return std::tanh(netRgb(weights_, feature(r, g, b)));
  return std::tanh(netFor(weights_, nearest(r, g, b)));
}

void ClusterPerceptron::buildLut() {
  // Cell q covers the colours [8q, 8q + 7] per band. A cell whose certainty its 8 corners prove to be
  // the same everywhere in it gets that certainty; every other cell is marked ambiguous and gets its
  // own 8×8×8 table of each colour's certainty (`exact`: the reference path's, certaintyOf(
  // outputReference()), computed the cheaper way), so the fast path needs no distance computation at
  // all and still equals the reference path colour by colour. `uniform` is the proof for one
  // perceptron: the certainty, or nothing.
  std::function<std::optional<std::uint8_t>(int, int, int)> uniform;
  std::function<std::uint8_t(int, int, int)> exact;
  std::vector<std::uint8_t> cert, near;
  auto corner = [](int i) { return i % 2 == 0 ? (i / 2) * 8 : (i / 2) * 8 + 7; };  // 8q and 8q + 7
  if (opt_.raw_rgb) {
    // The net input is linear in the colour: over a cell it lies between its values at the corners,
    // and the certainty, monotonic in it, is uniform when it is the same at both ends (a hair wider,
    // against rounding). In normalised colour the net input is a ratio of two linear functions of
    // the colour, which also takes its extremes over a box at the corners where the denominator
    // R + G + B stays positive.
    uniform = [&](int r, int g, int b) -> std::optional<std::uint8_t> {
      double lo = std::numeric_limits<double>::max(), hi = -lo;
      for (int m = 0; m < 8; ++m) {
        const Vec3 f = feature(corner(2 * r + (m & 1)), corner(2 * g + ((m >> 1) & 1)), corner(2 * b + ((m >> 2) & 1)));
        const double net = netRgb(weights_, f);
        lo = std::min(lo, net);
        hi = std::max(hi, net);
      }
      const std::uint8_t c = certaintyOf(std::tanh(lo - 1e-9));
      if (c == certaintyOf(std::tanh(hi + 1e-9))) return c;
      return std::nullopt;
    };
    exact = [&](int r, int g, int b) { return certaintyOf(std::tanh(netRgb(weights_, feature(r, g, b)))); };
  } else {
    // A cell whose 8 corners share their nearest cluster lies wholly in that cluster's (convex)
    // Voronoi cell. In normalised colour f = 255 C / (R + G + B), "nearer mean k than mean j" is
    // linear in f and so, times R + G + B, a half-space through black in RGB: the same holds.
    const int n = static_cast<int>(means_.size());
    cert.resize(n);
    for (int k = 0; k < n; ++k) cert[k] = certaintyOf(std::tanh(netFor(weights_, k)));
    // Nearest cluster of every lattice corner (33 values per band: 8q and 8q + 7 for q < 32).
    near.resize(64 * 64 * 64);
    for (int a = 0; a < 64; ++a)
      for (int b = 0; b < 64; ++b)
        for (int c = 0; c < 64; ++c)
          near[(a * 64 + b) * 64 + c] = static_cast<std::uint8_t>(nearest(corner(a), corner(b), corner(c)));
    // (`uniform` and `exact` outlive this block: they use only what the function's scope holds.)
    uniform = [&, n](int r, int g, int b) -> std::optional<std::uint8_t> {
      const int k0 = near[((2 * r) * 64 + 2 * g) * 64 + 2 * b];
      const std::uint8_t c = cert[k0];
      bool same = true;
      for (int m = 1; m < 8 && same; ++m)
        same = near[((2 * r + (m & 1)) * 64 + 2 * g + ((m >> 1) & 1)) * 64 + 2 * b + ((m >> 2) & 1)] == k0;
      if (same) return c;
      // Exact test for a cell spanning clusters of equal certainty c: no point of the cube has a
      // cluster j of another certainty as its nearest if, for every such j, some cluster k of
      // certainty c is nearer than j at all 8 corners (the region nearer k than j is a half-space, so
      // the whole cube is).
      const auto d2 = [&](int k, double x, double y, double z) { return (means_[k] - feature(x, y, z)).squaredNorm(); };
      for (int j = 0; j < n; ++j) {
        if (cert[j] == c) continue;
        bool out = false;
        for (int k = 0; k < n && !out; ++k) {
          if (cert[k] != c) continue;
          out = true;
          for (int m = 0; m < 8 && out; ++m) {
            const double x = corner(2 * r + (m & 1)), y = corner(2 * g + ((m >> 1) & 1)),
                         z = corner(2 * b + ((m >> 2) & 1));
            out = d2(k, x, y, z) < d2(j, x, y, z);
          }
        }
        if (!out) return std::nullopt;
      }
      return c;
    };
    exact = [&](int r, int g, int b) { return cert[nearest(r, g, b)]; };
  }
  lut_.assign(32 * 32 * 32, 0);
  sub_offset_.assign(32 * 32 * 32, 0);
  sub_.clear();
  for (int cell = 0; cell < 32 * 32 * 32; ++cell) {
    const int r = cell >> 10, g = (cell >> 5) & 31, b = cell & 31;
    // Black's cell proves nothing from its corners in normalised colour: black counts as grey there.
    const auto c = opt_.normalized_color && cell == 0 ? std::nullopt : uniform(r, g, b);
    if (c) {
      lut_[cell] = *c;
      continue;
    }
    lut_[cell] = kAmbiguous;
    sub_offset_[cell] = static_cast<std::uint32_t>(sub_.size());
    for (int i = 0; i < 512; ++i) sub_.push_back(exact(8 * r + (i >> 6), 8 * g + ((i >> 3) & 7), 8 * b + (i & 7)));
  }
}

void ClusterPerceptron::setRowWidths(std::vector<double> widths) {
  row_widths_ = std::move(widths);
  trained_ = !weights_.empty() && !row_widths_.empty();
}

void ClusterPerceptron::setCamera(const Camera& camera) {
  // Pin-hole, tilt only: the ground point (x, y) is at depth Z = (x − cx)·cos φ + h·sin φ and height
  // Y = −(x − cx)·sin φ + h·cos φ in the camera frame, so its row v = v_c + f·Y/Z depends on x alone,
  // and its column u = u_c − f·(y − cy)/Z is affine in y at that row: b_r = −f/Z.
  const int h = camera.height();
  row_x_.assign(static_cast<std::size_t>(h), std::nan(""));
  row_a_.assign(static_cast<std::size_t>(h), std::nan(""));
  row_b_.assign(static_cast<std::size_t>(h), std::nan(""));
  for (int v = 0; v < h; ++v) {
    const auto g = camera.backproject(Vec2(camera.intrinsics().cx, v));
    if (!g) continue;
    const auto p0 = camera.projectGround(Vec2(g->x(), 0.0)), p1 = camera.projectGround(Vec2(g->x(), 1.0));
    if (!p0 || !p1) continue;
    row_x_[v] = g->x();
    row_a_[v] = p0->x();
    row_b_[v] = p1->x() - p0->x();
  }
}

Polygon2 roadBand(const std::vector<Vec2>& centre, const std::vector<double>& row_widths, int width) {
  Polygon2 left, right;
  const long last = static_cast<long>(row_widths.size()) - 1;
  for (const Vec2& c : centre) {
    const double hw = 0.5 * row_widths[static_cast<std::size_t>(std::clamp(std::lround(c.y()), 0L, last))];
    left.emplace_back(std::clamp(c.x() - hw, -0.5, width - 0.5), c.y());
    right.emplace_back(std::clamp(c.x() + hw, -0.5, width - 0.5), c.y());
  }
  Polygon2 band = right;
  for (auto it = left.rbegin(); it != left.rend(); ++it) band.push_back(*it);
  return band;
}

// --- Bootstrap outline ------------------------------------------------------------------------------

Image fillPolygonMask(const std::vector<Polygon2>& polygons, int width, int height) {
  Image out(width, height, 1);
  cv::Mat m(height, width, CV_8UC1, out.data.data());
  for (const Polygon2& poly : polygons) {
    std::vector<cv::Point> pts;
    for (const Vec2& p : poly)
      pts.emplace_back(cvRound(std::clamp(p.x(), -1e5, 1e5)), cvRound(std::clamp(p.y(), -1e5, 1e5)));
    if (pts.size() >= 3) cv::fillPoly(m, std::vector<std::vector<cv::Point>>{pts}, cv::Scalar(255));
  }
  return out;
}

Image predictedRoadMask(const PredictedObject& prediction, const Camera& camera) {
  std::vector<Polygon2> rings;
  for (const PredictedRegion& region : prediction.regions)
    for (const Polygon2& ring : region.vehicle) {
      Polygon2 img;
      for (std::size_t i = 0; i < ring.size(); ++i) {
        const Vec2 a = ring[i], b = ring[(i + 1) % ring.size()];
        const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / 0.05)));
        for (int k = 0; k < steps; ++k)
          if (const auto p = camera.projectGround(a + (b - a) * (static_cast<double>(k) / steps))) img.push_back(*p);
      }
      rings.push_back(std::move(img));
    }
  return fillPolygonMask(rings, camera.width(), camera.height());
}

std::vector<double> trapezoidRowWidths(const Image& mask) {
  const int w = mask.width, h = mask.height;
  std::vector<double> widths(static_cast<std::size_t>(h), 0.0);
  std::vector<double> vs, ws;
  int top = h;
  for (int v = 0; v < h; ++v) {
    int lo = w, hi = -1;
    for (int u = 0; u < w; ++u)
      if (mask.pixel(u, v)[0] != 0) {
        lo = std::min(lo, u);
        hi = std::max(hi, u);
      }
    if (hi < 0) continue;
    top = std::min(top, v);
    widths[v] = hi - lo + 1;
    if (lo > 0 && hi < w - 1) {
      vs.push_back(v);
      ws.push_back(hi - lo + 1);
    }
  }
  if (vs.size() >= 8 && vs.back() - vs.front() >= 8) {
    // A flat road of constant width: the width is linear in v. Fit and extrapolate below the top.
    double sv = 0, sw = 0, svv = 0, svw = 0;
    const double m = static_cast<double>(vs.size());
    for (std::size_t i = 0; i < vs.size(); ++i) {
      sv += vs[i];
      sw += ws[i];
      svv += vs[i] * vs[i];
      svw += vs[i] * ws[i];
    }
    const double den = m * svv - sv * sv;
    if (std::abs(den) > 1e-9) {
      const double slope = (m * svw - sv * sw) / den, icpt = (sw - slope * sv) / m;
      for (int v = top; v < h; ++v) widths[v] = std::max(widths[v], std::max(1.0, icpt + slope * v));
    }
  }
  return widths;
}

// --- §5/§6 runtime ------------------------------------------------------------------------------------

namespace {

/// Per-thread scratch of find(): the frame's per-pixel certainty and its block sums, reused from
/// frame to frame so that a frame costs no allocation.
struct Scratch {
  std::vector<std::uint8_t> cert;
  std::vector<std::uint32_t> bsum;
};
Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

int threadCount(int option) {
#ifdef _OPENMP
  return option == 0 ? omp_get_num_procs() : option;
#else
  (void)option;
  return 1;
#endif
}

/// The arc model's offset per unit curvature (pixels per 1/m) of the rows: the column of the ground
/// parabola κ·(x − x0)(x − x1)/2, which vanishes at the rows v0 and v1 (ground distances x0, x1),
/// so that with it the centre line is an image line through (a, v0), (a + b, v1) plus κ times this.
/// The parabola differs from κx²/2 by a ground line, whose image is an image line: the same family.
struct ArcBasis {
  const std::vector<double>* x = nullptr;  // per image row: ground distance, m
  const std::vector<double>* b = nullptr;  // per image row: columns per metre of lateral offset
  double x0 = 0, x1 = 0;
  static double at(const std::vector<double>& f, double v) {
    const double c = std::clamp(v, 0.0, static_cast<double>(f.size() - 1));
    const std::size_t i = std::min(static_cast<std::size_t>(c), f.size() - 2);
    return f[i] + (c - static_cast<double>(i)) * (f[i + 1] - f[i]);
  }
  ArcBasis(const std::vector<double>& xs, const std::vector<double>& bs, double v0, double v1)
      : x(&xs), b(&bs), x0(at(xs, v0)), x1(at(xs, v1)) {}
  ArcBasis() = default;
  double operator()(double v) const {
    if (x == nullptr) return 0.0;
    const double xv = at(*x, v);
    return 0.5 * at(*b, v) * (xv - x0) * (xv - x1);
  }
};

/// The road model of the image centre line, t = (v − v0) / (v1 − v0): u = a + b t (the line), or
/// u = a + b t + κ·arc(v) (the ground arc; p[2] = κ, 1/m).
struct CentreModel {
  double v0 = 0, v1 = 1;
  Vec3 p = Vec3::Zero();  // a, b, κ
  ArcBasis arc;
  double t(double v) const { return (v - v0) / (v1 - v0); }
  Vec3 basis(double v) const { return Vec3(1.0, t(v), arc.x ? arc(v) : 0.0); }
  double u(double v) const { return p[0] + t(v) * p[1] + (arc.x ? p[2] * arc(v) : 0.0); }
};

/// Least-squares fit of the model's `degree + 1` coefficients to (v, u) samples with Huber
/// weights (IRLS, `k` pixels), starting from the model's own coefficients for the weights.
bool fitCentreModel(const std::vector<Vec2>& vu, int degree, double k, CentreModel& model) {
  const int m = degree + 1;
  if (static_cast<int>(vu.size()) < 4 * m) return false;
  for (int it = 0; it < 8; ++it) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Vec3 rhs = Vec3::Zero();
    for (const Vec2& s : vu) {
      const double r = std::abs(s.y() - model.u(s.x()));
      const double w = r <= k ? 1.0 : k / r;
      const Vec3 phi = model.basis(s.x());
      A.topLeftCorner(m, m) += w * phi.head(m) * phi.head(m).transpose();
      rhs.head(m) += w * phi.head(m) * (s.y() - (m < 3 ? model.p[2] * phi[2] : 0.0));
    }
    Vec3 p = Vec3(0.0, 0.0, m < 3 ? model.p[2] : 0.0);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(A.topLeftCorner(m, m));
    if (ldlt.info() != Eigen::Success) return false;
    p.head(m) = ldlt.solve(rhs.head(m));
    if (!p.allFinite()) return false;
    const double change = (p - model.p).cwiseAbs().maxCoeff();
    model.p = p;
    if (change < 1e-3) break;
  }
  return true;
}

/// Round half away from zero, without libm's call (|x| < 2³¹).
inline std::int32_t roundToInt(double x) {
  return x >= 0 ? static_cast<std::int32_t>(x + 0.5) : -static_cast<std::int32_t>(-x + 0.5);
}

/// Adds each block's certainty sum of one row to `sums` (blocks of `bs` pixels) and returns the
/// row's road pixels (certainty > 127, the byte's top bit). Eight pixels at a time with SSE2's sum
/// of absolute differences where the blocks are whole multiples of 8 pixels.
long long blockSums(const std::uint8_t* c, int width, int bs, std::uint32_t* sums) {
  const int cols = (width + bs - 1) / bs;
  long long road = 0;
  int b = 0;
#ifdef __SSE2__
  if (bs % 8 == 0) {
    const __m128i zero = _mm_setzero_si128(), ones = _mm_set1_epi8(1);
    for (; (b + 1) * bs <= width; ++b) {
      __m128i sum = zero, cnt = zero;
      for (int u = b * bs; u < (b + 1) * bs; u += 8) {
        const __m128i x = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(c + u));
        sum = _mm_add_epi64(sum, _mm_sad_epu8(x, zero));
        cnt = _mm_add_epi64(cnt, _mm_sad_epu8(_mm_and_si128(_mm_srli_epi16(x, 7), ones), zero));
      }
      sums[b] += static_cast<std::uint32_t>(_mm_cvtsi128_si32(sum));
      road += _mm_cvtsi128_si32(cnt);
    }
  }
#endif
  for (; b < cols; ++b) {
    const int u0 = b * bs, u1 = std::min(width, u0 + bs);
    std::uint32_t s = 0;
    for (int u = u0; u < u1; ++u) {
      s += c[u];
      road += c[u] > 127;
    }
    sums[b] += s;
  }
  return road;
}

struct HoughPeak {
  std::int64_t sum = std::numeric_limits<std::int64_t>::min();
  int x = 0, shift = 0, bend = 0;
};

/// The Hough's accumulation (§5): for every bend q and shift s, row i of the kernel sums `S`
/// (`rows` × 3·cols, column c of the image at index cols + c) moved by offsets[(q·shifts + s)·rows + i]
/// blocks and summed column by column; the largest column sum over the columns x_lo[s]..x_hi[s],
/// first in (q, s, x) order (none: sum stays the lowest int64). Exact integer arithmetic; built for
/// AVX2 too where the processor has it.
__attribute__((target_clones("avx2", "default"))) HoughPeak houghSearch(const std::int32_t* S, int rows, int cols,
                                                                         const int* offsets, int shifts, int bends,
                                                                         const int* x_lo, const int* x_hi) {
  HoughPeak best;
  const int ext = 3 * cols;
  std::vector<std::int32_t> acc(static_cast<std::size_t>(cols));
  for (int q = 0; q < bends; ++q)
    for (int s = 0; s < shifts; ++s) {
      if (x_lo[s] > x_hi[s]) continue;
      std::fill(acc.begin(), acc.end(), 0);
      const int* off = offsets + (static_cast<std::size_t>(q) * shifts + s) * rows;
      for (int i = 0; i < rows; ++i) {
        const std::int32_t* __restrict srow = S + static_cast<std::size_t>(i) * ext + cols + off[i];
        const int x0 = std::max(0, -cols - off[i]), x1 = std::min(cols, 2 * cols - off[i]);
        std::int32_t* __restrict a = acc.data();
        for (int x = x0; x < x1; ++x) a[x] += srow[x];
      }
      for (int x = x_lo[s]; x <= x_hi[s]; ++x)
        if (acc[x] > best.sum) best = {acc[x], x, s, q};
    }
  return best;
}

/// The fast path's classification of one row: the colour's cell in the 32³ table, and for the
/// cells that straddle a cluster boundary, the colour's entry in the cell's exact 8³ table.
void classifyRow(const std::uint8_t* __restrict p, std::uint8_t* __restrict c, int width,
                 const std::uint8_t* __restrict lut, const std::uint32_t* __restrict sub_offset,
                 const std::uint8_t* __restrict sub) {
  // The cell index per band from small tables: three loads and two ors instead of six shifts.
  static const auto index = [] {
    std::array<std::array<std::uint16_t, 256>, 3> t{};
    for (int x = 0; x < 256; ++x) {
      t[0][x] = static_cast<std::uint16_t>((x >> 3) << 10);
      t[1][x] = static_cast<std::uint16_t>((x >> 3) << 5);
      t[2][x] = static_cast<std::uint16_t>(x >> 3);
    }
    return t;
  }();
  const std::uint16_t *ir = index[0].data(), *ig = index[1].data(), *ib = index[2].data();
  for (int u = 0; u < width; ++u, p += 3) {
    const unsigned cell = ir[p[0]] | ig[p[1]] | ib[p[2]];
    const std::uint8_t q = lut[cell];
    if (q != kAmbiguous) [[likely]] {
      c[u] = q;
    } else {
      c[u] = sub[sub_offset[cell] + (((p[0] & 7u) << 6) | ((p[1] & 7u) << 3) | (p[2] & 7u))];
    }
  }
}

/// A place in a row where the class changes and stays changed for 3 pixels on each side (isolated
/// pixels of the other class are no edge): a left road edge (road starts, going right) or a right one.
struct EdgeCandidate {
  int v;
  double u;  // pixel boundary, x.5
  bool left;
};

/// The candidates of one row (certainties; road ⇔ > 127 ⇔ the byte's top bit) with u in [lo, hi].
void rowCandidates(const std::uint8_t* row, int width, int v, int lo, int hi, std::vector<EdgeCandidate>& out) {
  auto road = [row](int u) { return row[u] > 127; };
  const int u0 = std::max(3, lo), u1 = std::min(width - 3, hi);
  for (int u = u0; u <= u1; ++u) {
    // Eight pixels from u − 1 of one class hold no change: skip them.
    if (u + 7 <= width) {
      std::uint64_t word;
      std::memcpy(&word, row + u - 1, 8);
      const std::uint64_t top = word & 0x8080808080808080ULL;
      if (top == 0 || top == 0x8080808080808080ULL) {
        u += 6;
        continue;
      }
    }
    const bool now = road(u);
    if (road(u - 1) == now) continue;
    if (road(u - 3) != now && road(u - 2) != now && road(u + 1) == now && (u + 2 >= width || road(u + 2) == now))
      out.push_back({v, u - 0.5, now});
  }
}

/// The column of the edge of a candidate (`u` the first pixel of the class that begins, the boundary
/// u − 0.5) within the pair of pixels u − 1, u by their colours (ClusterPerceptronOptions::
/// subpixel_edges): the class that begins fills [x, u + 0.5] of the pair, x = u + 0.5 − Σ share, each
/// pixel's share its place, clamped to [0, 1], on the colour line from the ending class's pure pixels
/// (u − 3, u − 2) to the beginning class's (u + 1, u + 2). The boundary where their colours differ by
/// under 16 levels. `u` is in [3, width − 3], as rowCandidates() gives it.
double subpixelEdge(const std::uint8_t* row_rgb, int u) {
  double from[3], to[3], d2 = 0;
  for (int c = 0; c < 3; ++c) {
    from[c] = 0.5 * (row_rgb[3 * (u - 3) + c] + row_rgb[3 * (u - 2) + c]);
    to[c] = 0.5 * (row_rgb[3 * (u + 1) + c] + row_rgb[3 * (u + 2) + c]);
    d2 += (to[c] - from[c]) * (to[c] - from[c]);
  }
  if (d2 < 16.0 * 16.0) return u - 0.5;
  double share = 0;
  for (const int k : {u - 1, u}) {
    double dot = 0;
    for (int c = 0; c < 3; ++c) dot += (row_rgb[3 * k + c] - from[c]) * (to[c] - from[c]);
    share += std::clamp(dot / d2, 0.0, 1.0);
  }
  return u + 0.5 - share;
}

/// How many row sides of `edges` (in row order, `.v` the row) hold an edge that `near` accepts: each
/// row counts a left (`isLeft`) and a right edge at most once. The support of a consensus model.
template <typename Edge, typename IsLeft, typename Near>
int rowSideSupport(const std::vector<Edge>& edges, IsLeft isLeft, Near near) {
  int n = 0, last_v = -1;
  bool got_l = false, got_r = false;
  for (const Edge& e : edges) {
    if (e.v != last_v) {
      last_v = e.v;
      got_l = got_r = false;
    }
    bool& got = isLeft(e) ? got_l : got_r;
    if (got || !near(e)) continue;
    got = true;
    ++n;
  }
  return n;
}

/// How many candidates lie within `tol` pixels of the road edges the model puts at
/// centre ∓ width/2 (each row counts a left and a right edge at most once).
int edgeSupport(const std::vector<EdgeCandidate>& cands, const std::vector<double>& widths, const CentreModel& m,
                double tol) {
  return rowSideSupport(
      cands, [](const EdgeCandidate& e) { return e.left; },
      [&](const EdgeCandidate& e) { return !(std::abs(e.u - (m.u(e.v) + (e.left ? -0.5 : 0.5) * widths[e.v])) > tol); });
}

/// Edge consensus (RANSAC, seeded): models through the centres implied by `degree + 1` random edge
/// candidates in different rows, kept when more candidates support them than support `model` and
/// `allowed` admits them.
CentreModel edgeConsensus(const std::vector<EdgeCandidate>& cands, const std::vector<double>& widths,
                          const CentreModel& model, int degree, std::uint64_t seed, int iterations, double tol,
                          double max_curvature, const std::function<bool(const CentreModel&)>& allowed) {
  CentreModel best = model;
  int best_n = edgeSupport(cands, widths, model, tol);
  if (cands.size() < static_cast<std::size_t>(degree + 1)) return best;
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, cands.size() - 1);
  const int m = degree + 1;
  // Adaptive: stop once a better model is unlikely (probability 0.999) given the best one's support.
  int needed = iterations;
  for (int it = 0; it < std::min(iterations, needed); ++it) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
    Vec3 rhs = Vec3::Zero();
    bool ok = true;
    std::array<int, 3> rows{-1000, -1000, -1000};
    for (int k = 0; k < m && ok; ++k) {
      const EdgeCandidate& e = cands[pick(rng)];
      for (int j = 0; j < k; ++j) ok = ok && std::abs(e.v - rows[j]) >= 16;
      rows[k] = e.v;
      A.row(k) = model.basis(e.v).transpose();
      rhs[k] = e.u + (e.left ? 0.5 : -0.5) * widths[e.v];
    }
    if (!ok) continue;
    CentreModel h = model;
    h.p = Vec3::Zero();
    h.p.head(m) = A.topLeftCorner(m, m).partialPivLu().solve(rhs.head(m));
    if (!h.p.allFinite() || std::abs(h.p[2]) > max_curvature || !allowed(h)) continue;
    const int n = edgeSupport(cands, widths, h, tol);
    if (n > best_n) {
      best_n = n;
      best = h;
      const double w = std::min(0.99, static_cast<double>(n) / static_cast<double>(cands.size()));
      needed = static_cast<int>(std::ceil(std::log(0.001) / std::log(1.0 - std::pow(w, m))));
    }
  }
  return best;
}


/// The arc model's road on the ground (vehicle frame: x ahead, y left): the centre line is the
/// circle (a line when κ = 0) through (0, y0) with heading θ and curvature κ (1/m, left positive);
/// the road's edges are the concentric circles half the road's width to either side.
struct GroundArc {
  double y0 = 0, th = 0, k = 0;
  /// The signed perpendicular offset of the ground point (x, y) from the centre line (left
  /// positive), ℓ = N / (1 + D) with N = 2n − κa, D = √(1 − κN) (n the offset from the tangent
  /// line, a the squared distance to (0, y0)): exact for circles and lines alike. With its
  /// derivatives by y0, θ and κ when `jac` is given: (κ·dy − cos θ)/D, −along/D and (ℓ² − a)/(2D).
  double offset(double x, double y, double c, double s, Vec3* jac = nullptr) const {
    const double dy = y - y0, along = c * x + s * dy, n = -s * x + c * dy, a = x * x + dy * dy;
    const double N = 2.0 * n - k * a, D = std::sqrt(std::max(1e-12, 1.0 - k * N)), l = N / (1.0 + D);
    if (jac != nullptr) *jac = Vec3((k * dy - c) / D, -along / D, (l * l - a) / (2.0 * D));
    return l;
  }
  /// The centre line's lateral offset at ground distance x: y0 + x(κx + 2 sin θ) / (cos θ + √(1 − s²)),
  /// s = κx + sin θ; NaN where the circle turns back before x.
  double at(double x) const {
    const double s = k * x + std::sin(th);
    if (std::abs(s) >= 1.0) return std::nan("");
    return y0 + x * (k * x + 2.0 * std::sin(th)) / (std::cos(th) + std::sqrt(1.0 - s * s));
  }
};

/// An edge candidate on the ground: its point, the road side it would bound (+1 left, −1 right), its
/// image row, and the row's columns per metre of lateral offset (a residual in metres there, × this,
/// is one in pixels: rows weigh by their ground resolution).
struct GroundEdge {
  double x, y, side, px_per_m;
  int v;
};

/// The residuals (pixels) of edges from the road of centre line `arc` and width w, and with `jac`
/// their derivatives by (y0, θ, κ).
double edgeResidual(const GroundArc& arc, double w, const GroundEdge& e, double c, double s, Vec3* jac = nullptr) {
  const double r = (arc.offset(e.x, e.y, c, s, jac) - 0.5 * e.side * w) * e.px_per_m;
  if (jac != nullptr) *jac *= e.px_per_m;
  return r;
}

/// Robust Gauss-Newton (Huber weights, `huber` pixels) of the arc's y0, θ and, when `curved`, κ (else
/// κ stays as it is) to the edges. False when there are fewer than `per_parameter` edges per parameter
/// or the system is singular.
bool fitGroundArc(const std::vector<GroundEdge>& edges, double w, bool curved, double huber, GroundArc& arc,
                  int per_parameter = 4) {
  const int m = curved ? 3 : 2;
  if (static_cast<int>(edges.size()) < per_parameter * m) return false;
  for (int it = 0; it < 10; ++it) {
    const double c = std::cos(arc.th), s = std::sin(arc.th);
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Vec3 g = Vec3::Zero(), J;
    for (const GroundEdge& e : edges) {
      const double r = edgeResidual(arc, w, e, c, s, &J);
      const double wt = std::abs(r) <= huber ? 1.0 : huber / std::abs(r);
      A += wt * J * J.transpose();
      g += wt * r * J;
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(A.topLeftCorner(m, m));
    if (ldlt.info() != Eigen::Success) return false;
    Vec3 delta = Vec3::Zero();
    delta.head(m) = -ldlt.solve(g.head(m));
    if (!delta.allFinite()) return false;
    arc.y0 += delta[0];
    arc.th += delta[1];
    arc.k += delta[2];
    if (std::abs(delta[0]) < 1e-5 && std::abs(delta[1]) < 1e-6 && std::abs(delta[2]) < 1e-7) break;
  }
  return std::isfinite(arc.y0) && std::abs(arc.th) < 1.4 && std::isfinite(arc.k);
}

/// Σ r² of the edges (pixels²).
double sumSquares(const std::vector<GroundEdge>& edges, double w, const GroundArc& arc) {
  const double c = std::cos(arc.th), s = std::sin(arc.th);
  double sum = 0;
  for (const GroundEdge& e : edges) sum += std::pow(edgeResidual(arc, w, e, c, s), 2);
  return sum;
}

/// How many rows' left and right edges (each at most once) have a candidate within `tol` pixels of the
/// road of centre line `arc` and width w.
int groundSupport(const std::vector<GroundEdge>& edges, double w, const GroundArc& arc, double tol) {
  const double c = std::cos(arc.th), s = std::sin(arc.th);
  return rowSideSupport(
      edges, [](const GroundEdge& e) { return e.side > 0; },
      [&](const GroundEdge& e) { return std::abs(edgeResidual(arc, w, e, c, s)) <= tol; });
}

/// The vehicle stands on the road: the centre line passes within half the road's width w of it
/// (|y0| ≤ w/2 at x = 0). A hard physical constraint on every fit, not a pull toward any answer: a
/// circle through one shoulder's edges (the dirt/grass boundary 2.5 m out, or a single edge taken for
/// the other side's) that puts the vehicle off its road is not the road.
bool onRoad(const GroundArc& arc, double w) { return std::abs(arc.y0) <= 0.5 * w; }

/// Edge consensus on the ground (RANSAC, seeded): the circle whose road edges pass exactly through three
/// edge candidates in rows at least 16 apart (Gauss-Newton from the ground parabola y = y0 + t·x + c·x²/2
/// through them, each moved half the width to the centre: θ = atan t, κ = c·cos³θ), kept when more
/// rows' edges (and `carried` edges of earlier frames) lie within 2 px of it than of `start` (up to
/// 1000 draws). The image's consensus fits a parabola in the image, which on 15 m bends misses the far
/// edges by more than its tolerance, so that the refinement from it can lock onto a few stray edges;
/// this one finds where most of the road's edges are.
GroundArc groundConsensus(const std::vector<GroundEdge>& edges, const std::vector<GroundEdge>& carried, double w,
                          const GroundArc& start, double max_curvature, std::uint64_t seed) {
  constexpr double tol = 2.0;
  const auto support = [&](const GroundArc& h) {
    const double c = std::cos(h.th), s = std::sin(h.th);
    int n = groundSupport(edges, w, h, tol);
    for (const GroundEdge& e : carried) n += std::abs(edgeResidual(h, w, e, c, s)) <= tol;
    return n;
  };
  GroundArc best = start;
  int best_n = onRoad(start, w) ? support(start) : -1;
  if (edges.size() < 3) return best;
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, edges.size() - 1);
  // At most kMaxDraws draws, fewer when the draws needed for 99.9 % confidence (from the best support
  // so far) are fewer. On a bend the camera may see the road's outer edge alone, on 60 of 200
  // candidates' rows and only beyond 10 m: three of them 16 rows apart come in about one draw in 100,
  // and 300 draws missed the circle on 5 of 88 frames of true 15-20 m circles.
  constexpr int kMaxDraws = 1000;
  int needed = kMaxDraws;
  std::vector<GroundEdge> three(3);
  for (int it = 0; it < std::min(kMaxDraws, needed); ++it) {
    Eigen::Matrix3d A;
    Vec3 rhs;
    std::array<int, 3> rows{};
    bool ok = true;
    for (int k = 0; k < 3 && ok; ++k) {
      const GroundEdge& e = edges[pick(rng)];
      three[static_cast<std::size_t>(k)] = e;
      for (int j = 0; j < k; ++j) ok = ok && std::abs(e.v - rows[static_cast<std::size_t>(j)]) >= 16;
      rows[static_cast<std::size_t>(k)] = e.v;
      A.row(k) = Vec3(1.0, e.x, 0.5 * e.x * e.x).transpose();
      rhs[k] = e.y - 0.5 * e.side * w;
    }
    if (!ok) continue;
    const Vec3 p = A.partialPivLu().solve(rhs);
    if (!p.allFinite()) continue;
    GroundArc h;
    h.y0 = p[0];
    h.th = std::atan(p[1]);
    h.k = p[2] * std::pow(std::cos(h.th), 3);
    if (!fitGroundArc(three, w, true, std::numeric_limits<double>::infinity(), h, 1) || std::abs(h.k) > max_curvature ||
        !onRoad(h, w))
      continue;
    const int n = support(h);
    if (n > best_n) {
      best_n = n;
      best = h;
      const double frac = std::min(0.99, static_cast<double>(n) / static_cast<double>(edges.size() + carried.size()));
      needed = static_cast<int>(std::ceil(std::log(0.001) / std::log(1.0 - std::pow(frac, 3))));
    }
  }
  return best;
}

/// The camera's per-row geometry for the arc model (ClusterPerceptron::setCamera()).
struct RowGeometry {
  const std::vector<double>& x;  // ground distance, m
  const std::vector<double>& a;  // column of lateral offset 0
  const std::vector<double>& b;  // columns per metre of lateral offset
};

/// The bootstrap's road width on the ground, m (a flat road of constant width: its rows agree, the
/// median is taken); 0 when no row from v_top has a width.
double groundWidth(const RowGeometry& rows, const std::vector<double>& row_widths, int v_top, int height) {
  std::vector<double> ws;
  for (int v = v_top; v < height; ++v)
    if (row_widths[v] > 0) ws.push_back(row_widths[v] / std::abs(rows.b[v]));
  if (ws.empty()) return 0.0;
  std::nth_element(ws.begin(), ws.begin() + ws.size() / 2, ws.end());
  return ws[ws.size() / 2];
}

/// An image centre model taken to the ground: its centre columns from v_top down, fitted by
/// y = y0 + t·x + c·x²/2, then by the circle (on 15 m bends the parabola's curvature at x = 0 puts
/// the far edges tens of pixels off). False when the fit is singular.
bool groundCircleOf(const CentreModel& model, const RowGeometry& rows, int v_top, int height, double max_curvature,
                    GroundArc& arc) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Vec3 rhs = Vec3::Zero();
  for (int v = v_top; v < height; v += 4) {
    const Vec3 phi(1.0, rows.x[v], 0.5 * rows.x[v] * rows.x[v]);
    A += phi * phi.transpose();
    rhs += phi * ((model.u(v) - rows.a[v]) / rows.b[v]);
  }
  const Vec3 p = A.ldlt().solve(rhs);
  if (!p.allFinite()) return false;
  arc.y0 = p[0];
  arc.th = std::atan(p[1]);
  arc.k = std::clamp(p[2] * std::pow(std::cos(arc.th), 3), -max_curvature, max_curvature);
  std::vector<GroundEdge> centre;
  for (int v = v_top; v < height; v += 4)
    centre.push_back({rows.x[v], (model.u(v) - rows.a[v]) / rows.b[v], 0.0, std::abs(rows.b[v]), v});
  GroundArc circle = arc;
  if (fitGroundArc(centre, 0.0, true, std::numeric_limits<double>::infinity(), circle) && std::abs(circle.k) <= max_curvature)
    arc = circle;
  return true;
}

/// The standard error (pixels) of the column of `arc` at row v when fitted by least squares to `sel`,
/// each edge off by its pixel quantisation alone (uniform over one pixel: σ² = 1/12 px²): gᵀ(JᵀJ)⁻¹g/12,
/// J the edges' residual derivatives (pixels) by y0, θ and, on a circle, κ, and g the column's.
double bottomColumnSd(const std::vector<GroundEdge>& sel, double w, const GroundArc& arc, const RowGeometry& rows,
                      int v) {
  const int m = arc.k != 0.0 ? 3 : 2;
  const double c = std::cos(arc.th), s = std::sin(arc.th);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m, m);
  Vec3 J;
  for (const GroundEdge& e : sel) {
    edgeResidual(arc, w, e, c, s, &J);
    A += J.head(m) * J.head(m).transpose();
  }
  // The column's derivatives, numerically (at() is the closed form of the centre line's offset).
  const double x = rows.x[v], h = 1e-7, y = arc.at(x);
  Eigen::VectorXd g(m);
  for (int k = 0; k < m; ++k) {
    GroundArc p = arc;
    (k == 0 ? p.y0 : k == 1 ? p.th : p.k) += h;
    g[k] = (p.at(x) - y) / h * std::abs(rows.b[v]);
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(A);
  if (ldlt.info() != Eigen::Success || !std::isfinite(y)) return std::numeric_limits<double>::infinity();
  const Eigen::VectorXd ag = ldlt.solve(g);
  return std::sqrt(std::max(0.0, g.dot(ag)) / 12.0);
}

/// The arc model's edge refinement on the ground. The edge candidates of every road row taken to the
/// ground, the circle fitted to them by robust Gauss-Newton (in each row the left and right candidates
/// nearest the model's edges, within a tolerance that narrows from 4 to 1 px; the width from the rows
/// where both edges show, else the bootstrap's), from two starts: the circle nearest the image fit's
/// (`model`, a ground parabola) and the ground consensus's (groundConsensus()); the one that ends with
/// more edges wins; a fit that puts the vehicle off the road (onRoad()) does not count. Earlier frames'
/// edges (`carried`, row −1: ClusterPerceptronOptions::carry_frames) join every selection and the
/// consensus's support where they lie within the tolerance, each as one row side's edge. Then the
/// straight line fitted to the same edges, kept when the curvature does not pay for its parameter (BIC:
/// n ln(RSS/n) + p ln n) and it keeps the vehicle on the road. False when too few edges support either
/// fit. `used`: the winning fit's edges (this frame's, with their rows, and the carried ones it kept).
bool refineGroundArc(const std::uint8_t* cimg, const std::uint8_t* rgb, int width, int height, int v_top,
                     const CentreModel& model, const RowGeometry& rows, const std::vector<double>& row_widths,
                     double max_curvature, std::uint64_t seed, const std::vector<GroundEdge>& carried, GroundArc& arc,
                     int& edge_rows, double& bottom_sd, std::vector<GroundEdge>& used) {
  const double w0 = groundWidth(rows, row_widths, v_top, height);
  if (!(w0 > 0) || !groundCircleOf(model, rows, v_top, height, max_curvature, arc)) return false;
  std::vector<GroundEdge> all;
  std::vector<EdgeCandidate> cands;
  for (int v = v_top; v < height; ++v) {
    cands.clear();
    rowCandidates(cimg + static_cast<std::size_t>(v) * width, width, v, 0, width, cands);
    for (const EdgeCandidate& e : cands) {
      const double u =
          rgb != nullptr ? subpixelEdge(rgb + static_cast<std::size_t>(v) * width * 3, static_cast<int>(e.u + 0.5)) : e.u;
      all.push_back({rows.x[v], (u - rows.a[v]) / rows.b[v], e.left ? 1.0 : -1.0, std::abs(rows.b[v]), v});
    }
  }
  // The refinement from a start: in each row and side the candidate nearest the model's edge, within
  // a tolerance that narrows, and the circle fitted to them; false when too few edges support it.
  std::vector<int> best(2 * static_cast<std::size_t>(height), -1);
  std::vector<double> best_r(2 * static_cast<std::size_t>(height));
  const auto refine = [&](GroundArc& arc, double& w, std::vector<GroundEdge>& sel, int& rows_used) {
    for (const double tol : {4.0, 2.5, 1.5, 1.0}) {
      // In each row and side, the candidate nearest the model's edge, within the tolerance.
      std::fill(best.begin(), best.end(), -1);
      const double c = std::cos(arc.th), s = std::sin(arc.th);
      for (std::size_t i = 0; i < all.size(); ++i) {
        const double r = std::abs(edgeResidual(arc, w, all[i], c, s));
        const std::size_t slot = 2 * static_cast<std::size_t>(all[i].v) + (all[i].side > 0 ? 0 : 1);
        if (r <= tol && (best[slot] < 0 || r < best_r[slot])) {
          best[slot] = static_cast<int>(i);
          best_r[slot] = r;
        }
      }
      sel.clear();
      rows_used = 0;
      std::vector<double> widths;  // the rows where both edges show: their offsets' difference
      for (int v = v_top; v < height; ++v) {
        const int l = best[2 * static_cast<std::size_t>(v)], r = best[2 * static_cast<std::size_t>(v) + 1];
        rows_used += l >= 0 || r >= 0;
        if (l >= 0) sel.push_back(all[static_cast<std::size_t>(l)]);
        if (r >= 0) sel.push_back(all[static_cast<std::size_t>(r)]);
        if (l >= 0 && r >= 0) {
          const GroundEdge &el = all[static_cast<std::size_t>(l)], &er = all[static_cast<std::size_t>(r)];
          widths.push_back(arc.offset(el.x, el.y, c, s) - arc.offset(er.x, er.y, c, s));
        }
      }
      if (widths.size() >= 8) {
        std::nth_element(widths.begin(), widths.begin() + widths.size() / 2, widths.end());
        w = std::clamp(widths[widths.size() / 2], 0.8 * w0, 1.25 * w0);
      }
      // Earlier frames' edges (v < 0) near the model's edges, as they are: each was one row side's.
      for (const GroundEdge& e : carried)
        if (std::abs(edgeResidual(arc, w, e, c, s)) <= tol) sel.push_back(e);
      GroundArc fitted = arc;
      if (!fitGroundArc(sel, w, true, 0.6, fitted)) return false;
      if (std::abs(fitted.k) > max_curvature) {
        // Beyond the searched range: the line part with the curvature at its bound.
        fitted = arc;
        fitted.k = std::clamp(fitted.k, -max_curvature, max_curvature);
        if (!fitGroundArc(sel, w, false, 0.6, fitted)) return false;
      }
      arc = fitted;
    }
    return true;
  };
  // From the image fit's circle, and from the ground consensus's (which has to beat the first's
  // refined circle); the one that ends with more edges wins.
  double w = w0;
  int rows_used = 0;
  std::vector<GroundEdge> sel;
  bool ok = refine(arc, w, sel, rows_used) && onRoad(arc, w);
  GroundArc arc2 = groundConsensus(all, carried, w0, arc, max_curvature, seed);
  double w2 = w0;
  int rows2 = 0;
  std::vector<GroundEdge> sel2;
  const bool ok2 = refine(arc2, w2, sel2, rows2) && onRoad(arc2, w2);
  if (ok2 && (!ok || sel2.size() > sel.size())) {
    arc = arc2;
    w = w2;
    rows_used = rows2;
    sel.swap(sel2);
    ok = true;
  }
  if (!ok) return false;
  GroundArc line = arc;
  line.k = 0;
  if (fitGroundArc(sel, w, false, 0.6, line) && onRoad(line, w)) {
    const double n = static_cast<double>(sel.size());
    const double bic_arc = n * std::log(sumSquares(sel, w, arc) / n + 1e-12) + 3.0 * std::log(n);
    const double bic_line = n * std::log(sumSquares(sel, w, line) / n + 1e-12) + 2.0 * std::log(n);
    if (bic_line <= bic_arc) arc = line;
  }
  edge_rows = rows_used;
  bottom_sd = bottomColumnSd(sel, w, arc, rows, height - 1);
  used.swap(sel);
  return true;
}

}  // namespace

RoadFinding ClusterPerceptron::find(const std::uint8_t* rgb, int width, int height, bool want_mask,
                                    const std::optional<Segment2>& prior) const {
  RoadFinding res;
  if (!trained_) {
    res.reason = "not trained";
    return res;
  }
  if (static_cast<int>(row_widths_.size()) != height) {
    res.reason = "frame height differs from the bootstrap frame's";
    return res;
  }
  const int bs = opt_.block_size;
  const int cols = (width + bs - 1) / bs, rows = (height + bs - 1) / bs;
  Scratch& scr = scratch();
  scr.cert.resize(static_cast<std::size_t>(width) * height);
  scr.bsum.assign(static_cast<std::size_t>(cols) * rows, 0);

  // Classification and block certainty, one band of block rows per task: the bands write disjoint
  // rows of the certainty image and of the block sums, so threads do not change the answer.
  std::uint8_t* const cimg = scr.cert.data();
  std::uint32_t* const bsum = scr.bsum.data();
  const std::uint8_t* const lut = lut_.data();
  const std::uint32_t* const sub_offset = sub_offset_.data();
  const std::uint8_t* const sub = sub_.data();
  const bool fast = opt_.fast;
  long long road_px = 0;
  const int nt = std::min(threadCount(opt_.threads), rows);
#pragma omp parallel for num_threads(nt) if (nt > 1) schedule(static) reduction(+ : road_px)
  for (int r = 0; r < rows; ++r) {
    for (int v = r * bs; v < std::min(height, (r + 1) * bs); ++v) {
      const std::uint8_t* p = rgb + static_cast<std::size_t>(v) * width * 3;
      std::uint8_t* c = cimg + static_cast<std::size_t>(v) * width;
      if (fast) {
        classifyRow(p, c, width, lut, sub_offset, sub);
      } else {
        for (int u = 0; u < width; ++u, p += 3) {
          const double y = outputReference(p[0], p[1], p[2]);
          c[u] = certaintyOf(y);
        }
      }
      road_px += blockSums(c, width, bs, bsum + static_cast<std::size_t>(r) * cols);
    }
  }
  if (want_mask) {
    res.mask = Image(width, height, 1);
    for (std::size_t i = 0; i < scr.cert.size(); ++i) res.mask.data[i] = cimg[i] > 127 ? 255 : 0;
  }
  if (static_cast<double>(road_px) < opt_.min_road_fraction * width * height) {
    res.reason = "no road-coloured pixels";
    return res;
  }
  // Signed certainty per block: -127.5..+127.5.
  std::vector<double> sc(scr.bsum.size(), 0.0);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int npx = (std::min(width, (c + 1) * bs) - c * bs) * (std::min(height, (r + 1) * bs) - r * bs);
      sc[static_cast<std::size_t>(r) * cols + c] =
          static_cast<double>(bsum[static_cast<std::size_t>(r) * cols + c]) / (npx * static_cast<double>(kCertaintyMax)) * 255.0 - 127.5;
    }
  // Road rows and their widths in blocks.
  std::vector<int> rr;
  std::vector<double> wb(rows, 0.0);
  for (int r = 0; r < rows; ++r) {
    const int vc = std::min(height - 1, r * bs + bs / 2);
    wb[r] = row_widths_[vc] / bs;
    if (wb[r] >= 1.0) rr.push_back(r);
  }
  if (rr.size() < 2) {
    res.reason = "the bootstrap road outline has fewer than 2 block rows";
    return res;
  }
  // Per-row horizontal summation kernel over an extended column range [-cols, 2 cols), in fixed
  // point (1/1024) so that the Hough's sums are exact integers, in any order, and vectorise.
  const int ext = 3 * cols;
  std::vector<std::int32_t> S(rr.size() * ext, 0);
  std::vector<double> prefix(static_cast<std::size_t>(cols) + 1);
  double max_possible = 0;
  for (std::size_t i = 0; i < rr.size(); ++i) {
    const int r = rr[i];
    prefix[0] = 0;
    for (int c = 0; c < cols; ++c) prefix[c + 1] = prefix[c] + sc[static_cast<std::size_t>(r) * cols + c];
    const int k = std::max(1, static_cast<int>(std::lround(wb[r])));
    max_possible += 127.5 * std::min(k, cols) / k;
    for (int x = 0; x < ext; ++x) {
      const int centre = x - cols;
      const int lo = std::clamp(centre - k / 2, 0, cols), hi = std::clamp(centre - k / 2 + k, 0, cols);
      S[i * ext + x] = roundToInt((prefix[hi] - prefix[lo]) / k * 1024.0);  // rows weigh the same
    }
  }
  // Hough: row i (t from 0 at the top road row to 1 at the bottom one) is shifted by
  // round(s·t + q·g_i) blocks and the columns summed: s the bottom row's shift (the line's angle),
  // q the curvature's step (the arc model, g_i the row's arc offset per step; 0 for the paper's
  // straight trapezoid).
  const int r0 = rr.front(), rl = rr.back();
  const double span = std::max(1, rl - r0);
  std::vector<double> tr(rr.size());
  for (std::size_t i = 0; i < rr.size(); ++i) tr[i] = (rr[i] - r0) / span;
  // Continuous block coordinate X ↔ pixel u = X · bs − 0.5; rows at their block centres.
  CentreModel model;
  model.v0 = r0 * bs + (bs - 1) / 2.0;
  model.v1 = std::max(model.v0 + 1.0, rl * bs + (bs - 1) / 2.0);
  const bool arc = opt_.road_model == RoadModel::Arc;
  const int Q = arc ? opt_.curvature_steps : 0;
  const double dk = opt_.max_curvature / opt_.curvature_steps;  // curvature per step, 1/m
  std::vector<double> gb(rr.size(), 0.0);
  if (arc) {
    if (static_cast<int>(row_x_.size()) != height) {
      res.reason = "the arc model needs the camera (setCamera) of the frame's size";
      return res;
    }
    model.arc = ArcBasis(row_x_, row_b_, model.v0, model.v1);
    for (std::size_t i = 0; i < rr.size(); ++i) gb[i] = dk * model.arc(rr[i] * bs + (bs - 1) / 2.0) / bs;
    for (int v = rr.front() * bs; v < height; ++v)
      if (!std::isfinite(row_x_[v]) || !std::isfinite(row_b_[v])) {
        res.reason = "arc model: the road rows reach the horizon";
        return res;
      }
  }
  const int M = std::min(opt_.max_shift_blocks, 2 * cols);
  std::vector<int> offsets(rr.size() * static_cast<std::size_t>(2 * M + 1) * (2 * Q + 1));
  for (int q = -Q, j = 0; q <= Q; ++q)
    for (int s = -M; s <= M; ++s)
      for (std::size_t i = 0; i < rr.size(); ++i, ++j)
        offsets[j] = roundToInt(s * tr[i] + q * gb[i]);
  // The prior's window: the centre line's columns on the top and the bottom road rows (v0, v1; the
  // arc's offset vanishes on both, so bends do not move them) within prior_px of the prior's.
  const bool windowed = prior && opt_.prior_px > 0 && std::abs(prior->b.y() - prior->a.y()) > 1e-6;
  double prior_top = 0, prior_bottom = 0;
  if (windowed) {
    const auto at = [&](double v) {
      return prior->a.x() + (prior->b.x() - prior->a.x()) * (v - prior->a.y()) / (prior->b.y() - prior->a.y());
    };
    prior_top = at(model.v0);
    prior_bottom = at(model.v1);
  }
  const auto inWindow = [&](double u_top, double u_bottom) {
    return !windowed || (std::abs(u_top - prior_top) <= opt_.prior_px && std::abs(u_bottom - prior_bottom) <= opt_.prior_px);
  };
  // Block coordinate X (continuous) ↔ column X · bs − 0.5; the coarse Hough's line has X = x + 0.5 on
  // the top road row and x + 0.5 + s on the bottom one.
  std::vector<int> x_lo(2 * M + 1, 0), x_hi(2 * M + 1, cols - 1);
  if (windowed) {
    const double wb = opt_.prior_px / bs, top = (prior_top + 0.5) / bs - 0.5, bottom = (prior_bottom + 0.5) / bs - 0.5;
    for (int s = -M; s <= M; ++s) {
      x_lo[s + M] = std::max({0, static_cast<int>(std::ceil(top - wb)), static_cast<int>(std::ceil(bottom - s - wb))});
      x_hi[s + M] = std::min({cols - 1, static_cast<int>(std::floor(top + wb)), static_cast<int>(std::floor(bottom - s + wb))});
    }
  }
  const HoughPeak peak = houghSearch(S.data(), static_cast<int>(rr.size()), cols, offsets.data(), 2 * M + 1, 2 * Q + 1,
                                     x_lo.data(), x_hi.data());
  if (peak.sum == std::numeric_limits<std::int64_t>::min()) {
    res.reason = "no centre line within prior_px of the prior";
    return res;
  }
  const int bx = peak.x, bsft = peak.shift - M, bq = peak.bend - Q;
  const std::int64_t best_fixed = peak.sum;
  const double best = static_cast<double>(best_fixed) / 1024.0;
  res.intercept_col = bx;
  res.shift = bsft;
  // Sub-block refinement: the same Hough sum, with each block's certainty spread evenly over its
  // width and the kernel exactly the row's road width, evaluated at fractional intercepts, shifts
  // (and bends) around the coarse maximum, coarse to fine: half-block steps, then eighth-block steps.
  // The continuous kernel sum is P(x + W/2) − P(x − W/2), P the running integral of the row.
  std::vector<double> P(rr.size() * (static_cast<std::size_t>(cols) + 1), 0.0);
  for (std::size_t i = 0; i < rr.size(); ++i) {
    const double* row = sc.data() + static_cast<std::size_t>(rr[i]) * cols;
    double* pr = P.data() + i * (cols + 1);
    for (int c = 0; c < cols; ++c) pr[c + 1] = pr[c] + row[c];
  }
  auto integral = [&](std::size_t i, double x) {
    const double* pr = P.data() + i * (cols + 1);
    if (x <= 0) return 0.0;
    if (x >= cols) return pr[cols];
    const int c = static_cast<int>(x);
    return pr[c] + (x - c) * (pr[c + 1] - pr[c]);
  };
  auto score = [&](double X, double sft, double bend) {
    double total = 0;
    for (std::size_t i = 0; i < rr.size(); ++i) {
      const double x = X + sft * tr[i] + bend * gb[i], hw = 0.5 * wb[rr[i]];
      total += (integral(i, x + hw) - integral(i, x - hw)) / (2.0 * hw);
    }
    return total;
  };
  // Pattern search: move to the best of the ± step neighbours in each parameter until none is
  // better, then halve the step (0.5 → 0.25 → 0.125 blocks).
  Vec3 f(bx + 0.5, bsft, bq);
  double fbest = score(f[0], f[1], f[2]);
  for (double step = 0.5; step >= 0.125; step /= 2) {
    for (int moves = 0; moves < 32; ++moves) {
      Vec3 next = f;
      for (int d = 0; d < (Q > 0 ? 3 : 2); ++d)
        for (const double sign : {-1.0, 1.0}) {
          Vec3 g = f;
          g[d] += sign * step;
          if (!inWindow(g[0] * bs - 0.5, (g[0] + g[1]) * bs - 0.5)) continue;
          const double val = score(g[0], g[1], g[2]);
          if (val > fbest) {
            fbest = val;
            next = g;
          }
        }
      if (next == f) break;
      f = next;
    }
  }
  const double fx = f[0], fs = f[1], fq = f[2];
  model.p = Vec3(fx * bs - 0.5, fs * bs, arc ? fq * dk : 0.0);
  res.confidence = std::clamp(best / std::max(1.0, max_possible), 0.0, 1.0);

  // Beyond the paper: the Hough answer is good to about a block. Where the road's edges are in the
  // image, find them to the pixel around the Hough line (the step of best correlation, in each row),
  // turn each edge into a centre estimate with the row's road width (scaled by the widths measured
  // where both edges show), and fit the model to those by robust least squares. Twice: the second
  // time in narrower windows around the first fit.
  const int v_top = r0 * bs;
  std::optional<GroundArc> ground;  // the arc model's refined road on the ground
  if (opt_.refine_edges) {
    const int degree = Q > 0 ? 2 : 1;
    // The Hough line counts road-coloured area, which shaded shoulders of road colour can pull; the
    // road's edges are straight and a known width apart, which those shadows' outlines are not.
    // Start from the model that most edge candidates support.
    std::vector<EdgeCandidate> cands;
    for (int v = v_top; v < height; v += 4) rowCandidates(cimg + static_cast<std::size_t>(v) * width, width, v, 0, width, cands);
    model = edgeConsensus(cands, row_widths_, model, degree, opt_.seed, 200, 2.0, opt_.max_curvature,
                          [&](const CentreModel& m) { return inWindow(m.u(m.v0), m.u(m.v1)); });
    if (arc) {
      // The arc model: the circle on the ground, or the line where the curvature does not pay.
      GroundArc g;
      int edge_rows = 0;
      double bottom_sd = 0;
      std::vector<GroundEdge> carried, used;
      for (const auto& frame : carried_)
        for (const RoadEdgePoint& e : frame)
          carried.push_back({e.p.x(), e.p.y(), static_cast<double>(e.side), e.px_per_m, -1});
      if (refineGroundArc(cimg, opt_.subpixel_edges ? rgb : nullptr, width, height, v_top, model,
                          RowGeometry{row_x_, row_a_, row_b_}, row_widths_, opt_.max_curvature, opt_.seed, carried, g,
                          edge_rows, bottom_sd, used)) {
        res.refined = true;
        res.edge_rows = edge_rows;
        res.bottom_column_sd = bottom_sd;
        for (const GroundEdge& e : used) {
          if (e.v < 0) ++res.carried_edges;
          else res.ground_edges.push_back({Vec2(e.x, e.y), e.side > 0 ? 1 : -1, e.px_per_m});
        }
        ground = g;
      }
    }
    // Then fit it to the edges that support it: in each row the left and right candidates nearest
    // the model's edges, each turned into a centre estimate (the pair's middle, or one edge plus half
    // the row's width scaled by the widths measured where both show), by robust least squares; twice,
    // each time with the edges nearer the last fit.
    for (const double tol : {2.0, 1.5, 1.0}) {
      if (ground) break;
      // Every row's candidates near the model's two edges.
      cands.clear();
      for (int v = v_top; v < height; ++v)
        for (const double side : {-0.5, 0.5}) {
          const double want = model.u(v) + side * row_widths_[v];
          if (want < -tol || want > width + tol) continue;
          rowCandidates(cimg + static_cast<std::size_t>(v) * width, width, v, static_cast<int>(std::floor(want - tol)),
                        static_cast<int>(std::ceil(want + tol)) + 1, cands);
        }
      std::vector<double> left(height, std::nan("")), right(height, std::nan(""));
      for (const EdgeCandidate& e : cands) {
        const double want = model.u(e.v) + (e.left ? -0.5 : 0.5) * row_widths_[e.v];
        double& slot = e.left ? left[e.v] : right[e.v];
        if (std::abs(e.u - want) <= tol && !(std::abs(slot - want) <= std::abs(e.u - want))) slot = e.u;
      }
      std::vector<double> ratios;
      for (int v = v_top; v < height; ++v)
        if (!std::isnan(left[v]) && !std::isnan(right[v])) ratios.push_back((right[v] - left[v]) / row_widths_[v]);
      double scale = 1.0;
      if (ratios.size() >= 8) {
        std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
        scale = std::clamp(ratios[ratios.size() / 2], 0.8, 1.25);
      }
      std::vector<Vec2> vu;
      for (int v = v_top; v < height; ++v) {
        const double hw = 0.5 * scale * row_widths_[v];
        const bool l = !std::isnan(left[v]), r = !std::isnan(right[v]);
        if (l && r) vu.emplace_back(v, 0.5 * (left[v] + right[v]));
        else if (l) vu.emplace_back(v, left[v] + hw);
        else if (r) vu.emplace_back(v, right[v] - hw);
      }
      CentreModel fitted = model;
      // The arc's curvature within the searched range; else the line part with the curvature kept.
      if (!fitCentreModel(vu, degree, 0.6, fitted)) break;
      if (degree == 2 && std::abs(fitted.p[2]) > opt_.max_curvature) {
        fitted = model;
        if (!fitCentreModel(vu, 1, 0.6, fitted)) break;
      }
      model = fitted;
      res.refined = true;
      res.edge_rows = static_cast<int>(vu.size());
    }
  }
  if (arc && !ground) {
    // No ground fit: the image fit stands, unless its centre line, taken to the ground, passes
    // farther than half the road's width from the vehicle, which stands on the road (onRoad()): then
    // the road-coloured area holds no road the vehicle could be on (shoulders classed as road, no
    // edge of the road in view), and the frame fails rather than steer by it.
    const RowGeometry geo{row_x_, row_a_, row_b_};
    const double w0 = groundWidth(geo, row_widths_, v_top, height);
    GroundArc g;
    if (w0 > 0 && groundCircleOf(model, geo, v_top, height, opt_.max_curvature, g) && !onRoad(g, w0)) {
      res.reason = "arc model: no centre line within half the road's width of the vehicle";
      return res;
    }
  }
  res.centerline_curve.clear();
  for (int v = v_top;; v = std::min(height - 1, v + bs)) {
    if (!ground) {
      res.centerline_curve.emplace_back(model.u(v), v);
    } else if (const double y = ground->at(row_x_[v]); std::isfinite(y)) {
      res.centerline_curve.emplace_back(row_a_[v] + row_b_[v] * y, v);
    }
    if (v >= height - 1) break;
  }
  if (res.centerline_curve.size() < 2) {
    res.reason = "arc model: the circle turns back above the bottom rows";
    return res;
  }
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

// --- Grey frames -----------------------------------------------------------------------------------

Image greyTextureFeatures(const std::uint8_t* rgb, int width, int height, int window) {
  if (rgb == nullptr || width <= 0 || height <= 0) throw InvalidInput("greyTextureFeatures: empty frame");
  if (window < 3 || window > 63 || window % 2 == 0)
    throw InvalidInput("greyTextureFeatures: window " + std::to_string(window) + " is not odd in [3, 63]");
  cv::Mat grey(height, width, CV_32F);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) grey.at<float>(v, u) = rgb[3 * (static_cast<std::size_t>(v) * width + u)];
  const cv::Size box(window, window);
  cv::Mat mean, mean_sq, lap, grain;
  cv::blur(grey, mean, box, cv::Point(-1, -1), cv::BORDER_REPLICATE);
  cv::blur(grey.mul(grey), mean_sq, box, cv::Point(-1, -1), cv::BORDER_REPLICATE);
  cv::Laplacian(grey, lap, CV_32F, 1, 1.0, 0.0, cv::BORDER_REPLICATE);
  cv::blur(cv::abs(lap), grain, box, cv::Point(-1, -1), cv::BORDER_REPLICATE);
  Image out(width, height, 3);
  auto level = [](double x) { return static_cast<std::uint8_t>(std::clamp(std::lround(x), 0L, 255L)); };
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const double m = mean.at<float>(v, u);
      const double sd = std::sqrt(std::max(0.0, mean_sq.at<float>(v, u) - m * m));
      std::uint8_t* p = out.pixel(u, v);
      p[0] = level(m);
      p[1] = level(4.0 * grain.at<float>(v, u));
      p[2] = level(4.0 * sd);
    }
  return out;
}

// --- The "cluster-perceptron" pipeline ----------------------------------------------------------------

namespace {

/// The centre line of a road outline mask: the middle of each row's extent, over the rows whose extent
/// does not touch the image's sides (a clipped row's middle is not the road's), fitted by a line
/// (least squares); nothing when fewer than 8 rows qualify.
std::optional<Segment2> maskCentreLine(const Image& mask) {
  std::vector<Vec2> vu;
  for (int v = 0; v < mask.height; ++v) {
    int lo = mask.width, hi = -1;
    for (int u = 0; u < mask.width; ++u)
      if (mask.pixel(u, v)[0] != 0) {
        lo = std::min(lo, u);
        hi = std::max(hi, u);
      }
    if (hi >= 0 && lo > 0 && hi < mask.width - 1) vu.emplace_back(v, 0.5 * (lo + hi));
  }
  if (vu.size() < 8) return std::nullopt;
  CentreModel line;
  line.v0 = vu.front().x();
  line.v1 = std::max(line.v0 + 1.0, vu.back().x());
  if (!fitCentreModel(vu, 1, std::numeric_limits<double>::max(), line)) return std::nullopt;
  return Segment2{Vec2(line.u(line.v0), line.v0), Vec2(line.u(line.v1), line.v1)};
}

}  // namespace

const OptionTable<ClusterPerceptronPipelineOptions>& clusterPerceptronPipelineOptionTable() {
  using O = ClusterPerceptronPipelineOptions;
  static const OptionTable<O> table =
      OptionTable<O>("ClusterPerceptronPipelineOptions")
          .field("clusters", &O::clusters, inRange(1, 30), "colour clusters (competitive learning units), 1..30")
          .field("seed", &O::seed, inRange(0, 1e15), "seed of the random initial cluster means")
          .field("max_cluster_iterations", &O::max_cluster_iterations, inRange(1, 1000), "clustering iterations at most")
          .field("cluster_slope_threshold", &O::cluster_slope_threshold, inRange(0, 1e9),
                 "clustering stops when every band's mean squared reconstruction error changes by less than this "
                 "(levels^2)")
          .field("max_perceptron_iterations", &O::max_perceptron_iterations, inRange(1, 1e6),
                 "perceptron LMS iterations at most")
          .field("perceptron_rate", &O::perceptron_rate, inRange(1e-9, 100), "perceptron LMS learning rate")
          .field("perceptron_tolerance", &O::perceptron_tolerance, inRange(0, 1),
                 "perceptron training stops when the mean error changes by less")
          .field("train_stride", &O::train_stride, inRange(1, 64), "training uses every n-th pixel in each direction")
          .field("block_size", &O::block_size, inRange(1, 256), "side of a road-certainty block, pixels")
          .field("max_shift_blocks", &O::max_shift_blocks, inRange(0, 1024),
                 "Hough: largest shift of the bottom road row, blocks")
          .field("trapezoid_top", &O::trapezoid_top, inRange(0, 0.999),
                 "default bootstrap trapezoid (no predicted road): top row, fraction of the height")
          .field("trapezoid_top_width", &O::trapezoid_top_width, inRange(1e-6, 10),
                 "default trapezoid: top width, fraction of the image width")
          .field("trapezoid_bottom_width", &O::trapezoid_bottom_width, inRange(1e-6, 10),
                 "default trapezoid: bottom width, fraction of the image width")
          .computed(
              "arc", [](const O& o) { return o.road_model == RoadModel::Arc; },
              [](O& o, bool arc) { o.road_model = arc ? RoadModel::Arc : RoadModel::Line; },
              "beyond the paper (9): the Hough searches ground arcs y = y0 + theta x + kappa x^2 / 2 too, so that "
              "curves are not cut")
          .field("max_curvature", &O::max_curvature, inRange(1e-6, 1), "arc model: largest curvature searched, 1/m")
          .field("curvature_steps", &O::curvature_steps, inRange(1, 100),
                 "arc model: curvatures tried on each side of 0 before refining")
          .field("subpixel_edges", &O::subpixel_edges,
                 "arc model: each road edge placed within its pair of pixels by their colours (for cameras that "
                 "integrate over the pixel)")
          .field("adaptive", &O::adaptive,
                 "beyond the paper (9): add clusters for new colours, move them and retrain the perceptron when a "
                 "frame's reconstruction error exceeds adaptive_error_ratio x the recent frames' median, "
                 "bootstrapped from the last trusted road")
          .field("adaptive_error_ratio", &O::adaptive_error_ratio, inRange(1.000001, 1e6),
                 "adaptive: retrain above this multiple of the recent frames' median error")
          .field("adaptive_stride", &O::adaptive_stride, inRange(1, 64),
                 "adaptive: the reconstruction error uses every n-th pixel each way")
          .field("adaptive_window", &O::adaptive_window, inRange(1, 1000),
                 "adaptive: the reference is the median error of this many recent frames")
          .field("adaptive_max_clusters", &O::adaptive_max_clusters, inRange(1, 30),
                 "adaptive: clusters at most after additions")
          .field("refine_edges", &O::refine_edges,
                 "beyond the paper: refine the Hough centre line to the pixel from the road edges (robust fit)")
          .field("raw_rgb", &O::raw_rgb,
                 "beyond the paper (9): the perceptron's inputs are the pixel's R, G, B instead of the clusters' "
                 "winner code")
          .field("normalized_color", &O::normalized_color,
                 "beyond the paper (Wallace et al. 1985, 3.4.3): clusters and perceptron see (R, G, B) / (R + G + "
                 "B), which a shadow (C1 = k C2) does not change, so that shaded grass is not taken for asphalt; "
                 "brightness is lost")
          .field("balance_classes", &O::balance_classes,
                 "beyond the paper: the bootstrap weighs the road (inside the outline) and the rest equally, for "
                 "frames where the road is a small part")
          .field("threads", &O::threads, inRange(0, 256),
                 "runtime threads (0 = every core); the answer does not depend on it")
          .field("fast", &O::fast,
                 "runtime through a 32x32x32 colour lookup table (exact: boundary cells are classified per pixel); "
                 "false = per-pixel reference path")
          .field("min_road_fraction", &O::min_road_fraction, inRange(0, 1),
                 "fewer road pixels than this fraction of the frame: Failed")
          .field("grey_features", &O::grey_features,
                 "beyond the paper: a grey frame (R = G = B everywhere) is clustered on (local mean, 4 x mean "
                 "|Laplacian|, 4 x local standard deviation) instead of (R, G, B), so that texture can separate "
                 "asphalt from grass and paving; colour frames are not affected")
          .field("texture_window", &O::texture_window, oddIn(inRange(3, 63)),
                 "grey_features: side of the box of the local mean, Laplacian and deviation, pixels (odd)")
          .field("prior_px", &O::prior_px, inRange(0, 1e6),
                 "beyond the paper: the Hough and the edge consensus keep to centre lines whose columns on the top "
                 "and bottom road rows are within this many pixels of the predicted road's centre line (the middle "
                 "of the prediction's road region, row by row); 0 = the whole image (the paper)")
          .preset("park-shadows", R"({"arc": true, "normalized_color": true, "clusters": 8})",
                  "park paths with bends and tree shadows: the arc model, so that bends are not cut, in normalised "
                  "colour, which a shadow does not change, with the 8 clusters that normalised colour needs to part "
                  "grass, dirt and asphalt (5 took park_loop's dirt shoulder for road)");
  return table;
}

void ClusterPerceptronPipelineOptions::validate() const {
  clusterPerceptronPipelineOptionTable().validate(*this);
  ClusterPerceptronOptions::validate();
}

namespace {

class ClusterPerceptronPipeline : public VisionPipeline {
 public:
  ClusterPerceptronPipeline() { reset(); }
  std::string name() const override { return "cluster-perceptron"; }
  void configure(const std::string& text) override {
    opts_ = clusterPerceptronPipelineOptionTable().parse(text, opts_, "pipeline \"cluster-perceptron\"");
    reset();
  }
  void reset() override { finder_ = ClusterPerceptron(opts_); }

  DetectedObject detect(const VisionFrame& frame, const PredictedObject& prediction) override {
    if (frame.camera == nullptr) throw InvalidInput("pipeline \"cluster-perceptron\": the frame has no camera");
    if (frame.rgb == nullptr || frame.width <= 0 || frame.height <= 0)
      throw InvalidInput("pipeline \"cluster-perceptron\": the frame has no pixels");
    if (frame.width != frame.camera->width() || frame.height != frame.camera->height())
      throw InvalidInput("pipeline \"cluster-perceptron\": frame size differs from the camera's image size");
    const Camera& cam = *frame.camera;
    const int w = frame.width, h = frame.height;
    // Grey frames: texture features in place of the colours (both runtime paths see the same image).
    Image features;
    const std::uint8_t* pixels = frame.rgb;
    if (opts_.grey_features && isGreyFrame(frame.rgb, w, h)) {
      features = greyTextureFeatures(frame.rgb, w, h, opts_.texture_window);
      pixels = features.data.data();
    }
    if (!finder_.trained() || static_cast<int>(finder_.rowWidths().size()) != h) {
      // Bootstrap (§4): the predicted road outline, else the default trapezoid.
      Image outline = predictedRoadMask(prediction, cam);
      std::size_t count = 0;
      for (std::uint8_t m : outline.data) count += m != 0;
      if (count < 100) {
        const double top = opts_.trapezoid_top * h, tw = opts_.trapezoid_top_width * w,
                     bw = opts_.trapezoid_bottom_width * w, cx = (w - 1) / 2.0;
        outline = fillPolygonMask({{Vec2(cx - tw / 2, top), Vec2(cx + tw / 2, top), Vec2(cx + bw / 2, h - 1.0),
                                    Vec2(cx - bw / 2, h - 1.0)}},
                                  w, h);
      }
      ClusterPerceptronOptions o = opts_;
      // Grey frames' texture features are not colours: normalised, their texture would be gone.
      if (pixels != frame.rgb) o.normalized_color = false;
      finder_ = ClusterPerceptron(o);
      finder_.trainClusters(pixels, w, h);
      finder_.setRowWidths(trapezoidRowWidths(outline));
      finder_.setCamera(cam);
      finder_.trainPerceptron(pixels, w, h, outline.data.data());
    }
    std::optional<Segment2> prior;
    if (opts_.prior_px > 0) prior = maskCentreLine(predictedRoadMask(prediction, cam));
    const RoadFinding f = finder_.track(pixels, w, h, false, prior);
    if (!f.ok) {
      DetectedObject d = DetectedObject::failed(f.reason);
      d.timestamp = frame.timestamp;
      return d;
    }
    DetectedObject d;
    d.timestamp = frame.timestamp;
    d.confidence = f.confidence;
    // The road region: the bootstrap trapezoid's widths around the centre line (the arc model's
    // curve), clipped to the image.
    const Segment2& cl = f.centerline_image;
    std::vector<Vec2> centre;
    if (opts_.road_model == RoadModel::Arc) {
      centre = f.centerline_curve;
    } else {
      const double v0 = cl.a.y(), v1 = cl.b.y();
      const int steps = 16;
      for (int k = 0; k <= steps; ++k) {
        const double v = v0 + (v1 - v0) * k / steps;
        const double t = (v - v0) / std::max(1e-9, v1 - v0);
        centre.emplace_back(cl.a.x() + t * (cl.b.x() - cl.a.x()), v);
      }
    }
    d.region_image = roadBand(centre, finder_.rowWidths(), w);
    Polygon2 rv;
    for (const Vec2& p : d.region_image)
      if (const auto g = cam.backproject(p)) rv.push_back(*g);
    if (rv.size() == d.region_image.size()) d.region_vehicle = rv;
    // The centre line on the ground: its far end moved down to the first row below the horizon.
    std::optional<Vec2> ga, gb = cam.backproject(cl.b);
    for (int k = 0; k <= 64 && !ga; ++k) ga = cam.backproject(cl.a + (cl.b - cl.a) * (k / 64.0));
    if (ga && gb) d.centerline_vehicle = Segment2{*ga, *gb};
    return d;
  }

 private:
  ClusterPerceptronPipelineOptions opts_;
  ClusterPerceptron finder_;
};

}  // namespace

std::unique_ptr<VisionPipeline> createClusterPerceptronPipeline() {
  return std::make_unique<ClusterPerceptronPipeline>();
}

}  // namespace mapnav
