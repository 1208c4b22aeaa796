// The view footprint (see viewFootprint in camera.h): the image border walked onto the ground
// plane (FootprintWalker), clipped to the near/far window (Window), and simplified into the
// counter-clockwise parts of the ground region in view.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/polygon.h"

namespace mapnav {

namespace {


constexpr int kSamplesPerSide = 32;
constexpr double kMergeTolerance = 1e-3;          // m: vertices this close to their neighbours' line go
constexpr double kChordTolerance = 2e-3;          // m: the ground outline's chords stay this close to it
constexpr double kChordRelativeTolerance = 1e-4;  // or this fraction of the distance, if more
constexpr double kMaxSkyStep = 0.1;               // rad: sky samples' azimuths at most this far apart
constexpr int kMaxRefineDepth = 10;               // at most 2^10 extra samples between two border samples
constexpr double kMaxLateral = 1e6;               // m: the region's extent to either side of the camera

enum class SampleKind { None, Ground, Sky };

struct Sample {
  SampleKind kind = SampleKind::None;
  Vec2 point = Vec2::Zero();
};

// The footprint is computed on the ground plane closed by a circle of radius R about the optical
// centre's foot, with R so large that the circle lies outside the window near ≤ x − x_c ≤ far,
// |y − y_c| ≤ kMaxLateral. Every ray of the image border is mapped to the plane: to the ground point
// it meets when that is within R, else (beyond R, at or above the horizon) to the point of the circle
// in the ray's horizontal direction. The map is continuous along the border, and the image of the
// border, a closed curve, winds once around exactly the ground points that are in view (its sky part
// runs along the circle, outside the window, unless the camera sees the zenith). Clipping the curve
// to the window (Window::clip) gives the region's parts. (Sutherland–Hodgman clipping would keep the
// winding numbers too, but joins separate parts by zero-width bridges along the window's edges.)
class FootprintWalker {
 public:
  FootprintWalker(const Camera& camera, double radius)
      : camera_(camera), center_(camera.center()), foot_(center_.x(), center_.y()), radius_(radius) {
    const CameraIntrinsics& in = camera.intrinsics();
    principal_ = Vec2(in.cx, in.cy);
  }

  /// The point of the image border at parameter s in [0, 4]: the sides top (left → right), right
  /// (top → bottom), bottom (right → left), left (bottom → top), clockwise in the image.
  Vec2 border(double s) const {
    const double w = camera_.width();
    const double h = camera_.height();
    const int side = std::clamp(static_cast<int>(std::floor(s)), 0, 3);
    const double f = std::clamp(s - side, 0.0, 1.0);
    switch (side) {
      case 0:
        return {-0.5 + f * w, -0.5};
      case 1:
        return {w - 0.5, -0.5 + f * h};
      case 2:
        return {w - 0.5 - f * w, h - 0.5};
      default:
        return {-0.5, h - 0.5 - f * h};
    }
  }

  /// Where the border point at s maps (see above). Border pixels outside the lens' field (a
  /// fish-eye's corners) are first moved towards the principal point onto the field's edge.
  Sample evaluate(double s) const {
    const Vec2 pixel = border(s);
    auto d = camera_.ray(pixel);
    if (!d) {
      if (!camera_.ray(principal_)) return {};
      Vec2 inside = principal_;
      Vec2 outside = pixel;
      for (int k = 0; k < 60; ++k) {
        const Vec2 mid = 0.5 * (inside + outside);
        (camera_.ray(mid) ? inside : outside) = mid;
      }
      d = camera_.ray(inside);
      if (!d) return {};
    }
    const Vec2 horizontal(d->x(), d->y());
    if (d->z() < 0.0) {
      const double t = center_.z() / -d->z();
      if (t * horizontal.norm() <= radius_) return {SampleKind::Ground, foot_ + t * horizontal};
    }
    const double n = horizontal.norm();
    if (!(n > 1e-12)) return {};  // straight up
    return {SampleKind::Sky, foot_ + (radius_ / n) * horizontal};
  }

  /// The closed curve: the samples, the points where a sample's kind changes (found by bisection
  /// along the border), and more samples where the ground outline curves (a fish-eye's, a distorted
  /// lens') or the sky's azimuth turns fast.
  Polygon2 ring() const {
    constexpr int n = 4 * kSamplesPerSide;
    Polygon2 out;
    out.reserve(2 * n);
    Sample current = evaluate(0.0);
    for (int i = 0; i < n; ++i) {
      const double s0 = static_cast<double>(i) / kSamplesPerSide;
      const double s1 = static_cast<double>(i + 1) / kSamplesPerSide;  // border(4) is border(0)
      const Sample next = evaluate(s1);
      if (current.kind != SampleKind::None) out.push_back(current.point);
      refine(s0, current, s1, next, 0, out);
      current = next;
    }
    return out;
  }

 private:
  /// Appends the curve's points strictly between border parameters s0 and s1.
  void refine(double s0, const Sample& a, double s1, const Sample& b, int depth, Polygon2& out) const {
    if (a.kind != b.kind) {
      double lo = s0;
      double hi = s1;
      Sample lo_sample = a;
      Sample hi_sample = b;
      for (int k = 0; k < 50; ++k) {
        const double mid = 0.5 * (lo + hi);
        const Sample m = evaluate(mid);
        if (m.kind == a.kind) {
          lo = mid;
          lo_sample = m;
        } else {
          hi = mid;
          hi_sample = m;
        }
      }
      if (lo > s0) {
        refine(s0, a, lo, lo_sample, depth + 1, out);
        if (lo_sample.kind != SampleKind::None) out.push_back(lo_sample.point);
      }
      if (hi < s1) {
        if (hi_sample.kind != SampleKind::None) out.push_back(hi_sample.point);
        refine(hi, hi_sample, s1, b, depth + 1, out);
      }
      return;
    }
    if (a.kind == SampleKind::None || depth >= kMaxRefineDepth) return;
    const double s = 0.5 * (s0 + s1);
    const Sample m = evaluate(s);
    if (m.kind == a.kind) {
      if (a.kind == SampleKind::Ground) {
        const Vec2 chord = b.point - a.point;
        const double len = chord.norm();
        const double sag = len > 0.0 ? std::abs(cross2(chord, m.point - a.point)) / len : (m.point - a.point).norm();
        if (sag <= std::max(kChordTolerance, kChordRelativeTolerance * (m.point - foot_).norm())) return;
      } else {  // sky: on the circle, so the chord is good while the azimuths are close
        const Vec2 u = a.point - foot_;
        const Vec2 v = b.point - foot_;
        if (std::abs(std::atan2(cross2(u, v), u.dot(v))) <= kMaxSkyStep) return;
      }
    }
    refine(s0, a, s, m, depth + 1, out);
    if (m.kind != SampleKind::None) out.push_back(m.point);
    refine(s, m, s1, b, depth + 1, out);
  }

  const Camera& camera_;
  Vec3 center_;
  Vec2 foot_;  ///< the optical centre's foot on the ground
  double radius_;
  Vec2 principal_;
};

/// The window near ≤ x − x_c ≤ far, |y − y_c| ≤ kMaxLateral and the clipping of the closed curve to
/// it (Weiler–Atherton against a rectangle). The curve keeps the ground in view on its right: the
/// image border is walked clockwise as seen in the image, and every lens and mount maps that to a
/// clockwise walk round the ground it sees (the optical centre is above the ground). The pieces of the
/// curve inside the window are joined by walking the window's edge clockwise from where one leaves to
/// where the next enters, which gives each connected part of the region as a clockwise ring.
class Window {
 public:
  Window(double x0, double x1, double y0, double y1) : x0_(x0), x1_(x1), y0_(y0), y1_(y1) {}

  std::vector<Polygon2> clip(const Polygon2& ring) const {
    const std::size_t n = ring.size();
    if (n < 3) return {};
    std::size_t start = n;
    for (std::size_t i = 0; i < n && start == n; ++i) {
      if (!inside(ring[i])) start = i;
    }
    if (start == n) return {ring};  // all of it in the window
    // The pieces inside, each from where the curve enters the window to where it leaves.
    std::vector<Polygon2> chains;
    bool open = false;
    for (std::size_t k = 0; k < n; ++k) {
      const Vec2& a = ring[(start + k) % n];
      const Vec2& b = ring[(start + k + 1) % n];
      double t0 = 0.0;
      double t1 = 1.0;
      if (!segmentInside(a, b, t0, t1)) {
        open = false;
        continue;
      }
      const Vec2 p0 = t0 == 0.0 ? a : snap(a + t0 * (b - a));
      const Vec2 p1 = t1 == 1.0 ? b : snap(a + t1 * (b - a));
      if (!open || t0 > 0.0) {
        chains.push_back({p0});
        open = true;
      }
      if (p1 != chains.back().back()) chains.back().push_back(p1);
      if (t1 < 1.0) open = false;
    }
    std::vector<Polygon2> pieces;
    for (Polygon2& c : chains) {
      if (c.size() >= 2) pieces.push_back(std::move(c));
    }
    if (pieces.empty()) {
      // The curve does not cross the window: the window is all in view or not at all.
      if (winding(ring, Vec2(0.5 * (x0_ + x1_), 0.5 * (y0_ + y1_))) == 0) return {};
      return {{Vec2(x0_, y1_), Vec2(x1_, y1_), Vec2(x1_, y0_), Vec2(x0_, y0_)}};
    }
    std::vector<double> entry(pieces.size());
    std::vector<double> exit(pieces.size());
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      entry[i] = perimeter(pieces[i].front());
      exit[i] = perimeter(pieces[i].back());
    }
    std::vector<bool> used(pieces.size(), false);
    std::vector<Polygon2> out;
    for (std::size_t first = 0; first < pieces.size(); ++first) {
      if (used[first]) continue;
      Polygon2 polygon;
      std::size_t i = first;
      for (std::size_t guard = 0; guard <= pieces.size(); ++guard) {
        used[i] = true;
        polygon.insert(polygon.end(), pieces[i].begin(), pieces[i].end());
        // The next entry clockwise along the window's edge from this exit.
        std::size_t next = i;
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t j = 0; j < pieces.size(); ++j) {
          if (used[j] && j != first) continue;
          const double step = forward(exit[i], entry[j]);
          if (step < best) {
            best = step;
            next = j;
          }
        }
        appendCorners(exit[i], best, polygon);
        if (next == first) break;
        i = next;
      }
      out.push_back(std::move(polygon));
    }
    return out;
  }

 private:
  bool inside(const Vec2& p) const { return p.x() >= x0_ && p.x() <= x1_ && p.y() >= y0_ && p.y() <= y1_; }

  /// Liang–Barsky: the part [t0, t1] of a → b in the window; false when there is none.
  bool segmentInside(const Vec2& a, const Vec2& b, double& t0, double& t1) const {
    const Vec2 d = b - a;
    const std::array<double, 4> p{-d.x(), d.x(), -d.y(), d.y()};
    const std::array<double, 4> q{a.x() - x0_, x1_ - a.x(), a.y() - y0_, y1_ - a.y()};
    t0 = 0.0;
    t1 = 1.0;
    for (int k = 0; k < 4; ++k) {
      if (p[k] == 0.0) {
        if (q[k] < 0.0) return false;
        continue;
      }
      const double r = q[k] / p[k];
      if (p[k] < 0.0) {
        t0 = std::max(t0, r);
      } else {
        t1 = std::min(t1, r);
      }
      if (t0 > t1) return false;
    }
    return true;
  }

  /// A point computed on the window's edge, put exactly on it.
  Vec2 snap(Vec2 p) const {
    p.x() = std::clamp(p.x(), x0_, x1_);
    p.y() = std::clamp(p.y(), y0_, y1_);
    const std::array<double, 4> gap{std::abs(p.x() - x0_), std::abs(p.x() - x1_), std::abs(p.y() - y0_),
                                    std::abs(p.y() - y1_)};
    switch (std::min_element(gap.begin(), gap.end()) - gap.begin()) {
      case 0:
        p.x() = x0_;
        break;
      case 1:
        p.x() = x1_;
        break;
      case 2:
        p.y() = y0_;
        break;
      default:
        p.y() = y1_;
        break;
    }
    return p;
  }

  double width() const { return x1_ - x0_; }
  double height() const { return y1_ - y0_; }
  double length() const { return 2.0 * (width() + height()); }

  /// Clockwise position along the edge from the corner (x0, y1): the edges y = y1, x = x1, y = y0,
  /// x = x0 in turn.
  double perimeter(const Vec2& p) const {
    const std::array<double, 4> gap{std::abs(p.y() - y1_), std::abs(p.x() - x1_), std::abs(p.y() - y0_),
                                    std::abs(p.x() - x0_)};
    switch (std::min_element(gap.begin(), gap.end()) - gap.begin()) {
      case 0:
        return p.x() - x0_;
      case 1:
        return width() + (y1_ - p.y());
      case 2:
        return width() + height() + (x1_ - p.x());
      default:
        return std::fmod(2.0 * width() + height() + (p.y() - y0_), length());
    }
  }

  /// How far clockwise from position a to position b, in [0, length).
  double forward(double a, double b) const {
    const double d = b - a;
    return d >= 0.0 ? d : d + length();
  }

  /// The window's corners passed walking `distance` clockwise from position `from`.
  void appendCorners(double from, double distance, Polygon2& out) const {
    const std::array<double, 4> at{0.0, width(), width() + height(), 2.0 * width() + height()};
    const std::array<Vec2, 4> corner{Vec2(x0_, y1_), Vec2(x1_, y1_), Vec2(x1_, y0_), Vec2(x0_, y0_)};
    std::array<std::pair<double, int>, 4> order;
    for (int k = 0; k < 4; ++k) order[static_cast<std::size_t>(k)] = {forward(from, at[static_cast<std::size_t>(k)]), k};
    std::sort(order.begin(), order.end());
    for (const auto& [d, k] : order) {
      if (d > 0.0 && d < distance) out.push_back(corner[static_cast<std::size_t>(k)]);
    }
  }

  /// The winding number of `ring` about p.
  static int winding(const Polygon2& ring, const Vec2& p) {
    int w = 0;
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const Vec2& a = ring[i];
      const Vec2& b = ring[(i + 1) % ring.size()];
      if (a.y() <= p.y()) {
        if (b.y() > p.y() && cross2(b - a, p - a) > 0.0) ++w;
      } else if (b.y() <= p.y() && cross2(b - a, p - a) < 0.0) {
        --w;
      }
    }
    return w;
  }

  double x0_, x1_, y0_, y1_;
};

/// Distance from p to the line through a and b (to a when they coincide).
double lineDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len = ab.norm();
  if (len == 0.0) return (p - a).norm();
  return std::abs(cross2(ab, p - a)) / len;
}

Polygon2 dropDuplicates(const Polygon2& ring) {
  Polygon2 out;
  for (const Vec2& p : ring) {
    if (out.empty() || (p - out.back()).norm() > 1e-9) out.push_back(p);
  }
  while (out.size() > 1 && (out.front() - out.back()).norm() <= 1e-9) out.pop_back();
  return out;
}

/// Removes vertices while every vertex of the input stays within `tolerance` of the line through the
/// kept neighbours: a straight image edge, sampled many times, becomes one edge, and a zero-width
/// spike (the curve running out along a window edge and back) goes.
Polygon2 mergeCollinear(const Polygon2& ring, double tolerance) {
  const std::size_t n = ring.size();
  if (n < 3) return ring;
  std::vector<std::size_t> kept(n);
  for (std::size_t i = 0; i < n; ++i) kept[i] = i;
  bool changed = true;
  while (changed && kept.size() >= 3) {
    changed = false;
    for (std::size_t k = 0; k < kept.size() && kept.size() >= 3;) {
      const std::size_t prev = kept[(k + kept.size() - 1) % kept.size()];
      const std::size_t next = kept[(k + 1) % kept.size()];
      bool removable = true;
      for (std::size_t j = (prev + 1) % n; j != next; j = (j + 1) % n) {
        if (lineDistance(ring[j], ring[prev], ring[next]) >= tolerance) {
          removable = false;
          break;
        }
      }
      if (removable) {
        kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(k));
        changed = true;
      } else {
        ++k;
      }
    }
  }
  Polygon2 out;
  out.reserve(kept.size());
  for (std::size_t i : kept) out.push_back(ring[i]);
  return out;
}

/// True when the camera sees straight up.
bool seesZenith(const Camera& camera) {
  const auto px = camera.project(camera.center() + Vec3::UnitZ());
  return px && camera.inImage(*px) && camera.ray(*px);
}

}  // namespace

std::vector<Polygon2> viewFootprintParts(const Camera& camera, double near_m, double far_m) {
  if (!std::isfinite(near_m) || !std::isfinite(far_m) || near_m < 0.0 || !(near_m < far_m)) {
    throw InvalidInput("viewFootprint: near_m = " + numberText(near_m) + ", far_m = " + numberText(far_m) +
                       ": need finite 0 <= near_m < far_m");
  }
  // A camera that sees the zenith would see the ground, if at all, round a hole: not rings.
  if (seesZenith(camera)) return {};
  const Vec3 c = camera.center();
  const double radius = 2.0 * std::hypot(far_m, kMaxLateral);
  const Polygon2 ring = dropDuplicates(FootprintWalker(camera, radius).ring());
  const Window window(c.x() + near_m, c.x() + far_m, c.y() - kMaxLateral, c.y() + kMaxLateral);
  std::vector<std::pair<double, Polygon2>> parts;
  for (Polygon2& part : window.clip(ring)) {
    part = mergeCollinear(dropDuplicates(part), kMergeTolerance);
    const double area = signedArea(part);
    if (part.size() < 3 || std::abs(area) < 1e-6) continue;
    parts.emplace_back(std::abs(area), counterClockwise(std::move(part)));
  }
  std::stable_sort(parts.begin(), parts.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<Polygon2> out;
  out.reserve(parts.size());
  for (auto& [area, part] : parts) out.push_back(std::move(part));
  return out;
}

Polygon2 viewFootprint(const Camera& camera, double near_m, double far_m) {
  auto parts = viewFootprintParts(camera, near_m, far_m);
  if (parts.empty()) return {};
  return std::move(parts.front());
}

}  // namespace mapnav
