// The edge tracker's grey image and its oriented step-edge operator (Wallace et al. 1985, 3.1): the
// edge profile integrated along the expected direction at a few orientations, and the step that
// correlates best with it. See edge_tracker.h.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "edge_tracker_internal.h"
#include "subpixel.h"
#include "mapnav/vision/edge_tracker.h"

namespace mapnav {

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

Vec2 rotateVec(const Vec2& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

/// Perpendicular of an image direction: the direction turned clockwise on screen (up → right).
Vec2 across(const Vec2& d) { return {-d.y(), d.x()}; }

}  // namespace

double bandLevel(double r, double g, double b, GreyBand band) {
  switch (band) {
    case GreyBand::Blue: return b;
    case GreyBand::Luminance: return 0.299 * r + 0.587 * g + 0.114 * b;
    case GreyBand::NormalizedGreen: return 255.0 * (g + 1) / (r + g + b + 3);
    case GreyBand::NormalizedRed: return 255.0 * (r + 1) / (r + g + b + 3);
  }
  return 0;
}

GreyImage toGrey(const std::uint8_t* rgb, int width, int height, GreyBand band) {
  GreyImage g;
  g.width = width;
  g.height = height;
  const std::size_t n = static_cast<std::size_t>(width) * height;
  g.data.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* p = rgb + 3 * i;
    g.data[i] = static_cast<float>(bandLevel(p[0], p[1], p[2], band));
  }
  return g;
}

namespace {

// The edge profile: column k (offset o = k − (W − 1) / 2 across, along n) is the mean of the L
// nearest-pixel samples centre + o n + t d, t = j − (L − 1) / 2; NaN when fewer than L / 4 fall
// inside the image. As written first: every sample rounded by std::lround and checked.
void profileReference(const GreyImage& image, const Vec2& centre, const Vec2& d, const Vec2& n, int L,
                      std::vector<double>& prof) {
  const int W = static_cast<int>(prof.size());
  for (int k = 0; k < W; ++k) {
    const double o = k - (W - 1) / 2.0;
    double sum = 0;
    int count = 0;
    for (int j = 0; j < L; ++j) {
      const double t = j - (L - 1) / 2.0;
      const Vec2 p = centre + o * n + t * d;
      const long u = std::lround(p.x()), v = std::lround(p.y());
      if (u < 0 || v < 0 || u >= image.width || v >= image.height) continue;
      sum += image.at(static_cast<int>(u), static_cast<int>(v));
      ++count;
    }
    prof[k] = count * 4 >= L ? sum / count : kNaN;
  }
}

// std::lround(x), inline: the integer part by truncation and the exact remainder x − trunc(x).
// NaN and |x| >= 2^63 give LONG_MIN, outside every image (as lround's unspecified value does).
inline long roundHalfAway(double x) {
  if (!(std::abs(x) < 9.2e18)) return std::numeric_limits<long>::min();
  const long t = static_cast<long>(x);
  const double f = x - static_cast<double>(t);
  return t + (f >= 0.5) - (f <= -0.5);
}

// std::lround(x) for 0 <= x < 2^51, branch-free (the compiler vectorises it): x rounded to the
// nearest integer with ties to even by the 1.5 · 2^52 trick, then a tie moved up (lround rounds
// halves away from zero).
inline int nearestInside(double x) {
  constexpr double kShift = 6755399441055744.0;  // 1.5 · 2^52: x + kShift has no bits below 1
  const double r = (x + kShift) - kShift;
  return static_cast<int>(r) + static_cast<int>(x - r == 0.5);
}

// The same profile, the same sums of the same samples in the same order (the same bits): each
// column's base centre + o n computed once (the reference evaluates (centre + o n) + t d too),
// lround inlined, and, when the window's corners are a pixel inside the image (the samples are
// affine in o and t, so then every one is inside), no per-sample bounds check and the rounding
// of a column's samples vectorised.
void profileFast(const GreyImage& image, const Vec2& centre, const Vec2& d, const Vec2& n, int L,
                 std::vector<double>& prof) {
  const int W = static_cast<int>(prof.size());
  const double o0 = -(W - 1) / 2.0, t0 = -(L - 1) / 2.0;
  bool inside = true;
  for (const double o : {o0, -o0})
    for (const double t : {t0, -t0}) {
      const double x = centre.x() + o * n.x() + t * d.x(), y = centre.y() + o * n.y() + t * d.y();
      inside = inside && x >= 1 && y >= 1 && x <= image.width - 2.0 && y <= image.height - 2.0;
    }
  const float* pixels = image.data.data();
  const long width = image.width, height = image.height;
  const int row = image.width;
  thread_local std::vector<double> ts;
  thread_local std::vector<int> index;  // an image has fewer than 2^31 pixels
  ts.resize(L);
  index.resize(L);
  for (int j = 0; j < L; ++j) ts[j] = j - (L - 1) / 2.0;
  for (int k = 0; k < W; ++k) {
    const double o = k - (W - 1) / 2.0;
    const double bx = centre.x() + o * n.x(), by = centre.y() + o * n.y();
    double sum = 0;
    int count = 0;
    if (inside) {
      for (int j = 0; j < L; ++j) index[j] = nearestInside(by + ts[j] * d.y()) * row + nearestInside(bx + ts[j] * d.x());
      for (int j = 0; j < L; ++j) sum += pixels[index[j]];
      count = L;
    } else {
      for (int j = 0; j < L; ++j) {
        const double t = j - (L - 1) / 2.0;
        const long u = roundHalfAway(bx + t * d.x()), v = roundHalfAway(by + t * d.y());
        if (u < 0 || v < 0 || u >= width || v >= height) continue;
        sum += pixels[v * width + u];
        ++count;
      }
    }
    prof[k] = count * 4 >= L ? sum / count : kNaN;
  }
}

EdgeMatch orientedEdgeWith(bool reference, const GreyImage& image, const Vec2& centre, const Vec2& direction,
                           const OrientedEdgeParams& params, int polarity) {
  EdgeMatch best;
  const int L = std::max(1, params.along_px), W = std::max(4, params.across_px);
  const int h = std::max(1, params.step_half_width_px);
  const Vec2 d0 = direction.normalized();
  const int na = params.angle_step_deg > 0 ? static_cast<int>(std::floor(params.angle_search_deg / params.angle_step_deg))
                                            : 0;
  double best_score = -std::numeric_limits<double>::infinity();
  std::vector<double> prof(W), scores(W);
  for (int ai = -na; ai <= na; ++ai) {
    const Vec2 d = rotateVec(d0, ai * params.angle_step_deg * kDeg);
    const Vec2 n = across(d);
    if (reference) profileReference(image, centre, d, n, L, prof);
    else profileFast(image, centre, d, n, L, prof);
    // Correlation with the ideal step at each position (step between k-1 and k).
    int kbest = -1;
    double sbest = -std::numeric_limits<double>::infinity();
    for (int k = 0; k < W; ++k) {
      scores[k] = kNaN;
      if (k - h < 0 || k + h > W) continue;
      if (std::abs(k - 0.5 - (W - 1) / 2.0) > params.max_offset_px) continue;
      // An edge point outside the image is no edge seen: there the profile's columns hold only
      // their part inside the image, and where that part ends looks like a step.
      const Vec2 at = centre + (k - 0.5 - (W - 1) / 2.0) * n;
      if (at.x() < 0 || at.y() < 0 || at.x() > image.width - 1 || at.y() > image.height - 1) continue;
      double l = 0, r = 0;
      bool ok = true;
      for (int i = 1; i <= h && ok; ++i) {
        if (std::isnan(prof[k - i]) || std::isnan(prof[k + i - 1])) ok = false;
        else {
          l += prof[k - i];
          r += prof[k + i - 1];
        }
      }
      if (!ok) continue;
      const double c = (r - l) / h;
      const double s = polarity == 0 ? std::abs(c) : polarity * c;
      scores[k] = s;
      if (s > sbest) {
        sbest = s;
        kbest = k;
      }
    }
    if (kbest < 0 || sbest <= best_score) continue;
    best_score = sbest;
    // Sub-pixel position: parabola through the neighbouring scores (0 beside a NaN: parabolaPeak).
    const double frac = kbest > 0 && kbest + 1 < W ? parabolaPeak(scores[kbest - 1], scores[kbest], scores[kbest + 1]) : 0.0;
    const double pos = kbest - 0.5 + frac - (W - 1) / 2.0;
    best.found = true;
    best.point = centre + pos * n;
    best.direction = d;
    double l = 0, r = 0, mean = 0, var = 0, slope = 0;
    for (int i = 1; i <= h; ++i) {
      l += prof[kbest - i];
      r += prof[kbest + i - 1];
    }
    best.contrast = (r - l) / h;
    for (int i = kbest - h; i < kbest + h; ++i) mean += prof[i];
    mean /= 2 * h;
    for (int i = kbest - h; i < kbest + h; ++i) var += (prof[i] - mean) * (prof[i] - mean);
    const double sd = std::sqrt(var / (2 * h));
    best.correlation = sd > 1e-9 ? (best.contrast / 2) / sd : 0;
    for (int i = kbest - h; i + 1 < kbest + h; ++i) slope = std::max(slope, std::abs(prof[i + 1] - prof[i]));
    best.width_px = slope > 1e-9 ? std::abs(best.contrast) / slope : 0;
    best.profile = prof;
  }
  return best;
}

}  // namespace

EdgeMatch orientedEdge(const GreyImage& image, const Vec2& centre, const Vec2& direction,
                       const OrientedEdgeParams& params, int polarity) {
  return orientedEdgeWith(false, image, centre, direction, params, polarity);
}

EdgeMatch orientedEdgeReference(const GreyImage& image, const Vec2& centre, const Vec2& direction,
                                const OrientedEdgeParams& params, int polarity) {
  return orientedEdgeWith(true, image, centre, direction, params, polarity);
}

}  // namespace mapnav
