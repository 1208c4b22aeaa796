#include "mapnav/geometry/pose2.h"

#include "mapnav/core/strprintf.h"

#include <cmath>
#include <limits>

#include "mapnav/geometry/types.h"

namespace mapnav {

double normalizeAngle(double radians) {
  if (!std::isfinite(radians)) return radians;
  constexpr double kTwoPi = 2.0 * kPi;
  // std::remainder gives a value in [-pi, pi]; fold -pi (and anything rounding below it) to +pi.
  double a = std::remainder(radians, kTwoPi);
  if (a <= -kPi) a += kTwoPi;
  if (a > kPi) a -= kTwoPi;
  return a;
}

namespace {

// sin(theta)/theta and (1 - cos(theta))/theta, with Taylor series near zero (errors O(theta^4)
// and O(theta^5) respectively, far below double precision for |theta| < 1e-4).
void vCoefficients(double theta, double& sinByTheta, double& oneMinusCosByTheta) {
  if (std::abs(theta) < 1e-4) {
    const double t2 = theta * theta;
    sinByTheta = 1.0 - t2 / 6.0;
    oneMinusCosByTheta = theta / 2.0 - theta * t2 / 24.0;
  } else {
    sinByTheta = std::sin(theta) / theta;
    oneMinusCosByTheta = (1.0 - std::cos(theta)) / theta;
  }
}

}  // namespace

double degreesFor(double radians) {
  if (radians == 0.0 || !std::isfinite(radians)) return radians;  // keeps 0 (and -0) as it is
  const double nearest = radToDeg(radians);
  auto length = [](double value) { return numberText(value).size(); };  // of the shortest round-trip text
  double best = nearest;
  std::size_t best_length = std::numeric_limits<std::size_t>::max();
  double candidate = nearest;
  for (int k = 0; k < 8; ++k) candidate = std::nextafter(candidate, -std::numeric_limits<double>::infinity());
  for (int k = 0; k <= 16; ++k, candidate = std::nextafter(candidate, std::numeric_limits<double>::infinity())) {
    if (degToRad(candidate) != radians) continue;
    if (length(candidate) < best_length) {
      best = candidate;
      best_length = length(candidate);
    }
  }
  return best;
}

Pose2::Pose2(double x, double y, double heading) : t_(x, y), heading_(normalizeAngle(heading)) {}

Pose2::Pose2(const Vec2& translation, double heading) : t_(translation), heading_(normalizeAngle(heading)) {}

Pose2 Pose2::exp(const Tangent& xi) {
  const double theta = xi.z();
  double a = 0, b = 0;
  vCoefficients(theta, a, b);
  // V = [[a, -b], [b, a]]
  const Vec2 t(a * xi.x() - b * xi.y(), b * xi.x() + a * xi.y());
  return Pose2(t, theta);
}

Pose2::Tangent Pose2::log() const {
  const double theta = heading_;
  const double half = 0.5 * theta;
  // V^-1 = [[c, half], [-half, c]] with c = half * cot(half) (Sophus' halftheta_by_tan_of_halftheta).
  double c = 0;
  if (std::abs(theta) < 1e-4) {
    const double t2 = theta * theta;
    c = 1.0 - t2 / 12.0 - t2 * t2 / 720.0;
  } else {
    c = half * std::cos(half) / std::sin(half);
  }
  return {c * t_.x() + half * t_.y(), -half * t_.x() + c * t_.y(), theta};
}

Mat2 Pose2::rotation() const {
  const double c = std::cos(heading_), s = std::sin(heading_);
  Mat2 r;
  r << c, -s, s, c;
  return r;
}

Mat3 Pose2::matrix() const {
  Mat3 m = Mat3::Identity();
  m.topLeftCorner<2, 2>() = rotation();
  m.topRightCorner<2, 1>() = t_;
  return m;
}

Pose2 Pose2::operator*(const Pose2& other) const {
  return Pose2(transform(other.t_), heading_ + other.heading_);
}

Pose2 Pose2::inverse() const {
  return Pose2(-(rotation().transpose() * t_), -heading_);
}

Vec2 Pose2::transform(const Vec2& p) const { return rotation() * p + t_; }

Segment2 Pose2::transform(const Segment2& s) const { return {transform(s.a), transform(s.b)}; }

Vec2 Pose2::inverseTransform(const Vec2& p) const { return rotation().transpose() * (p - t_); }

Vec2 Pose2::rotate(const Vec2& v) const { return rotation() * v; }

Pose2 Pose2::interpolate(const Pose2& a, const Pose2& b, double s) {
  const Tangent delta = (a.inverse() * b).log();
  return a * exp(s * delta);
}

Mat3 rotatePoseCovariance(const Mat3& covariance, const Mat2& rotation) {
  Mat3 r = Mat3::Identity();
  r.topLeftCorner<2, 2>() = rotation;
  return r * covariance * r.transpose();
}

}  // namespace mapnav
