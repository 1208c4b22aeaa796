#include "mapnav/geometry/camera.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cstddef>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "mapnav/core/error.h"
#include "mapnav/geometry/polygon.h"

namespace mapnav {

std::string_view toString(LensModel model) {
  switch (model) {
    case LensModel::Pinhole:
      return "pinhole";
    case LensModel::PaperFisheye:
      return "fisheye-orthographic";
    case LensModel::EquidistantFisheye:
      return "fisheye-equidistant";
  }
  return "unknown";
}

std::optional<LensModel> lensModelFromString(std::string_view text) {
  for (LensModel m : {LensModel::Pinhole, LensModel::PaperFisheye, LensModel::EquidistantFisheye}) {
    if (text == toString(m)) return m;
  }
  return std::nullopt;
}

namespace {

// The mount's rotation camera frame → vehicle frame:
//
//   vehicle_from_camera = Rz(yaw) · Ry(tilt) · N · Rz(roll)
//
// N is the nominal mount (level, looking straight ahead): camera z → vehicle x, camera x → vehicle
// −y, camera y → vehicle −z; its columns are the camera axes in the vehicle frame.
// Rz(roll) acts first, in the camera frame, about the optical axis: positive roll turns the camera's
// x axis (image right) towards its y axis (image down), i.e. the camera turns clockwise as drawn in
// the image's u-right/v-down axes, and the right side of the camera goes down (as an aircraft's
// positive roll). The scene therefore appears turned counter-clockwise in the picture.
// Ry(tilt) is about the vehicle's y axis (left): positive turns the optical axis (vehicle x) down to
// (cos tilt, 0, −sin tilt). Rz(yaw) is about the vehicle's z axis (up): positive turns it left.
// So the optical axis is (cos tilt cos yaw, cos tilt sin yaw, −sin tilt) whatever the roll, and the
// tilt is the angle of the optical axis below the horizon whatever the yaw.
Mat3 mountRotation(const CameraMount& mount) {
  Mat3 nominal;
  nominal << 0, 0, 1,  //
      -1, 0, 0,        //
      0, -1, 0;
  const Mat3 yaw = Eigen::AngleAxisd(mount.yaw_rad, Vec3::UnitZ()).toRotationMatrix();
  const Mat3 tilt = Eigen::AngleAxisd(mount.tilt_rad, Vec3::UnitY()).toRotationMatrix();
  const Mat3 roll = Eigen::AngleAxisd(mount.roll_rad, Vec3::UnitZ()).toRotationMatrix();
  return yaw * tilt * nominal * roll;
}

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

// ---- validation ------------------------------------------------------------------------------------

std::string numberText(double value) {
  std::array<char, 64> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

[[noreturn]] void reject(std::string_view field, const std::string& value, std::string_view rule) {
  throw InvalidInput(std::string(field) + " = " + value + ": " + std::string(rule));
}

void requireFinite(std::string_view field, double value) {
  if (!std::isfinite(value)) reject(field, numberText(value), "must be finite");
}

void requirePositive(std::string_view field, double value) {
  if (!std::isfinite(value) || !(value > 0.0)) reject(field, numberText(value), "must be finite and > 0");
}

void validate(LensModel model, const CameraIntrinsics& in, const CameraMount& mount) {
  if (in.width <= 0) reject("CameraIntrinsics::width", std::to_string(in.width), "must be > 0");
  if (in.height <= 0) reject("CameraIntrinsics::height", std::to_string(in.height), "must be > 0");
  requirePositive("CameraIntrinsics::fx", in.fx);
  requirePositive("CameraIntrinsics::fy", in.fy);
  requireFinite("CameraIntrinsics::cx", in.cx);
  requireFinite("CameraIntrinsics::cy", in.cy);
  const std::size_t n = in.distortion.size();
  std::string_view allowed;
  switch (model) {
    case LensModel::Pinhole:
      if (n != 0 && n != 4 && n != 5) allowed = "a pinhole takes 0, 4 (k1 k2 p1 p2) or 5 (k1 k2 p1 p2 k3) coefficients";
      break;
    case LensModel::PaperFisheye:
      if (n != 0) allowed = "the paper's fish-eye (fisheye-orthographic) takes no coefficients";
      break;
    case LensModel::EquidistantFisheye:
      if (n != 0 && n != 4) allowed = "an equidistant fish-eye takes 0 or 4 (k1 k2 k3 k4) coefficients";
      break;
    default:
      throw InvalidInput("LensModel = " + std::to_string(static_cast<int>(model)) + ": not a lens model");
  }
  if (!allowed.empty()) {
    throw InvalidInput("CameraIntrinsics::distortion has " + std::to_string(n) + " coefficients: " + std::string(allowed));
  }
  for (std::size_t i = 0; i < n; ++i) {
    requireFinite("CameraIntrinsics::distortion[" + std::to_string(i) + "]", in.distortion[i]);
  }
  requireFinite("CameraMount::offset.x", mount.offset.x());
  requireFinite("CameraMount::offset.y", mount.offset.y());
  requirePositive("CameraMount::height_m", mount.height_m);
  requireFinite("CameraMount::tilt_rad", mount.tilt_rad);
  requireFinite("CameraMount::roll_rad", mount.roll_rad);
  requireFinite("CameraMount::yaw_rad", mount.yaw_rad);
}

}  // namespace

// ---- Camera ----------------------------------------------------------------------------------------

Camera::Camera(LensModel model, CameraIntrinsics intrinsics, CameraMount mount)
    : model_(model), intrinsics_(std::move(intrinsics)), mount_(mount), vehicle_from_camera_(mountRotation(mount_)) {}

std::optional<Vec2> Camera::project(const Vec3& vehicle_point) const {
  const Vec3 p = vehicle_from_camera_.transpose() * (vehicle_point - center());
  return projectCamera(p);
}

std::optional<Vec3> Camera::ray(const Vec2& pixel) const {
  if (!std::isfinite(pixel.x()) || !std::isfinite(pixel.y())) return std::nullopt;
  const auto d = unprojectCamera(pixel);
  if (!d) return std::nullopt;
  const double n = d->norm();
  if (!(n > 0.0) || !std::isfinite(n)) return std::nullopt;
  return Vec3(vehicle_from_camera_ * (*d / n));
}

std::optional<Vec2> Camera::backproject(const Vec2& pixel) const {
  const auto d = ray(pixel);
  if (!d || !(d->z() < 0.0)) return std::nullopt;
  const Vec3 c = center();
  const double t = c.z() / -d->z();
  const Vec3 p = c + t * *d;
  if (!std::isfinite(p.x()) || !std::isfinite(p.y())) return std::nullopt;
  return Vec2(p.x(), p.y());
}

bool Camera::inImage(const Vec2& pixel) const {
  return pixel.x() >= -0.5 && pixel.x() <= intrinsics_.width - 0.5 && pixel.y() >= -0.5 &&
         pixel.y() <= intrinsics_.height - 0.5;
}

Vec3 Camera::center() const { return Vec3(mount_.offset.x(), mount_.offset.y(), mount_.height_m); }

std::unique_ptr<Camera> createCamera(LensModel model, const CameraIntrinsics& intrinsics, const CameraMount& mount) {
  validate(model, intrinsics, mount);
  switch (model) {
    case LensModel::Pinhole:
      return std::make_unique<PinholeCamera>(intrinsics, mount);
    case LensModel::PaperFisheye:
      return std::make_unique<PaperFisheyeCamera>(intrinsics, mount);
    case LensModel::EquidistantFisheye:
      return std::make_unique<EquidistantFisheyeCamera>(intrinsics, mount);
  }
  throw InvalidInput("LensModel = " + std::to_string(static_cast<int>(model)) + ": not a lens model");
}

// ---- view footprint --------------------------------------------------------------------------------

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
