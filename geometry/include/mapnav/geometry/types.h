#pragma once
// Named Eigen types used across mapnav. World frame: local metric ENU (x east, y north, metres).
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace mapnav {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
using Box2 = Eigen::AlignedBox2d;

/// A closed ring of vertices, the first not repeated at the end. Orientation is not fixed unless a
/// function says so.
using Polygon2 = std::vector<Vec2>;

inline constexpr double kPi = 3.14159265358979323846;
inline double degToRad(double deg) { return deg * kPi / 180.0; }
inline double radToDeg(double rad) { return rad * 180.0 / kPi; }

/// Degrees for `radians` that degToRad turns back into exactly `radians`, the shortest such decimal
/// when there is one, else the nearest: what files written in degrees (cameras, logs) store, so
/// that they read back to the same radians.
double degreesFor(double radians);

/// The angle wrapped into (-pi, pi].
double normalizeAngle(double radians);

/// The 2-D cross product a.x*b.y - a.y*b.x (positive when b is counter-clockwise of a).
inline double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// The unit vector at `heading` radians counter-clockwise from +x.
inline Vec2 unitVector(double heading) { return {std::cos(heading), std::sin(heading)}; }

/// The left normal (rotated +90 degrees) of v.
inline Vec2 leftNormal(const Vec2& v) { return {-v.y(), v.x()}; }

}  // namespace mapnav
