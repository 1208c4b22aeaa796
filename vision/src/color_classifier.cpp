#include "mapnav/vision/color_classifier.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mapnav/core/options.h"

namespace mapnav {

namespace {

// Regularisation added to the covariance diagonal: noise floor of the feature.
double minVariance(ColorSpace space) { return space == ColorSpace::NormalizedRG ? 4e-6 : 1.0; }

struct Accum {
  Vec3 sum = Vec3::Zero();
  Mat3 sq = Mat3::Zero();
  double n = 0;
  void add(const Vec3& x) {
    sum += x;
    sq += x * x.transpose();
    n += 1;
  }
  GaussianClass estimate(ColorSpace space) const {
    GaussianClass g;
    if (n < 2) return g;
    g.mean = sum / n;
    g.cov = sq / n - g.mean * g.mean.transpose();
    g.count = n;
    g.valid = true;
    const int d = featureDims(space);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        if (i >= d || j >= d) g.cov(i, j) = (i == j) ? 1.0 : 0.0;
      }
      if (i < d) g.cov(i, i) += minVariance(space);
    }
    return g;
  }
};

Mat3 inverseOf(const Mat3& m) { return m.inverse(); }

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

}  // namespace

void ColorClassifierOptions::validate() const {
  requireOption(blend > 0 && blend <= 1, "ColorClassifierOptions", "blend", blend, "in (0, 1]");
  requireOption(max_mean_shift_sigma > 0, "ColorClassifierOptions", "max_mean_shift_sigma", max_mean_shift_sigma,
                "> 0");
  requireOption(min_pixels >= 1, "ColorClassifierOptions", "min_pixels", min_pixels, ">= 1");
  requireOption(stride >= 1, "ColorClassifierOptions", "stride", stride, ">= 1");
}

int featureDims(ColorSpace space) { return space == ColorSpace::NormalizedRG ? 2 : 3; }

Vec3 colorFeature(ColorSpace space, const std::uint8_t* p) {
  const double r = p[0], g = p[1], b = p[2];
  if (space == ColorSpace::RGB) return Vec3(r, g, b);
  // +1 per channel: black stays neutral (1/3, 1/3) instead of dividing by zero.
  const double s = r + g + b + 3.0;
  return Vec3((r + 1.0) / s, (g + 1.0) / s, 0.0);
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
                                                      const std::uint8_t* road, const std::uint8_t* nonroad) {
  Accum ar, an;
  const int s = options_.stride;
  for (int v = 0; v < height; v += s) {
    for (int u = 0; u < width; u += s) {
      const std::size_t i = static_cast<std::size_t>(v) * width + u;
      if (road[i] == 0 && nonroad[i] == 0) continue;
      const Vec3 x = colorFeature(options_.space, rgb + 3 * i);
      if (road[i] != 0) ar.add(x);
      else an.add(x);
    }
  }
  UpdateResult result;
  const auto take = [&](GaussianClass& model, const Accum& acc, const char* what) {
    if (acc.n < options_.min_pixels) {
      result.note += std::string(result.note.empty() ? "" : "; ") + what + ": too few pixels (" +
                     std::to_string(static_cast<long>(acc.n)) + ")";
      return false;
    }
    const GaussianClass fresh = acc.estimate(options_.space);
    if (!model.valid) {
      model = fresh;
      return true;
    }
    const double shift = std::sqrt(mahalanobis2(model, fresh.mean));
    if (shift > options_.max_mean_shift_sigma) {
      result.note += std::string(result.note.empty() ? "" : "; ") + what + ": mean moved " +
                     std::to_string(shift) + " sigma";
      return false;
    }
    model = blendClass(model, fresh, options_.blend);
    return true;
  };
  result.road_accepted = take(road_, ar, "road");
  result.nonroad_accepted = take(nonroad_, an, "non-road");
  if (result.road_accepted && result.nonroad_accepted) {
    const double p = ar.n / (ar.n + an.n);
    const double a = (road_.count == ar.n && nonroad_.count == an.n) ? options_.blend : 1.0;
    prior_road_ = std::clamp((1 - a) * prior_road_ + a * p, 0.05, 0.95);
  }
  if (trained()) refreshCache();
  return result;
}

void ColorClassifier::refreshCache() {
  road_inv_ = road_.cov.inverse();
  nonroad_inv_ = nonroad_.cov.inverse();
  road_logdet_ = std::log(std::max(road_.cov.determinant(), 1e-300));
  nonroad_logdet_ = std::log(std::max(nonroad_.cov.determinant(), 1e-300));
}

float ColorClassifier::logOdds(const std::uint8_t* pixel) const {
  const Vec3 x = colorFeature(options_.space, pixel);
  const Vec3 dr = x - road_.mean, dn = x - nonroad_.mean;
  const double lr = -0.5 * (dr.dot(road_inv_ * dr) + road_logdet_);
  const double ln = -0.5 * (dn.dot(nonroad_inv_ * dn) + nonroad_logdet_);
  const double v = lr - ln + std::log(prior_road_ / (1 - prior_road_));
  return static_cast<float>(std::clamp(v, -1e4, 1e4));
}

std::vector<float> ColorClassifier::logOdds(const std::uint8_t* rgb, int width, int height,
                                            const std::uint8_t* where) const {
  std::vector<float> out(static_cast<std::size_t>(width) * height, 0.0f);
  if (!trained()) return out;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (where != nullptr && where[i] == 0) continue;
    out[i] = logOdds(rgb + 3 * i);
  }
  return out;
}

double ColorClassifier::separation() const {
  if (!trained()) return 0;
  const Mat3 c = 0.5 * (road_.cov + nonroad_.cov);
  const Vec3 d = road_.mean - nonroad_.mean;
  const double term1 = 0.125 * d.dot(c.inverse() * d);
  const double term2 =
      0.5 * std::log(c.determinant() / std::sqrt(road_.cov.determinant() * nonroad_.cov.determinant()));
  return term1 + term2;
}

}  // namespace mapnav
