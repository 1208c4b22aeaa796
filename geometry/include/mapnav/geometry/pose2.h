#pragma once
// SE(2) rigid motions. A Pose2 maps points of a child frame (e.g. the vehicle: x forward, y left)
// into its parent frame (e.g. the world): p_parent = R(heading) * p_child + translation.
// Invariant: heading() is always in (-pi, pi].
#include "mapnav/geometry/segment2.h"
#include "mapnav/geometry/types.h"

namespace mapnav {

class Pose2 {
 public:
  /// The tangent vector (vx, vy, omega) of SE(2), as in Sophus' SE2::log.
  using Tangent = Eigen::Vector3d;

  Pose2() = default;  ///< identity
  Pose2(double x, double y, double heading);
  Pose2(const Vec2& translation, double heading);

  static Pose2 identity() { return {}; }
  /// The group exponential: the pose reached by moving with constant twist `xi` for unit time.
  static Pose2 exp(const Tangent& xi);
  /// The inverse of exp: exp(log(p)) == p, for heading in (-pi, pi].
  Tangent log() const;

  double x() const { return t_.x(); }
  double y() const { return t_.y(); }
  double heading() const { return heading_; }
  const Vec2& translation() const { return t_; }
  Mat2 rotation() const;
  /// The 3x3 homogeneous matrix [R t; 0 0 1].
  Mat3 matrix() const;

  /// Composition: (a * b) maps b's child frame into a's parent frame.
  Pose2 operator*(const Pose2& other) const;
  Pose2 inverse() const;

  /// Child-frame point → parent frame.
  Vec2 transform(const Vec2& p) const;
  Segment2 transform(const Segment2& s) const;
  /// Parent-frame point → child frame (== inverse().transform(p)).
  Vec2 inverseTransform(const Vec2& p) const;
  /// A direction (no translation) child → parent.
  Vec2 rotate(const Vec2& v) const;

  /// Geodesic interpolation on SE(2): a at s = 0, b at s = 1 (a * exp(s * log(a^-1 b))).
  static Pose2 interpolate(const Pose2& a, const Pose2& b, double s);

 private:
  Vec2 t_ = Vec2::Zero();
  double heading_ = 0.0;
};

/// A pose covariance (x, y, heading) with its position block expressed in other axes: R P Rᵀ for
/// R = diag(`rotation`, 1); the heading's variance is the same in every frame. With the pose's
/// rotation transposed: world axes onto the vehicle's (forward, left); with the rotation: back.
Mat3 rotatePoseCovariance(const Mat3& covariance, const Mat2& rotation);

}  // namespace mapnav
