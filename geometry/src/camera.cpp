// Camera (see camera.h): the lens model names, the mount's rotation, the validation of intrinsics
// and mount, and the projections common to every lens. The lenses are in camera_lenses.cpp, the
// view footprint in camera_footprint.cpp.
#include "mapnav/geometry/camera.h"

#include <cmath>
#include <cstddef>
#include <string>
#include <utility>

#include "camera_lenses.h"
#include "mapnav/core/error.h"
#include "mapnav/core/strprintf.h"

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

// ---- validation ------------------------------------------------------------------------------------


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
      return detail::makePinholeCamera(intrinsics, mount);
    case LensModel::PaperFisheye:
      return detail::makePaperFisheyeCamera(intrinsics, mount);
    case LensModel::EquidistantFisheye:
      return detail::makeEquidistantFisheyeCamera(intrinsics, mount);
  }
  throw InvalidInput("LensModel = " + std::to_string(static_cast<int>(model)) + ": not a lens model");
}

std::optional<double> groundWidthPx(const Camera& camera, const Vec2& ground_point, double radius_m) {
  const Vec2 sight = ground_point - camera.center().head<2>();
  const Vec2 across = Vec2(-sight.y(), sight.x()).normalized() * radius_m;
  const auto left = camera.projectGround(ground_point + across), right = camera.projectGround(ground_point - across);
  if (!left || !right) return std::nullopt;
  return (*left - *right).norm();
}

}  // namespace mapnav
