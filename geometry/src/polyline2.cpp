#include "mapnav/geometry/polyline2.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace mapnav {

Polyline2::Polyline2(std::vector<Vec2> points) : points_(std::move(points)) {
  cumulative_.resize(points_.size());
  double s = 0;
  for (std::size_t i = 0; i < points_.size(); ++i) {
    if (i > 0) s += (points_[i] - points_[i - 1]).norm();
    cumulative_[i] = s;
  }
}

std::size_t Polyline2::segmentIndexAt(double s) const {
  if (points_.size() < 2) return 0;
  const double total = length();
  if (!(total > 0)) return 0;
  if (s >= total) {
    for (std::size_t i = points_.size() - 1; i-- > 0;) {
      if (cumulative_[i + 1] > cumulative_[i]) return i;
    }
    return 0;
  }
  if (!(s > 0)) s = 0;  // also NaN
  // First vertex with arc length > s; the segment ending there holds s and has non-zero length.
  const auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), s);
  return static_cast<std::size_t>(it - cumulative_.begin()) - 1;
}

Vec2 Polyline2::pointAt(double s) const {
  if (points_.empty()) return Vec2::Zero();
  const double total = length();
  if (points_.size() < 2 || !(total > 0) || !(s > 0)) return points_.front();
  if (s >= total) return points_.back();
  const std::size_t i = segmentIndexAt(s);
  const double t = (s - cumulative_[i]) / (cumulative_[i + 1] - cumulative_[i]);
  return points_[i] + t * (points_[i + 1] - points_[i]);
}

Vec2 Polyline2::tangentAt(double s) const {
  if (points_.size() < 2 || !(length() > 0)) return {1.0, 0.0};
  return segment(segmentIndexAt(s)).direction();
}

double Polyline2::headingAt(double s) const {
  const Vec2 t = tangentAt(s);
  return std::atan2(t.y(), t.x());
}

Polyline2::Projection Polyline2::project(const Vec2& p) const {
  Projection result;
  if (points_.empty()) {
    result.distance = p.norm();
    return result;
  }
  // Closest non-zero-length segment; strict '<' keeps the smallest arc length on ties.
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::size_t best = kNone;
  double bestT = 0;
  double bestD2 = std::numeric_limits<double>::infinity();
  std::size_t first = kNone, last = kNone;
  for (std::size_t i = 0; i + 1 < points_.size(); ++i) {
    const Vec2& a = points_[i];
    const Vec2 v = points_[i + 1] - a;
    const double l2 = v.squaredNorm();
    if (!(l2 > 0)) continue;
    if (first == kNone) first = i;
    last = i;
    const double t = std::clamp((p - a).dot(v) / l2, 0.0, 1.0);
    const double d2 = (a + t * v - p).squaredNorm();
    if (d2 < bestD2) {
      bestD2 = d2;
      best = i;
      bestT = t;
    }
  }
  if (best == kNone) {  // a single point, or all points equal
    result.point = points_.front();
    result.distance = (p - result.point).norm();
    return result;
  }

  // A closest point at the end of a segment is the start of the next non-zero-length one.
  std::size_t next = kNone;
  if (bestT >= 1.0) {
    for (std::size_t j = best + 1; j + 1 < points_.size(); ++j) {
      if (points_[j + 1] != points_[j]) {
        next = j;
        break;
      }
    }
  }

  const Vec2 dir = segment(best).direction();
  if (bestT <= 0.0 && best == first) {  // at (or before) the start
    result.point = points_[best];
    result.segment = best;
    result.arc_length = 0.0;
    result.distance = (p - result.point).norm();
    result.lateral = cross2(dir, p - result.point);
    if ((p - result.point).dot(dir) >= 0) result.lateral = std::copysign(result.distance, result.lateral);
    return result;
  }
  if (bestT >= 1.0 && best == last) {  // at (or beyond) the end
    result.point = points_[best + 1];
    result.segment = best;
    result.arc_length = length();
    result.distance = (p - result.point).norm();
    result.lateral = cross2(dir, p - result.point);
    if ((p - result.point).dot(dir) <= 0) result.lateral = std::copysign(result.distance, result.lateral);
    return result;
  }

  if (bestT > 0.0 && bestT < 1.0) {  // inside a segment
    result.segment = best;
    result.point = points_[best] + bestT * (points_[best + 1] - points_[best]);
    result.arc_length = cumulative_[best] + bestT * (cumulative_[best + 1] - cumulative_[best]);
    result.distance = (p - result.point).norm();
    result.lateral = std::copysign(result.distance, cross2(dir, p - result.point));
    return result;
  }

  // At an interior vertex: side from the sum of the two segment directions (the vertex's
  // pseudo-normal), which is right in the whole wedge of points whose closest point is the vertex.
  std::size_t in = best, out = best;
  if (bestT >= 1.0) {
    out = next;
  } else {
    for (std::size_t j = best; j-- > 0;) {
      if (points_[j + 1] != points_[j]) {
        in = j;
        break;
      }
    }
  }
  result.segment = out;
  result.point = points_[out];
  result.arc_length = cumulative_[out];
  result.distance = (p - result.point).norm();
  const Vec2 dIn = segment(in).direction(), dOut = segment(out).direction();
  double side = cross2(dIn + dOut, p - result.point);
  if (side == 0) side = cross2(dIn, p - result.point);
  result.lateral = std::copysign(result.distance, side);
  if (side == 0) result.lateral = 0;
  return result;
}

Polyline2 Polyline2::reversed() const { return Polyline2(std::vector<Vec2>(points_.rbegin(), points_.rend())); }

Polyline2 Polyline2::offset(double d) const {
  const std::size_t n = points_.size();
  if (n < 2) return *this;
  // Directions of the nearest non-zero-length segment before / after each vertex.
  std::vector<Vec2> before(n, Vec2::Zero()), after(n, Vec2::Zero());
  std::vector<bool> hasBefore(n, false), hasAfter(n, false);
  for (std::size_t i = 1; i < n; ++i) {
    if (points_[i] != points_[i - 1]) {
      before[i] = segment(i - 1).direction();
      hasBefore[i] = true;
    } else if (hasBefore[i - 1]) {
      before[i] = before[i - 1];
      hasBefore[i] = true;
    }
  }
  for (std::size_t i = n - 1; i-- > 0;) {
    if (points_[i] != points_[i + 1]) {
      after[i] = segment(i).direction();
      hasAfter[i] = true;
    } else if (hasAfter[i + 1]) {
      after[i] = after[i + 1];
      hasAfter[i] = true;
    }
  }

  const double maxMiter = 4.0 * std::abs(d);
  std::vector<Vec2> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& v = points_[i];
    if (hasBefore[i] && hasAfter[i]) {
      const Vec2 m = leftNormal(before[i]) + leftNormal(after[i]);
      const double len = m.norm();
      // The miter point v + k m/|m| lies at distance d from both offset lines when k = 2d/|m|.
      if (len * maxMiter > 2.0 * std::abs(d)) {
        out[i] = v + (2.0 * d / (len * len)) * m;
      } else if (len > 1e-12) {
        out[i] = v + std::copysign(maxMiter, d) * (m / len);
      } else {  // the polyline turns straight back: cap beyond the tip
        out[i] = v + maxMiter * before[i];
      }
    } else if (hasAfter[i]) {
      out[i] = v + d * leftNormal(after[i]);
    } else if (hasBefore[i]) {
      out[i] = v + d * leftNormal(before[i]);
    } else {
      out[i] = v;
    }
  }
  return Polyline2(std::move(out));
}

Polyline2 Polyline2::slice(double s0, double s1) const {
  if (points_.empty()) return {};
  const double total = length();
  s0 = std::clamp(std::isnan(s0) ? 0.0 : s0, 0.0, total);
  s1 = std::clamp(std::isnan(s1) ? 0.0 : s1, 0.0, total);
  if (!(s1 > s0)) return Polyline2({pointAt(s0)});
  std::vector<Vec2> out;
  out.push_back(pointAt(s0));
  for (std::size_t i = 0; i < points_.size(); ++i) {
    if (cumulative_[i] > s0 && cumulative_[i] < s1) out.push_back(points_[i]);
  }
  out.push_back(pointAt(s1));
  return Polyline2(std::move(out));
}

Box2 Polyline2::bounds() const {
  Box2 box;  // empty
  for (const Vec2& p : points_) box.extend(p);
  return box;
}

}  // namespace mapnav
