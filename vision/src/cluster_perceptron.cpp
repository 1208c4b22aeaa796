// Jochem & Baluja 1993: colour clustering by competitive learning, a perceptron combiner and a
// Hough road finder over (top-row intercept column × angle). See cluster_perceptron.h.
#include "mapnav/vision/cluster_perceptron.h"

#include "pipeline_options.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

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
  requireOption(min_road_fraction >= 0 && min_road_fraction <= 1, o, "min_road_fraction", min_road_fraction,
                "in [0, 1]");
}

ClusterPerceptron::ClusterPerceptron(ClusterPerceptronOptions options) : opt_(std::move(options)) { opt_.validate(); }

int ClusterPerceptron::nearest(float r, float g, float b) const {
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
  means_.assign(static_cast<std::size_t>(n), Vec3::Zero());
  for (Vec3& m : means_) m = Vec3(uni(rng), uni(rng), uni(rng));
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
        const int k = nearest(p[0], p[1], p[2]);
        const double er = p[0] - means_[k].x(), eg = p[1] - means_[k].y(), eb = p[2] - means_[k].z();
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
  return history;
}

Image ClusterPerceptron::reconstruct(const std::uint8_t* rgb, int width, int height) const {
  Image out(width, height, 3);
  if (means_.empty()) return out;
  for (std::size_t i = 0; i < static_cast<std::size_t>(width) * height; ++i) {
    const int k = nearest(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
    for (int c = 0; c < 3; ++c)
      out.data[3 * i + c] = static_cast<std::uint8_t>(std::clamp(std::lround(means_[k][c]), 0L, 255L));
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
std::uint8_t certaintyOf(double y) { return static_cast<std::uint8_t>(std::lround((y + 1.0) * 127.0)); }
constexpr std::uint8_t kAmbiguous = 255;  // LUT cell spanning a cluster boundary: classify exactly
}  // namespace

std::vector<double> ClusterPerceptron::trainPerceptron(const std::uint8_t* rgb, int width, int height,
                                                       const std::uint8_t* road) {
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
  weights_.assign(static_cast<std::size_t>(n) + 1, 0.0);
  std::vector<double> history;
  double prev = std::numeric_limits<double>::max();
  int calm = 0;
  for (int it = 0; it < opt_.max_perceptron_iterations; ++it) {
    std::vector<double> grad(static_cast<std::size_t>(n) + 1, 0.0);
    double err = 0;
    for (int k = 0; k < n; ++k) {
      const double y = std::tanh(netFor(weights_, k));
      const double e = pos[k] * (1.0 - y) + neg[k] * (-1.0 - y);  // Σ (target − output)
      err += pos[k] * std::abs(1.0 - y) + neg[k] * std::abs(-1.0 - y);
      for (int j = 0; j < n; ++j) grad[j] += e * (j == k ? 1.0 : -1.0);
      grad[n] += e;  // bias input 1
    }
    err /= total;
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

double ClusterPerceptron::outputReference(std::uint8_t r, std::uint8_t g, std::uint8_t b) const {
  return std::tanh(netFor(weights_, nearest(r, g, b)));
}

void ClusterPerceptron::buildLut() {
  // Cell q covers the colours [8q, 8q + 7] per band. A cell whose 8 corners share their nearest
  // cluster lies wholly in that cluster's (convex) Voronoi cell: its certainty is exact. Others are
  // marked ambiguous and classified per pixel, so the fast path equals the reference path.
  const int n = static_cast<int>(means_.size());
  std::vector<std::uint8_t> cert(n);
  for (int k = 0; k < n; ++k) cert[k] = std::min<std::uint8_t>(certaintyOf(std::tanh(netFor(weights_, k))), 254);
  // Nearest cluster of every lattice corner (33 values per band: 8q and 8q + 7 for q < 32).
  auto corner = [](int i) { return i % 2 == 0 ? (i / 2) * 8 : (i / 2) * 8 + 7; };
  std::vector<std::uint8_t> near(64 * 64 * 64);
  for (int a = 0; a < 64; ++a)
    for (int b = 0; b < 64; ++b)
      for (int c = 0; c < 64; ++c)
        near[(a * 64 + b) * 64 + c] = static_cast<std::uint8_t>(
            nearest(static_cast<float>(corner(a)), static_cast<float>(corner(b)), static_cast<float>(corner(c))));
  // Exact test for a cell spanning clusters of equal certainty c: no point of the cube has a cluster j
  // of another certainty as its nearest if, for every such j, some cluster k of certainty c is nearer
  // than j at all 8 corners (the region nearer k than j is a half-space, so the whole cube is).
  auto d2 = [&](int k, double x, double y, double z) {
    return (means_[k] - Vec3(x, y, z)).squaredNorm();
  };
  auto uniform = [&](int r, int g, int b, std::uint8_t c) {
    for (int j = 0; j < n; ++j) {
      if (cert[j] == c) continue;
      bool excluded = false;
      for (int k = 0; k < n && !excluded; ++k) {
        if (cert[k] != c) continue;
        excluded = true;
        for (int m = 0; m < 8 && excluded; ++m) {
          const double x = corner(2 * r + (m & 1)), y = corner(2 * g + ((m >> 1) & 1)),
                       z = corner(2 * b + ((m >> 2) & 1));
          excluded = d2(k, x, y, z) < d2(j, x, y, z);
        }
      }
      if (!excluded) return false;
    }
    return true;
  };
  lut_.assign(32 * 32 * 32, 0);
  for (int r = 0; r < 32; ++r)
    for (int g = 0; g < 32; ++g)
      for (int b = 0; b < 32; ++b) {
        const int k0 = near[((2 * r) * 64 + 2 * g) * 64 + 2 * b];
        bool same = true;
        for (int m = 1; m < 8 && same; ++m)
          same = near[((2 * r + (m & 1)) * 64 + 2 * g + ((m >> 1) & 1)) * 64 + 2 * b + ((m >> 2) & 1)] == k0;
        if (!same) same = uniform(r, g, b, cert[k0]);
        lut_[(r << 10) | (g << 5) | b] = same ? cert[k0] : kAmbiguous;
      }
}

void ClusterPerceptron::setRowWidths(std::vector<double> widths) {
  row_widths_ = std::move(widths);
  trained_ = !weights_.empty() && !row_widths_.empty();
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

RoadFinding ClusterPerceptron::find(const std::uint8_t* rgb, int width, int height, bool want_mask) const {
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
  // Block road certainty, 0..255 (mean of the pixels' 0..254 certainty, scaled).
  std::vector<std::uint32_t> bsum;
  std::vector<std::uint8_t> pcert;
  bsum.assign(static_cast<std::size_t>(cols) * rows, 0);
  if (want_mask) res.mask = Image(width, height, 1);
  std::size_t road_px = 0;
  const int n = static_cast<int>(means_.size());
  std::array<std::uint8_t, 32> cert{};
  for (int k = 0; k < n; ++k) cert[k] = std::min<std::uint8_t>(certaintyOf(std::tanh(netFor(weights_, k))), 254);
  pcert.resize(static_cast<std::size_t>(width));
  for (int v = 0; v < height; ++v) {
    const std::uint8_t* row = rgb + static_cast<std::size_t>(v) * width * 3;
    if (opt_.fast) {
      const std::uint8_t* lut = lut_.data();
      for (int u = 0; u < width; ++u) {
        const std::uint8_t* p = row + 3 * u;
        std::uint8_t c = lut[((p[0] >> 3) << 10) | ((p[1] >> 3) << 5) | (p[2] >> 3)];
        if (c == kAmbiguous) c = cert[nearest(p[0], p[1], p[2])];
        pcert[u] = c;
      }
    } else {
      for (int u = 0; u < width; ++u) {
        const std::uint8_t* p = row + 3 * u;
        const double y = std::tanh(netFor(weights_, nearest(p[0], p[1], p[2])));
        pcert[u] = std::min<std::uint8_t>(certaintyOf(y), 254);
      }
    }
    std::uint32_t* brow = bsum.data() + static_cast<std::size_t>(v / bs) * cols;
    for (int c = 0; c < cols; ++c) {
      const int u0 = c * bs, u1 = std::min(width, u0 + bs);
      std::uint32_t s = 0;
      for (int u = u0; u < u1; ++u) s += pcert[u];
      brow[c] += s;
    }
    if (want_mask) {
      std::uint8_t* m = res.mask.data.data() + static_cast<std::size_t>(v) * width;
      for (int u = 0; u < width; ++u) m[u] = pcert[u] > 127 ? 255 : 0;
    }
    for (int u = 0; u < width; ++u) road_px += pcert[u] > 127;
  }
  if (static_cast<double>(road_px) < opt_.min_road_fraction * width * height) {
    res.reason = "no road-coloured pixels";
    return res;
  }
  // Signed certainty per block: -127..+128 (0 outside the image).
  std::vector<double> sc;
  sc.assign(bsum.size(), 0.0);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int npx = (std::min(width, (c + 1) * bs) - c * bs) * (std::min(height, (r + 1) * bs) - r * bs);
      sc[static_cast<std::size_t>(r) * cols + c] = static_cast<double>(bsum[static_cast<std::size_t>(r) * cols + c]) /
                                                       (npx * 254.0) * 255.0 - 127.5;
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
  // Per-row horizontal summation kernel over an extended column range [-cols, 2 cols).
  const int ext = 3 * cols;
  std::vector<double> S, prefix;
  S.assign(rr.size() * ext, 0.0);
  prefix.resize(static_cast<std::size_t>(cols) + 1);
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
      S[i * ext + x] = (prefix[hi] - prefix[lo]) / k;  // each row weighs the same
    }
  }
  // Hough: shift row i by round(s · (r − r0) / (r_last − r0)) and sum up the columns.
  const int r0 = rr.front(), rl = rr.back();
  const int M = std::min(opt_.max_shift_blocks, 2 * cols);
  double best = -std::numeric_limits<double>::max();
  int bx = 0, bsft = 0;
  std::vector<double> acc;
  for (int s = -M; s <= M; ++s) {
    acc.assign(static_cast<std::size_t>(cols), 0.0);
    for (std::size_t i = 0; i < rr.size(); ++i) {
      const int off = static_cast<int>(std::lround(static_cast<double>(s) * (rr[i] - r0) / std::max(1, rl - r0)));
      const double* srow = S.data() + i * ext + cols + off;
      for (int x = 0; x < cols; ++x) {
        const int xx = x + off;
        if (xx >= -cols && xx < 2 * cols) acc[x] += srow[x];
      }
    }
    for (int x = 0; x < cols; ++x)
      if (acc[x] > best) {
        best = acc[x];
        bx = x;
        bsft = s;
      }
  }
  res.intercept_col = bx;
  res.shift = bsft;
  // Sub-block refinement: the same Hough sum, with each block's certainty spread evenly over its
  // width and the kernel exactly the row's road width, evaluated at fractional intercepts and
  // shifts around the coarse maximum (coarse to fine: half-block steps, then eighth-block steps).
  // The continuous kernel sum is P(x + W/2) − P(x − W/2), P the running integral of the row.
  std::vector<double> P;
  P.assign(rr.size() * (static_cast<std::size_t>(cols) + 1), 0.0);
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
  const double span = std::max(1, rl - r0);
  auto score = [&](double X, double sft) {
    double total = 0;
    for (std::size_t i = 0; i < rr.size(); ++i) {
      const double x = X + sft * (rr[i] - r0) / span, hw = 0.5 * wb[rr[i]];
      total += (integral(i, x + hw) - integral(i, x - hw)) / (2.0 * hw);
    }
    return total;
  };
  double fx = bx + 0.5, fs = bsft, fbest = score(fx, fs);
  for (const double step : {0.5, 0.125}) {
    const double cx = fx, cs = fs;
    const int reach = step == 0.5 ? 3 : 4;
    for (int a = -reach; a <= reach; ++a)
      for (int b = -reach; b <= reach; ++b) {
        const double val = score(cx + a * step, cs + b * step);
        if (val > fbest) {
          fbest = val;
          fx = cx + a * step;
          fs = cs + b * step;
        }
      }
  }
  // Continuous block coordinate X ↔ pixel u = X · bs − 0.5; rows at their block centres.
  const double vt = r0 * bs + (bs - 1) / 2.0, vb = rl * bs + (bs - 1) / 2.0;
  const double b = (fs * bs) / std::max(1.0, vb - vt);
  const double a = fx * bs - 0.5 - b * vt;
  const double v_top = r0 * bs, v_bot = height - 1.0;
  res.centerline_image = Segment2{Vec2(a + b * v_top, v_top), Vec2(a + b * v_bot, v_bot)};
  res.confidence = std::clamp(best / std::max(1.0, max_possible), 0.0, 1.0);
  res.ok = true;
  return res;
}

// --- The "cluster-perceptron" pipeline ----------------------------------------------------------------

namespace {


const std::vector<OptionSpec>& specs() {
  static const std::vector<OptionSpec> s = {
      {"clusters", 5, false, true, 1, 30, "colour clusters (competitive learning units), 1..30"},
      {"seed", 1, false, true, 0, 1e15, "seed of the random initial cluster means"},
      {"max_cluster_iterations", 30, false, true, 1, 1000, "clustering iterations at most"},
      {"cluster_slope_threshold", 0.5, false, false, 0, 1e9,
       "clustering stops when every band's mean squared reconstruction error changes by less than this (levels^2)"},
      {"max_perceptron_iterations", 2000, false, true, 1, 1e6, "perceptron LMS iterations at most"},
      {"perceptron_rate", 0.3, false, false, 1e-9, 100, "perceptron LMS learning rate"},
      {"perceptron_tolerance", 1e-6, false, false, 0, 1, "perceptron training stops when the mean error changes by less"},
      {"train_stride", 1, false, true, 1, 64, "training uses every n-th pixel in each direction"},
      {"block_size", 8, false, true, 1, 256, "side of a road-certainty block, pixels"},
      {"max_shift_blocks", 32, false, true, 0, 1024, "Hough: largest shift of the bottom road row, blocks"},
      {"trapezoid_top", 0.0, false, false, 0, 0.999, "default bootstrap trapezoid (no predicted road): top row, fraction of the height"},
      {"trapezoid_top_width", 0.45, false, false, 1e-6, 10, "default trapezoid: top width, fraction of the image width"},
      {"trapezoid_bottom_width", 1.6, false, false, 1e-6, 10, "default trapezoid: bottom width, fraction of the image width"},
      {"fast", 1, true, false, 0, 1,
       "runtime through a 32x32x32 colour lookup table (exact: boundary cells are classified per pixel); false = "
       "per-pixel reference path"},
      {"min_road_fraction", 0.02, false, false, 0, 1, "fewer road pixels than this fraction of the frame: Failed"},
  };
  return s;
}


class ClusterPerceptronPipeline : public VisionPipeline {
 public:
  ClusterPerceptronPipeline() : options_(specs()) { apply(); }
  std::string name() const override { return "cluster-perceptron"; }
  void configure(const std::string& text) override {
    options_.configure("cluster-perceptron", text);
    apply();
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
      finder_ = ClusterPerceptron(opts_);
      finder_.trainClusters(frame.rgb, w, h);
      finder_.setRowWidths(trapezoidRowWidths(outline));
      finder_.trainPerceptron(frame.rgb, w, h, outline.data.data());
    }
    const RoadFinding f = finder_.find(frame.rgb, w, h, false);
    if (!f.ok) {
      DetectedObject d = DetectedObject::failed(f.reason);
      d.timestamp = frame.timestamp;
      return d;
    }
    DetectedObject d;
    d.timestamp = frame.timestamp;
    d.confidence = f.confidence;
    // The road region: the bootstrap trapezoid's widths around the centre line, clipped to the image.
    const Segment2& cl = f.centerline_image;
    const double v0 = cl.a.y(), v1 = cl.b.y();
    Polygon2 left, right;
    const int steps = 16;
    for (int k = 0; k <= steps; ++k) {
      const double v = v0 + (v1 - v0) * k / steps;
      const double t = (v - v0) / std::max(1e-9, v1 - v0);
      const double u = cl.a.x() + t * (cl.b.x() - cl.a.x());
      const double hw = 0.5 * finder_.rowWidths()[static_cast<std::size_t>(std::clamp(std::lround(v), 0L, h - 1L))];
      left.emplace_back(std::clamp(u - hw, -0.5, w - 0.5), v);
      right.emplace_back(std::clamp(u + hw, -0.5, w - 0.5), v);
    }
    d.region_image = right;
    for (auto it = left.rbegin(); it != left.rend(); ++it) d.region_image.push_back(*it);
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
  void apply() {
    ClusterPerceptronOptions o;
    o.clusters = static_cast<int>(options_["clusters"]);
    o.seed = static_cast<std::uint64_t>(options_["seed"]);
    o.max_cluster_iterations = static_cast<int>(options_["max_cluster_iterations"]);
    o.cluster_slope_threshold = options_["cluster_slope_threshold"];
    o.max_perceptron_iterations = static_cast<int>(options_["max_perceptron_iterations"]);
    o.perceptron_rate = options_["perceptron_rate"];
    o.perceptron_tolerance = options_["perceptron_tolerance"];
    o.train_stride = static_cast<int>(options_["train_stride"]);
    o.block_size = static_cast<int>(options_["block_size"]);
    o.max_shift_blocks = static_cast<int>(options_["max_shift_blocks"]);
    o.trapezoid_top = options_["trapezoid_top"];
    o.trapezoid_top_width = options_["trapezoid_top_width"];
    o.trapezoid_bottom_width = options_["trapezoid_bottom_width"];
    o.fast = options_["fast"] != 0;
    o.min_road_fraction = options_["min_road_fraction"];
    o.validate();
    opts_ = o;
    reset();
  }
  PipelineOptions options_;
  ClusterPerceptronOptions opts_;
  ClusterPerceptron finder_;
};

}  // namespace

std::unique_ptr<VisionPipeline> createClusterPerceptronPipeline() {
  return std::make_unique<ClusterPerceptronPipeline>();
}

std::vector<OptionInfo> clusterPerceptronOptionInfos() { return optionInfos(specs()); }

}  // namespace mapnav
