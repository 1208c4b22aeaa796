// The lens models (see camera_lenses.h): pin-hole with radial-tangential distortion, the paper's
// orthographic fish-eye and OpenCV's equidistant fish-eye, each with the radius or angle beyond
// which its mapping folds back.
#include "camera_lenses.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

namespace mapnav::detail {
namespace {

/// The first r in (0, r_max] where the derivative `slope(r)` of a radial mapping stops being positive,
/// or infinity when it stays positive: beyond it the lens folds back and images points twice.
template <class Slope>
double monotonicLimit(Slope slope, double r_max, double infinity) {
  constexpr int kSteps = 20000;
  double previous = 0.0;
  for (int i = 1; i <= kSteps; ++i) {
    const double r = r_max * i / kSteps;
    if (!(slope(r) > 0.0)) {
      double lo = previous;
      double hi = r;
      for (int k = 0; k < 100; ++k) {
        const double mid = 0.5 * (lo + hi);
        (slope(mid) > 0.0 ? lo : hi) = mid;
      }
      return lo;
    }
    previous = r;
  }
  return infinity;
}

// ---- pin-hole with OpenCV radial-tangential distortion ---------------------------------------------

class PinholeCamera final : public Camera {
 public:
  PinholeCamera(CameraIntrinsics intrinsics, const CameraMount& mount)
      : Camera(LensModel::Pinhole, std::move(intrinsics), mount) {
    const std::vector<double>& d = this->intrinsics().distortion;
    distorted_ = !d.empty();
    if (distorted_) {
      k1_ = d[0];
      k2_ = d[1];
      p1_ = d[2];
      p2_ = d[3];
      k3_ = d.size() > 4 ? d[4] : 0.0;
      // d/dr of r·(1 + k1 r² + k2 r⁴ + k3 r⁶); searched up to r = 20 (87° off the axis).
      r_limit_ = monotonicLimit(
          [&](double r) {
            const double r2 = r * r;
            return 1.0 + r2 * (3.0 * k1_ + r2 * (5.0 * k2_ + r2 * 7.0 * k3_));
          },
          20.0, std::numeric_limits<double>::infinity());
    }
  }

 protected:
  std::optional<Vec2> projectCamera(const Vec3& p) const override {
    if (!(p.z() > 0.0)) return std::nullopt;
    Vec2 xy(p.x() / p.z(), p.y() / p.z());
    if (!std::isfinite(xy.x()) || !std::isfinite(xy.y())) return std::nullopt;
    if (distorted_) {
      if (xy.norm() > r_limit_) return std::nullopt;
      xy = distort(xy, nullptr);
    }
    const CameraIntrinsics& in = intrinsics();
    return Vec2(in.fx * xy.x() + in.cx, in.fy * xy.y() + in.cy);
  }

  std::optional<Vec3> unprojectCamera(const Vec2& pixel) const override {
    const CameraIntrinsics& in = intrinsics();
    const Vec2 target((pixel.x() - in.cx) / in.fx, (pixel.y() - in.cy) / in.fy);
    if (!distorted_) return Vec3(target.x(), target.y(), 1.0);
    // Newton on distort(x) = target from x = target, with step halving when a step does not reduce
    // the residual (cv::undistortPoints iterates x ← (target − tangential(x)) / radial(x) instead;
    // Newton converges to the last bit in a handful of steps, also near the image corners).
    Vec2 x = target;
    Mat2 jacobian;
    Vec2 residual = distort(x, &jacobian) - target;
    for (int iteration = 0; iteration < 50 && residual.norm() > 1e-15; ++iteration) {
      const double det = jacobian.determinant();
      if (!(std::abs(det) > 1e-300)) break;
      const Vec2 step = jacobian.inverse() * residual;
      bool improved = false;
      for (double lambda = 1.0; lambda > 1e-6; lambda *= 0.5) {
        const Vec2 candidate = x - lambda * step;
        Mat2 candidate_jacobian;
        const Vec2 candidate_residual = distort(candidate, &candidate_jacobian) - target;
        if (candidate_residual.norm() < residual.norm()) {
          x = candidate;
          residual = candidate_residual;
          jacobian = candidate_jacobian;
          improved = true;
          break;
        }
      }
      if (!improved) break;
    }
    if (!(residual.norm() <= 1e-12 * std::max(1.0, target.norm())) || x.norm() > r_limit_) return std::nullopt;
    return Vec3(x.x(), x.y(), 1.0);
  }

 private:
  /// OpenCV's model on normalised coordinates; the Jacobian d(distorted)/d(x) when asked.
  Vec2 distort(const Vec2& p, Mat2* jacobian) const {
    const double x = p.x();
    const double y = p.y();
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (k1_ + r2 * (k2_ + r2 * k3_));
    const double xd = x * radial + 2.0 * p1_ * x * y + p2_ * (r2 + 2.0 * x * x);
    const double yd = y * radial + p1_ * (r2 + 2.0 * y * y) + 2.0 * p2_ * x * y;
    if (jacobian != nullptr) {
      const double dradial = k1_ + r2 * (2.0 * k2_ + r2 * 3.0 * k3_);  // d radial / d r²
      const double cross = 2.0 * x * y * dradial + 2.0 * p1_ * x + 2.0 * p2_ * y;
      (*jacobian)(0, 0) = radial + 2.0 * x * x * dradial + 2.0 * p1_ * y + 6.0 * p2_ * x;
      (*jacobian)(0, 1) = cross;
      (*jacobian)(1, 0) = cross;
      (*jacobian)(1, 1) = radial + 2.0 * y * y * dradial + 6.0 * p1_ * y + 2.0 * p2_ * x;
    }
    return {xd, yd};
  }

  bool distorted_ = false;
  double k1_ = 0.0, k2_ = 0.0, p1_ = 0.0, p2_ = 0.0, k3_ = 0.0;
  double r_limit_ = std::numeric_limits<double>::infinity();  ///< normalised radius where the model folds
};

// ---- the paper's fish-eye: unit sphere, then perpendicular projection -------------------------------

class PaperFisheyeCamera final : public Camera {
 public:
  PaperFisheyeCamera(CameraIntrinsics intrinsics, const CameraMount& mount)
      : Camera(LensModel::PaperFisheye, std::move(intrinsics), mount) {}

 protected:
  // Wallace 1985, 3.5.1: the point is projected onto the unit sphere about the optical centre, then
  // perpendicularly onto the image plane tangent to the sphere at the optical axis (0, 0, 1). Only
  // the front hemisphere (d.z > 0) is imaged; a direction θ off the axis lands at radius f·sin θ.
  std::optional<Vec2> projectCamera(const Vec3& p) const override {
    const double n = p.norm();
    if (!(n > 0.0) || !std::isfinite(n)) return std::nullopt;
    const Vec3 d = p / n;
    if (!(d.z() > 0.0)) return std::nullopt;
    const CameraIntrinsics& in = intrinsics();
    return Vec2(in.fx * d.x() + in.cx, in.fy * d.y() + in.cy);
  }

  std::optional<Vec3> unprojectCamera(const Vec2& pixel) const override {
    const CameraIntrinsics& in = intrinsics();
    const double a = (pixel.x() - in.cx) / in.fx;
    const double b = (pixel.y() - in.cy) / in.fy;
    const double s = a * a + b * b;
    if (!(s <= 1.0)) return std::nullopt;
    return Vec3(a, b, std::sqrt(std::max(0.0, 1.0 - s)));
  }
};

// ---- OpenCV's equidistant fish-eye (cv::fisheye) ---------------------------------------------------

class EquidistantFisheyeCamera final : public Camera {
 public:
  EquidistantFisheyeCamera(CameraIntrinsics intrinsics, const CameraMount& mount)
      : Camera(LensModel::EquidistantFisheye, std::move(intrinsics), mount) {
    const std::vector<double>& d = this->intrinsics().distortion;
    for (std::size_t i = 0; i < d.size() && i < k_.size(); ++i) k_[i] = d[i];
    theta_max_ = monotonicLimit([&](double t) { return slope(t); }, kPi, kPi);
    theta_d_max_ = distortTheta(theta_max_);
  }

 protected:
  // As cv::fisheye::projectPoints, but with θ = atan2(r, z) so that directions up to 180° off the
  // axis are imaged (OpenCV divides by z first). Directions beyond the angle where θd(θ) stops
  // increasing are not imaged.
  std::optional<Vec2> projectCamera(const Vec3& p) const override {
    const double r = std::hypot(p.x(), p.y());
    const CameraIntrinsics& in = intrinsics();
    if (!std::isfinite(r) || !std::isfinite(p.z())) return std::nullopt;
    if (r == 0.0) {
      if (p.z() > 0.0) return Vec2(in.cx, in.cy);
      return std::nullopt;
    }
    const double theta = std::atan2(r, p.z());
    if (theta > theta_max_ || theta >= kPi) return std::nullopt;
    const double scale = distortTheta(theta) / r;
    return Vec2(in.fx * scale * p.x() + in.cx, in.fy * scale * p.y() + in.cy);
  }

  // As cv::fisheye::undistortPoints: Newton on θd(θ) = θd from θ = θd.
  std::optional<Vec3> unprojectCamera(const Vec2& pixel) const override {
    const CameraIntrinsics& in = intrinsics();
    const double a = (pixel.x() - in.cx) / in.fx;
    const double b = (pixel.y() - in.cy) / in.fy;
    const double theta_d = std::hypot(a, b);
    if (theta_d == 0.0) return Vec3(0.0, 0.0, 1.0);
    if (!(theta_d <= theta_d_max_)) return std::nullopt;
    double theta = std::min(theta_d, theta_max_);
    for (int iteration = 0; iteration < 50; ++iteration) {
      const double f = distortTheta(theta) - theta_d;
      if (std::abs(f) <= 1e-16) break;
      const double next = std::clamp(theta - f / slope(theta), 0.0, theta_max_);
      if (next == theta) break;
      theta = next;
    }
    if (!(std::abs(distortTheta(theta) - theta_d) <= 1e-12)) return std::nullopt;
    const double s = std::sin(theta) / theta_d;
    return Vec3(s * a, s * b, std::cos(theta));
  }

 private:
  double distortTheta(double t) const {
    const double t2 = t * t;
    return t * (1.0 + t2 * (k_[0] + t2 * (k_[1] + t2 * (k_[2] + t2 * k_[3]))));
  }
  double slope(double t) const {
    const double t2 = t * t;
    return 1.0 + t2 * (3.0 * k_[0] + t2 * (5.0 * k_[1] + t2 * (7.0 * k_[2] + t2 * 9.0 * k_[3])));
  }

  std::array<double, 4> k_{0.0, 0.0, 0.0, 0.0};
  double theta_max_ = kPi;    ///< the largest angle off the axis that is imaged
  double theta_d_max_ = kPi;  ///< its θd
};

}  // namespace

std::unique_ptr<Camera> makePinholeCamera(const CameraIntrinsics& intrinsics, const CameraMount& mount) {
  return std::make_unique<PinholeCamera>(intrinsics, mount);
}

std::unique_ptr<Camera> makePaperFisheyeCamera(const CameraIntrinsics& intrinsics, const CameraMount& mount) {
  return std::make_unique<PaperFisheyeCamera>(intrinsics, mount);
}

std::unique_ptr<Camera> makeEquidistantFisheyeCamera(const CameraIntrinsics& intrinsics, const CameraMount& mount) {
  return std::make_unique<EquidistantFisheyeCamera>(intrinsics, mount);
}

}  // namespace mapnav::detail
