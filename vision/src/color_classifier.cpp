#include "mapnav/vision/color_classifier.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <opencv2/core.hpp>

#include "log_colour.h"
#include "mapnav/core/options.h"

namespace mapnav {

namespace {

// What a pixel's feature is: log RGB; rg; or rg and the log brightness.
enum class Features { LogRGB, RG, RGBrightness };

// The features the options ask for.
Features featuresOf(const ColorClassifierOptions& o) {
  if (o.space == ColorSpace::LogRGB) return Features::LogRGB;
  return o.brightness_sigma > 0 ? Features::RGBrightness : Features::RG;
}

// The features the models use: rg alone when the brightness was asked for but is not needed
// (ColorClassifier::brightnessUsed()).
Features usedFeatures(const ColorClassifierOptions& o, bool brightness_used) {
  const Features f = featuresOf(o);
  return f == Features::RGBrightness && !brightness_used ? Features::RG : f;
}

constexpr double kLogScale = log_colour::kScale;

// Added to every class's covariance: the camera's noise (noise_sigma levels per channel; in rg one
// level moves r or g by about 1/500 at mid-grey, R + G + B ≈ 384; in log RGB by kLogScale / 129 at
// mid-grey) and the spread in log brightness (brightness_sigma: on the diagonal in rg and brightness;
// in log RGB along the grey axis, where a brightness change of δ moves every channel by kLogScale δ).
Mat3 minCovariance(const ColorClassifierOptions& o) {
  const double n2 = o.noise_sigma * o.noise_sigma;
  const double b2 = o.brightness_sigma * o.brightness_sigma;
  if (featuresOf(o) == Features::LogRGB) {
    const double k = kLogScale / 129.0;
    return Mat3(Vec3::Constant(n2 * k * k).asDiagonal()) + Mat3::Constant(kLogScale * kLogScale * b2);
  }
  const double rg2 = n2 / (500.0 * 500.0);
  return Vec3(rg2, rg2, featuresOf(o) == Features::RGBrightness ? b2 : 0.0).asDiagonal();
}

// ln((s + 3) / 3) for s = R + G + B: the log brightness, 0 for black (+1 per channel, as rg's).
// In double: feature()'s, the same bits as std::log(s / 3.0) there; in float: the fast path's.
const std::array<double, 766>& logBrightnessTableD() {
  static const std::array<double, 766> table = [] {
    std::array<double, 766> t{};
    for (std::size_t s = 0; s < t.size(); ++s) t[s] = std::log((static_cast<double>(s) + 3.0) / 3.0);
    return t;
  }();
  return table;
}
const std::array<float, 766>& logBrightnessTable() {
  static const std::array<float, 766> table = [] {
    std::array<float, 766> t{};
    for (std::size_t s = 0; s < t.size(); ++s) t[s] = static_cast<float>(logBrightnessTableD()[s]);
    return t;
  }();
  return table;
}

struct Accum {
  double s0 = 0, s1 = 0, s2 = 0;                          // sums of the feature
  double q00 = 0, q01 = 0, q02 = 0, q11 = 0, q12 = 0, q22 = 0;  // sums of its products
  double n = 0;
  void add(const Vec3& x) {
    s0 += x[0], s1 += x[1], s2 += x[2];
    q00 += x[0] * x[0], q01 += x[0] * x[1], q02 += x[0] * x[2];
    q11 += x[1] * x[1], q12 += x[1] * x[2], q22 += x[2] * x[2];
    n += 1;
  }
  GaussianClass estimate(const ColorClassifierOptions& o) const {
    GaussianClass g;
    if (n < 2) return g;
    Mat3 sq;
    sq << q00, q01, q02, q01, q11, q12, q02, q12, q22;
    g.mean = Vec3(s0, s1, s2) / n;
    g.cov = sq / n - g.mean * g.mean.transpose();
    g.count = n;
    g.valid = true;
    const int d = featureDims(o);
    g.cov += minCovariance(o);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (i >= d || j >= d) g.cov(i, j) = (i == j) ? 1.0 : 0.0;
    return g;
  }
};

/// A Gaussian so broad that it is nearly flat over the feature space: rg in [0, 1]², the log
/// brightness in [0, 5.55], log RGB in 0..255.
GaussianClass flatClass(const ColorClassifierOptions& o) {
  GaussianClass g;
  const Features f = featuresOf(o);
  if (f == Features::LogRGB) {
    g.mean = Vec3::Constant(127.5);
    g.cov = Vec3(Vec3::Constant(256.0 * 256.0)).asDiagonal();
  } else {
    g.mean = Vec3(1.0 / 3, 1.0 / 3, f == Features::RGBrightness ? 2.8 : 0.0);
    g.cov = Vec3(1, 1, f == Features::RGBrightness ? 36.0 : 1.0).asDiagonal();
  }
  g.valid = true;
  return g;
}

Mat3 inverseOf(const Mat3& m) { return m.inverse(); }

/// The class in rg alone: its marginal, with the third feature decoupled (mean 0, variance 1).
GaussianClass rgMarginal(GaussianClass g) {
  g.mean[2] = 0;
  g.cov.row(2).setZero();
  g.cov.col(2).setZero();
  g.cov(2, 2) = 1;
  return g;
}

/// The Bhattacharyya distance between two Gaussians.
double bhattacharyya(const GaussianClass& a, const GaussianClass& b) {
  const Mat3 c = 0.5 * (a.cov + b.cov);
  const Vec3 d = a.mean - b.mean;
  return 0.125 * d.dot(c.inverse() * d) + 0.5 * std::log(c.determinant() / std::sqrt(a.cov.determinant() * b.cov.determinant()));
}

double mahalanobis2(const GaussianClass& g, const Vec3& x) {
  const Vec3 d = x - g.mean;
  return d.dot(inverseOf(g.cov) * d);
}

GaussianClass blendClass(const GaussianClass& old, const GaussianClass& fresh, double a) {
  GaussianClass g;
  g.mean = (1 - a) * old.mean + a * fresh.mean;
  const Vec3 d0 = old.mean - g.mean, d1 = fresh.mean - g.mean;
  g.cov = (1 - a) * (old.cov + d0 * d0.transpose()) + a * (fresh.cov + d1 * d1.transpose());
  g.count = fresh.count;
  g.valid = true;
  return g;
}

// colorFeature, inline here (the per-pixel loops call it without going through the library's PLT).
inline Vec3 feature(Features f, const std::uint8_t* p) {
  const double r = p[0], g = p[1], b = p[2];
  if (f == Features::LogRGB) {
    const auto& t = log_colour::table();
    return Vec3(t[p[0]], t[p[1]], t[p[2]]);
  }
  // +1 per channel: black stays neutral (1/3, 1/3) instead of dividing by zero.
  const double s = r + g + b + 3.0;
  return Vec3((r + 1.0) / s, (g + 1.0) / s,
              f == Features::RGBrightness ? logBrightnessTableD()[p[0] + p[1] + p[2]] : 0.0);  // ln(s / 3)
}

// The log-odds of one pixel on the fast path (the same arithmetic, lane by lane, as quadraticRow).
// `ln` is logBrightnessTable() (read for RGBrightness only), `lc` log_colour::tableF() (LogRGB only).
inline float quadratic(const LogOddsQuadratic& q, Features f, const float* ln, const float* lc, float r, float g,
                       float b) {
  float u0, u1, u2;
  if (f != Features::LogRGB) {
    const float inv = 1.0f / (r + g + b + 3.0f);
    u0 = (r + 1.0f) * inv - q.c0;
    u1 = (g + 1.0f) * inv - q.c1;
    u2 = (f == Features::RGBrightness ? ln[static_cast<int>(r + g + b)] : 0.0f) - q.c2;
  } else {
    u0 = lc[static_cast<int>(r)] - q.c0, u1 = lc[static_cast<int>(g)] - q.c1, u2 = lc[static_cast<int>(b)] - q.c2;
  }
  const float v = q.k + u0 * (q.l0 + q.q00 * u0 + q.q01 * u1 + q.q02 * u2) + u1 * (q.l1 + q.q11 * u1 + q.q12 * u2) +
                  u2 * (q.l2 + q.q22 * u2);
  return v < -1e4f ? -1e4f : (v > 1e4f ? 1e4f : v);
}

// One run of planar pixels: plain loops the vectoriser turns into SIMD (this file is built with -O3),
// built for AVX2 too where the processor has it (8 lanes instead of 4; the same single-precision
// operations lane by lane, no FMA: the same values).
template <Features F>
inline void quadraticLoop(const LogOddsQuadratic& c, const std::uint8_t* __restrict R, const std::uint8_t* __restrict G,
                          const std::uint8_t* __restrict B, const std::uint8_t* __restrict where, float* __restrict out,
                          int n) {
  const float* ln = logBrightnessTable().data();
  const float* lc = log_colour::tableF().data();
  for (int i = 0; i < n; ++i) {
    const float v = quadratic(c, F, ln, lc, R[i], G[i], B[i]);
    out[i] = where[i] != 0 ? v : 0.0f;
  }
}

__attribute__((target_clones("avx2", "default"))) void quadraticRow(const LogOddsQuadratic& q, Features f, const std::uint8_t* __restrict R, const std::uint8_t* __restrict G,
                  const std::uint8_t* __restrict B, const std::uint8_t* __restrict where, float* __restrict out,
                  int n) {
  const LogOddsQuadratic c = q;
  switch (f) {
    case Features::RG: quadraticLoop<Features::RG>(c, R, G, B, where, out, n); break;
    case Features::RGBrightness: quadraticLoop<Features::RGBrightness>(c, R, G, B, where, out, n); break;
    case Features::LogRGB: quadraticLoop<Features::LogRGB>(c, R, G, B, where, out, n); break;
  }
}

}  // namespace

const OptionTable<ColorClassifierOptions>& colorClassifierOptionTable() {
  using O = ColorClassifierOptions;
  static const OptionTable<O> table =
      OptionTable<O>("ColorClassifierOptions")
          .choice("space", &O::space, {{ColorSpace::LogRGB, "log_rgb"}, {ColorSpace::NormalizedRG, "normalized_rg"}},
                  "the classes' colour space: \"log_rgb\" (255 ln(c + 1) / ln 256 per channel) or \"normalized_rg\" "
                  "(r = R / (R + G + B), g = G / (R + G + B))")
          .field("blend", &O::blend, aboveUpTo(0, 1), "weight of a frame's estimate in the blended model (1 = replace)")
          .field("max_mean_shift_sigma", &O::max_mean_shift_sigma, aboveUpTo(0, 1e6),
                 "refuse a road estimate (and an ungated non-road one) whose mean moved more than this many sigma "
                 "(drift guard); a gated non-road estimate, which holds no road colour, follows the surroundings")
          .field("min_pixels", &O::min_pixels, inRange(1, 1e9),
                 "refuse a class estimate from fewer labelled training pixels (a region pipeline: cells, of which "
                 "training reads every 2nd of every 2nd row)")
          .field("stride", &O::stride, atLeast(1), "training uses every n-th pixel of every n-th row")
          .field("nonroad_gate_sigma", &O::nonroad_gate_sigma, inRange(0, 1e6),
                 "non-road trains only on the pixels labelled non-road whose colour is more than this many sigma "
                 "(Mahalanobis) from the road's: on real roads the rest of the view is mostly road; until a frame "
                 "shows such pixels, non-road is flat (road is what the road colour explains); 0 = every labelled pixel")
          .field("brightness_sigma", &O::brightness_sigma, inRange(0, 10),
                 "the spread in log brightness added to every class (0.1 = 10 %); normalized_rg: > 0 makes the log "
                 "brightness a third feature, 0 = rg only (Wallace 3.4.3); log_rgb: added along the grey axis")
          .field("brightness_separation", &O::brightness_separation, atLeast(0),
                 "with brightness_sigma > 0: the brightness only while rg alone separates road and non-road by less "
                 "than this Bhattacharyya distance (a grey road among grey cars and walls: 2-4); where colour separates "
                 "them (grass: 5 and more) rg alone stays robust to shadows")
          .field("noise_sigma", &O::noise_sigma, inRange(1e-3, 100),
                 "the camera's noise, 8-bit levels per channel, added to every class's spread (in rg scaled to one "
                 "level's effect at mid-grey, 1/500): a real camera's noise and compression; 1 = a rendered frame's");
  return table;
}

void ColorClassifierOptions::validate() const { colorClassifierOptionTable().validate(*this); }

int featureDims(const ColorClassifierOptions& options) { return featuresOf(options) == Features::RG ? 2 : 3; }

Vec3 colorFeature(const ColorClassifierOptions& options, const std::uint8_t* p) {
  return feature(featuresOf(options), p);
}

ColorClassifier::ColorClassifier(ColorClassifierOptions options) : options_(options) {
  options_.validate();
}

void ColorClassifier::reset() {
  road_ = {};
  nonroad_ = {};
  prior_road_ = 0.5;
}

ColorClassifier::UpdateResult ColorClassifier::update(const std::uint8_t* rgb, int width, int height,
                                                      const std::uint8_t* road, const std::uint8_t* nonroad,
                                                      std::optional<double> nonroad_gate_sigma) {
  const double gate_sigma = nonroad_gate_sigma.value_or(options_.nonroad_gate_sigma);
  requireArgument(std::isfinite(gate_sigma) && gate_sigma >= 0, "ColorClassifier::update", "nonroad_gate_sigma",
                  gate_sigma, "finite and >= 0");
  Accum ar, an;
  const int s = options_.stride;
  const Features features = featuresOf(options_);
  const auto each = [&](auto&& f) {
    for (int v = 0; v < height; v += s)
      for (int u = 0; u < width; u += s) f(static_cast<std::size_t>(v) * width + u);
  };
  each([&](std::size_t i) {
    if (road[i] != 0) ar.add(feature(features, rgb + 3 * i));
  });
  // Non-road: the labelled pixels, or with a gate only those far in colour from the road (this
  // frame's estimate when it is usable, else the model).
  const GaussianClass gate_road = ar.n >= options_.min_pixels ? ar.estimate(options_) : road_;
  const bool gated = gate_sigma > 0 && gate_road.valid;
  const Mat3 gate_inv = gated ? Mat3(gate_road.cov.inverse()) : Mat3::Identity();
  const double gate2 = gate_sigma * gate_sigma;
  each([&](std::size_t i) {
    if (road[i] != 0 || nonroad[i] == 0) return;
    const Vec3 x = feature(features, rgb + 3 * i);
    const Vec3 d = x - gate_road.mean;
    if (!gated || d.dot(gate_inv * d) > gate2) an.add(x);
  });
  UpdateResult result;
  // The drift guard keeps the road model from jumping onto another surface (a prediction that is
  // off). A gated non-road estimate has no road colour in it, and the surroundings do change
  // colour (a lawn gives way to a dirt shoulder, to a shadow): guarded, the non-road model stayed
  // the lawn's and the dirt was closer to the road's, road (random-campus --junctions 6, seed 9).
  const auto take = [&](GaussianClass& model, const Accum& acc, const char* what, bool guarded) {
    if (acc.n < options_.min_pixels) {
      result.note += std::string(result.note.empty() ? "" : "; ") + what + ": too few pixels (" +
                     std::to_string(static_cast<long>(acc.n)) + ")";
      return false;
    }
    const GaussianClass fresh = acc.estimate(options_);
    if (!model.valid) {
      model = fresh;
      return true;
    }
    const double shift = std::sqrt(mahalanobis2(model, fresh.mean));
    if (guarded && shift > options_.max_mean_shift_sigma) {
      result.note += std::string(result.note.empty() ? "" : "; ") + what + ": mean moved " +
                     std::to_string(shift) + " sigma";
      return false;
    }
    model = blendClass(model, fresh, options_.blend);
    return true;
  };
  result.road_accepted = take(road_, ar, "road", true);
  result.nonroad_accepted = take(nonroad_, an, "non-road", !gated);
  if (!nonroad_.valid && gated && an.n < options_.min_pixels) {
    // Too few pixels are confidently not road-coloured: the view is nearly all road. Until a frame
    // shows non-road, it is a flat density over the colour space (every colour about equally likely):
    // road is then what the road class explains better than chance.
    nonroad_ = flatClass(options_);
    result.nonroad_accepted = true;
    result.note += std::string(result.note.empty() ? "" : "; ") + "non-road: flat (every colour)";
  }
  if (result.road_accepted && result.nonroad_accepted) {
    const double p = ar.n / (ar.n + an.n);
    const double a = (road_.count == ar.n && nonroad_.count == an.n) ? options_.blend : 1.0;
    prior_road_ = std::clamp((1 - a) * prior_road_ + a * p, 0.05, 0.95);
  }
  if (trained()) refreshCache();
  return result;
}

void ColorClassifier::refreshCache() {
  // The brightness only where rg alone does not separate the classes (e.g. a grey road among grey
  // cars and walls): where colour does, rg alone is robust to shadows (Wallace 3.4.3).
  used_road_ = road_;
  used_nonroad_ = nonroad_;
  brightness_used_ = false;
  if (featuresOf(options_) == Features::RGBrightness) {
    const GaussianClass r = rgMarginal(road_), n = rgMarginal(nonroad_);
    brightness_used_ = bhattacharyya(r, n) < options_.brightness_separation;
    if (!brightness_used_) used_road_ = r, used_nonroad_ = n;
  }
  road_inv_ = used_road_.cov.inverse();
  nonroad_inv_ = used_nonroad_.cov.inverse();
  road_logdet_ = std::log(std::max(used_road_.cov.determinant(), 1e-300));
  nonroad_logdet_ = std::log(std::max(used_nonroad_.cov.determinant(), 1e-300));
  // The fast path: both quadratic forms in one, centred between the means so that single precision
  // keeps the cancellation near the decision boundary small.
  const Vec3 c = 0.5 * (used_road_.mean + used_nonroad_.mean);
  const Vec3 ar = used_road_.mean - c, an = used_nonroad_.mean - c;
  const Mat3 q = -0.5 * (road_inv_ - nonroad_inv_);
  const Vec3 l = road_inv_ * ar - nonroad_inv_ * an;
  const double k = -0.5 * (ar.dot(road_inv_ * ar) - an.dot(nonroad_inv_ * an)) - 0.5 * (road_logdet_ - nonroad_logdet_) +
                   std::log(prior_road_ / (1 - prior_road_));
  const auto f = [](double x) { return static_cast<float>(x); };
  quad_ = {f(c[0]), f(c[1]), f(c[2]), f(q(0, 0)), f(q(0, 1) + q(1, 0)), f(q(0, 2) + q(2, 0)), f(q(1, 1)),
           f(q(1, 2) + q(2, 1)), f(q(2, 2)), f(l[0]), f(l[1]), f(l[2]), f(k)};
}

float ColorClassifier::logOdds(const std::uint8_t* pixel) const {
  return quadratic(quad_, usedFeatures(options_, brightness_used_), logBrightnessTable().data(),
                   log_colour::tableF().data(), pixel[0], pixel[1], pixel[2]);
}

float ColorClassifier::logOddsReference(const std::uint8_t* pixel) const {
  const Vec3 x = feature(usedFeatures(options_, brightness_used_), pixel);
  const Vec3 dr = x - used_road_.mean, dn = x - used_nonroad_.mean;
  const double lr = -0.5 * (dr.dot(road_inv_ * dr) + road_logdet_);
  const double ln = -0.5 * (dn.dot(nonroad_inv_ * dn) + nonroad_logdet_);
  const double v = lr - ln + std::log(prior_road_ / (1 - prior_road_));
  return static_cast<float>(std::clamp(v, -1e4, 1e4));
}

std::vector<float> ColorClassifier::logOdds(const std::uint8_t* rgb, int width, int height,
                                            const std::uint8_t* where) const {
  std::vector<float> out(static_cast<std::size_t>(width) * height, 0.0f);
  if (!trained() || out.empty()) return out;
  const Features f = usedFeatures(options_, brightness_used_);
  // Planar colour, a band of rows at a time (small enough to stay in cache).
  constexpr int kBand = 16;
  std::vector<std::uint8_t> planes(static_cast<std::size_t>(3) * kBand * width);
  const std::vector<std::uint8_t> everywhere(where == nullptr ? static_cast<std::size_t>(width) * kBand : 0, 1);
  for (int v0 = 0; v0 < height; v0 += kBand) {
    const int rows = std::min(kBand, height - v0);
    const std::size_t first = static_cast<std::size_t>(v0) * width, count = static_cast<std::size_t>(rows) * width;
    const std::uint8_t* mask = where != nullptr ? where + first : everywhere.data();
    std::uint8_t any = 0;
    for (std::size_t i = 0; i < count; ++i) any |= mask[i];
    if (any == 0) continue;  // e.g. the sky: nothing asked for
    const cv::Mat interleaved(1, static_cast<int>(count), CV_8UC3, const_cast<std::uint8_t*>(rgb + 3 * first));
    cv::Mat channels[3] = {cv::Mat(1, static_cast<int>(count), CV_8UC1, planes.data()),
                           cv::Mat(1, static_cast<int>(count), CV_8UC1, planes.data() + count),
                           cv::Mat(1, static_cast<int>(count), CV_8UC1, planes.data() + 2 * count)};
    cv::split(interleaved, channels);
    quadraticRow(quad_, f, planes.data(), planes.data() + count, planes.data() + 2 * count, mask, out.data() + first,
                 static_cast<int>(count));
  }
  return out;
}

std::vector<float> ColorClassifier::logOddsReference(const std::uint8_t* rgb, int width, int height,
                                                     const std::uint8_t* where) const {
  std::vector<float> out(static_cast<std::size_t>(width) * height, 0.0f);
  if (!trained()) return out;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (where != nullptr && where[i] == 0) continue;
    out[i] = logOddsReference(rgb + 3 * i);
  }
  return out;
}

double ColorClassifier::separation() const { return trained() ? bhattacharyya(used_road_, used_nonroad_) : 0; }

}  // namespace mapnav
