#pragma once
// Open polylines parameterised by arc length: road centre lines and edges.
#include <cstddef>
#include <vector>

#include "mapnav/geometry/segment2.h"
#include "mapnav/geometry/types.h"

namespace mapnav {

class Polyline2 {
 public:
  /// Where a point projects onto the polyline.
  struct Projection {
    double arc_length = 0;   ///< s of the closest point, in [0, length()]
    double lateral = 0;      ///< signed distance, positive on the left of the travel direction
    double distance = 0;     ///< |lateral| except beyond the ends, where it is the distance to the end point
    Vec2 point = Vec2::Zero();  ///< the closest point on the polyline
    std::size_t segment = 0;    ///< index of the segment holding it
  };

  Polyline2() = default;
  /// Any number of points; consecutive repeated points make zero-length segments, which every
  /// query skips. Queries on a polyline with fewer than 2 points return its only point (or zero).
  explicit Polyline2(std::vector<Vec2> points);

  const std::vector<Vec2>& points() const { return points_; }
  std::size_t size() const { return points_.size(); }
  bool empty() const { return points_.empty(); }
  const Vec2& front() const { return points_.front(); }
  const Vec2& back() const { return points_.back(); }
  std::size_t segmentCount() const { return points_.size() < 2 ? 0 : points_.size() - 1; }
  Segment2 segment(std::size_t i) const { return {points_[i], points_[i + 1]}; }

  double length() const { return cumulative_.empty() ? 0.0 : cumulative_.back(); }
  /// Arc length at vertex i.
  double arcLengthAt(std::size_t vertex) const { return cumulative_[vertex]; }
  /// Index of the segment holding arc length s (clamped): the non-zero-length segment i with
  /// arcLengthAt(i) <= s < arcLengthAt(i + 1); at length() the last non-zero-length segment.
  /// 0 when the polyline has no segment of non-zero length.
  std::size_t segmentIndexAt(double s) const;
  /// The point at arc length s, clamped to [0, length()].
  Vec2 pointAt(double s) const;
  /// Unit tangent at arc length s (of the segment holding s; at a vertex, of the next segment).
  Vec2 tangentAt(double s) const;
  double headingAt(double s) const;
  /// The closest point of the polyline to p (ties: the smallest arc length).
  Projection project(const Vec2& p) const;

  /// The same points in reverse order.
  Polyline2 reversed() const;
  /// The parallel curve at signed distance d (left positive), with mitred joints (miter length
  /// capped at 4·|d|). Used for road edges.
  Polyline2 offset(double d) const;
  /// The piece between arc lengths s0 < s1 (clamped).
  Polyline2 slice(double s0, double s1) const;
  Box2 bounds() const;

  bool operator==(const Polyline2& other) const { return points_ == other.points_; }

 private:
  std::vector<Vec2> points_;
  std::vector<double> cumulative_;  // cumulative_[i] = arc length at points_[i]
};

}  // namespace mapnav
