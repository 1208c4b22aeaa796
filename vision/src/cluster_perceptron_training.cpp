// The cluster-perceptron's training (Jochem & Baluja 1993 §3-4): colour clustering by competitive
// learning (isodata) and its adaptation to a changed scene (§9, beyond the paper: track()'s new
// clusters) and the perceptron over the clusters' code (or raw RGB) by LMS; the colour lookup table
// that collapses both for the fast runtime path is cluster_perceptron_lut.cpp's. See
// cluster_perceptron.h.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <unordered_map>
#include <utility>
#include <vector>

#include "cluster_perceptron_internal.h"
#include "log_colour.h"
#include "mapnav/core/error.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav {

Vec3 ClusterPerceptron::feature(double r, double g, double b) const {
  if (opt_.normalized_color) {
    const double sum = r + g + b;
    return sum > 0 ? Vec3(Vec3(r, g, b) * (255.0 / sum)) : Vec3::Constant(85.0);
  }
  if (opt_.log_color) return Vec3(log_colour::of(r), log_colour::of(g), log_colour::of(b));
  return Vec3(r, g, b);
}

std::optional<ChannelTables> ClusterPerceptron::channelTables() const {
  if (opt_.normalized_color) return std::nullopt;
  return ChannelTables([this](double r, double g, double b) { return feature(r, g, b); }, means_);
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

namespace {

/// A colour of the frame and how many of the pixels clustered have it.
struct ColourCount {
  std::uint8_t r, g, b;
  double count;
  Vec3 feature;
};

/// The distinct colours of every `stride`-th pixel in each direction, ordered by (r, g, b), with
/// their counts: a clustering pass needs each colour once (a 480 x 360 photo has a few times fewer
/// colours than pixels). Sorted by a radix sort of the packed colours, two 12-bit digits.
template <class Feature>
std::vector<ColourCount> distinctColours(const std::uint8_t* rgb, int width, int height, int stride, const Feature& feature) {
  std::vector<std::uint32_t> keys, sorted;
  keys.reserve(static_cast<std::size_t>((height + stride - 1) / stride) * static_cast<std::size_t>((width + stride - 1) / stride));
  for (int v = 0; v < height; v += stride)
    for (int u = 0; u < width; u += stride) {
      const std::uint8_t* p = rgb + 3 * (static_cast<std::size_t>(v) * width + u);
      keys.push_back(static_cast<std::uint32_t>(p[0]) << 16 | static_cast<std::uint32_t>(p[1]) << 8 | p[2]);
    }
  sorted.resize(keys.size());
  for (const int shift : {0, 12}) {
    std::vector<std::uint32_t> start(4097, 0);
    for (const std::uint32_t k : keys) ++start[((k >> shift) & 0xFFF) + 1];
    for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
    for (const std::uint32_t k : keys) sorted[start[(k >> shift) & 0xFFF]++] = k;
    keys.swap(sorted);
  }
  std::vector<ColourCount> out;
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i + 1;
    while (j < keys.size() && keys[j] == keys[i]) ++j;
    const auto r = static_cast<std::uint8_t>(keys[i] >> 16), g = static_cast<std::uint8_t>(keys[i] >> 8),
               b = static_cast<std::uint8_t>(keys[i]);
    out.push_back(ColourCount{r, g, b, static_cast<double>(j - i), feature(r, g, b)});
    i = j;
  }
  return out;
}

}  // namespace

std::vector<Vec3> ClusterPerceptron::clusterFrom(const std::uint8_t* rgb, int width, int height) {
  const int n = static_cast<int>(means_.size());
  trained_ = false;
  const std::vector<ColourCount> colours =
      distinctColours(rgb, width, height, opt_.train_stride, [this](double r, double g, double b) { return feature(r, g, b); });

  // One pass: each colour's winner; counts, difference sums and the reconstruction error per band,
  // each colour weighted by its pixels. `nearestOf(c)` gives a colour's nearest cluster. The means
  // are read from locals that the sums' stores cannot alias.
  std::vector<double> cnt(n), dr(n), dg(n), db(n), mr(n), mg(n), mb(n);
  const auto sweep = [&](const auto& nearestOf) {
    for (int k = 0; k < n; ++k) mr[k] = means_[k].x(), mg[k] = means_[k].y(), mb[k] = means_[k].z();
    std::fill(cnt.begin(), cnt.end(), 0.0);
    std::fill(dr.begin(), dr.end(), 0.0);
    std::fill(dg.begin(), dg.end(), 0.0);
    std::fill(db.begin(), db.end(), 0.0);
    double e0 = 0, e1 = 0, e2 = 0, total = 0;
    double *c = cnt.data(), *sr = dr.data(), *sg = dg.data(), *sb = db.data();
    for (const ColourCount& colour : colours) {
      const int k = nearestOf(colour);
      const Vec3& f = colour.feature;
      const double w = colour.count, er = f.x() - mr[k], eg = f.y() - mg[k], eb = f.z() - mb[k];
      c[k] += w;
      sr[k] += w * er;
      sg[k] += w * eg;
      sb[k] += w * eb;
      e0 += w * er * er;
      e1 += w * eg * eg;
      e2 += w * eb * eb;
      total += w;
    }
    return Vec3(Vec3(e0, e1, e2) / total);
  };
  auto pass = [&]() {
    const std::optional<ChannelTables> tables = channelTables();  // this pass's means
    if (!tables) return sweep([this](const ColourCount& c) { return nearest(c.feature); });
    return sweep([&tables](const ColourCount& c) { return tables->nearest(c.r, c.g, c.b); });
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
    else if (opt_.log_color) c = c.unaryExpr([](double x) { return log_colour::level(x); });
    for (int b = 0; b < 3; ++b)
      out.data[3 * i + b] = static_cast<std::uint8_t>(std::clamp(std::lround(c[b]), 0L, 255L));
  }
  return out;
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

// --- §4 perceptron ---------------------------------------------------------------------------------

std::vector<std::int8_t> ClusterPerceptron::trainingClasses(const std::uint8_t* rgb, int width, int height,
                                                            const std::uint8_t* road, bool gated) const {
  const int st = opt_.train_stride;
  std::vector<std::int8_t> cls(static_cast<std::size_t>(width) * height, 0);
  const auto each = [&](auto&& f) {
    for (int v = 0; v < height; v += st)
      for (int u = 0; u < width; u += st) {
        const std::size_t i = static_cast<std::size_t>(v) * width + u;
        f(i, feature(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]));
      }
  };
  gated = gated && opt_.nonroad_gate_sigma > 0;
  for (int v = 0; v < height; v += st)  // the outline's classes need no feature
    for (int u = 0; u < width; u += st) {
      const std::size_t i = static_cast<std::size_t>(v) * width + u;
      cls[i] = road[i] != 0 ? 1 : gated ? 0 : -1;
    }
  if (!gated) return cls;
  // The road's colour estimate: mean and covariance of the outline's features (a level of noise
  // added to the diagonal, so that a flat road does not make the gate a point).
  Vec3 sum = Vec3::Zero();
  Mat3 sq = Mat3::Zero();
  double n = 0;
  each([&](std::size_t i, const Vec3& f) {
    if (road[i] == 0) return;
    sum += f;
    sq += f * f.transpose();
    n += 1;
  });
  if (n < 1) {  // no road to measure the gate from: every pixel outside is not road, as in the paper
    each([&](std::size_t i, const Vec3&) { cls[i] = road[i] != 0 ? 1 : -1; });
    return cls;
  }
  const Vec3 mean = sum / n;
  const Mat3 inv = (Mat3(sq / n - mean * mean.transpose()) + Mat3::Identity()).inverse();
  const double gate2 = opt_.nonroad_gate_sigma * opt_.nonroad_gate_sigma;
  each([&](std::size_t i, const Vec3& f) {
    const Vec3 d = f - mean;
    if (road[i] == 0 && d.dot(inv * d) > gate2) cls[i] = -1;
  });
  return cls;
}

std::vector<double> ClusterPerceptron::trainPerceptron(const std::uint8_t* rgb, int width, int height,
                                                       const std::uint8_t* road) {
  if (!opt_.raw_rgb && means_.empty()) throw InvalidInput("trainPerceptron: the clusters are not trained");
  const auto train = [&](bool gated) {
    const std::vector<std::int8_t> cls = trainingClasses(rgb, width, height, road, gated);
    return opt_.raw_rgb ? trainRgbPerceptron(rgb, cls) : trainClusterPerceptron(rgb, cls);
  };
  // The paper's bootstrap first; the gate only when it calls most of its own road outline not road.
  Trained t = train(false);
  gated_ = opt_.nonroad_gate_sigma > 0 && t.road_share < opt_.nonroad_gate_below;
  if (gated_) t = train(true);
  return t.history;
}

namespace {
/// balance_classes: every road count scaled so that the road's total equals the rest's; returns the
/// new total of the counts (unchanged when either class is empty).
template <typename Counts, typename Road, typename Rest>
double balanceCounts(Counts& counts, Road road, Rest rest, double total) {
  double inside = 0, outside = 0;
  for (auto& c : counts) {
    inside += road(c);
    outside += rest(c);
  }
  if (inside <= 0 || outside <= 0) return total;
  for (auto& c : counts) road(c) *= outside / inside;
  return 2 * outside;
}
}  // namespace

ClusterPerceptron::Trained ClusterPerceptron::trainClusterPerceptron(const std::uint8_t* rgb,
                                                                     const std::vector<std::int8_t>& cls) {
  const int n = static_cast<int>(means_.size());
  // Every pixel won by the same cluster has the same inputs, so the per-pixel LMS sums reduce exactly
  // to per-cluster counts of road and non-road pixels.
  std::vector<std::pair<double, double>> counts(static_cast<std::size_t>(n), {0.0, 0.0});  // (road, not road)
  double total = 0;
  const std::optional<ChannelTables> tables = channelTables();
  for (std::size_t i = 0; i < cls.size(); ++i) {
    if (cls[i] == 0) continue;
    const std::uint8_t* p = rgb + 3 * i;
    auto& c = counts[static_cast<std::size_t>(tables ? tables->nearest(p[0], p[1], p[2]) : nearest(p[0], p[1], p[2]))];
    (cls[i] > 0 ? c.first : c.second) += 1;
    total += 1;
  }
  const std::vector<double> road_px = [&] {
    std::vector<double> r;
    for (const auto& c : counts) r.push_back(c.first);
    return r;
  }();
  if (opt_.balance_classes)
    total = balanceCounts(counts, [](auto& c) -> double& { return c.first; }, [](auto& c) { return c.second; }, total);
  Trained t;
  t.history = runLms(static_cast<std::size_t>(n) + 1, total, [&](std::vector<double>& grad) {
    double err = 0;
    for (int k = 0; k < n; ++k) {
      const auto [pos, neg] = counts[static_cast<std::size_t>(k)];
      const double y = std::tanh(netFor(weights_, k));
      const double e = pos * (1.0 - y) + neg * (-1.0 - y);  // Σ (target − output)
      err += pos * std::abs(1.0 - y) + neg * std::abs(-1.0 - y);
      for (int j = 0; j < n; ++j) grad[j] += e * (j == k ? 1.0 : -1.0);
      grad[n] += e;  // bias input 1
    }
    return err;
  });
  double road = 0, called = 0;
  for (int k = 0; k < n; ++k) {
    road += road_px[static_cast<std::size_t>(k)];
    if (certaintyOf(std::tanh(netFor(weights_, k))) > 127) called += road_px[static_cast<std::size_t>(k)];
  }
  t.road_share = road > 0 ? called / road : 0.0;
  return t;
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
  resetLut();
  trained_ = !row_widths_.empty();
  return history;
}

ClusterPerceptron::Trained ClusterPerceptron::trainRgbPerceptron(const std::uint8_t* rgb,
                                                                 const std::vector<std::int8_t>& cls) {
  // Pixels of the same colour have the same inputs: the LMS sums reduce exactly to per-colour counts.
  std::unordered_map<std::uint32_t, std::pair<double, double>> counts;  // colour → (road, not road)
  double total = 0;
  for (std::size_t i = 0; i < cls.size(); ++i) {
    if (cls[i] == 0) continue;
    const std::uint32_t key = (std::uint32_t{rgb[3 * i]} << 16) | (std::uint32_t{rgb[3 * i + 1]} << 8) | rgb[3 * i + 2];
    auto& c = counts[key];
    (cls[i] > 0 ? c.first : c.second) += 1;
    total += 1;
  }
  std::vector<std::pair<std::uint32_t, std::pair<double, double>>> colours(counts.begin(), counts.end());
  std::sort(colours.begin(), colours.end());  // a fixed summation order: the same weights every run
  std::vector<double> road_px;
  for (const auto& c : colours) road_px.push_back(c.second.first);
  if (opt_.balance_classes)
    total = balanceCounts(colours, [](auto& c) -> double& { return c.second.first; },
                          [](auto& c) { return c.second.second; }, total);
  const auto featureOf = [&](std::uint32_t key) { return feature(key >> 16, (key >> 8) & 255, key & 255); };
  Trained t;
  t.history = runLms(4, total, [&](std::vector<double>& grad) {
    double err = 0;
    for (const auto& [key, pn] : colours) {
      const Vec3 f = featureOf(key);
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
  double road = 0, called = 0;
  for (std::size_t k = 0; k < colours.size(); ++k) {
    road += road_px[k];
    if (certaintyOf(std::tanh(netRgb(weights_, featureOf(colours[k].first)))) > 127) called += road_px[k];
  }
  t.road_share = road > 0 ? called / road : 0.0;
  return t;
}

double ClusterPerceptron::outputReference(std::uint8_t r, std::uint8_t g, std::uint8_t b) const {
  if (opt_.raw_rgb) return std::tanh(netRgb(weights_, feature(r, g, b)));
  return std::tanh(netFor(weights_, nearest(r, g, b)));
}

void ClusterPerceptron::setRowWidths(std::vector<double> widths) {
  row_widths_ = std::move(widths);
  trained_ = !weights_.empty() && !row_widths_.empty();
}

}  // namespace mapnav
