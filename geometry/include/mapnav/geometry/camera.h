#pragma once
// Camera models: where a ground point appears in the image, and which ground point a pixel sees.
//
// Frames. Vehicle: x forward, y left, z up (REP 103), origin on the ground at the vehicle's
// reference point. Camera: x right, y down, z along the optical axis (OpenCV). Image: u right,
// v down, pixels, origin at the top-left pixel's centre.
//
// The mount places the optical centre at (offset.x, offset.y, height_m) in the vehicle frame and
// turns the camera by yaw (left positive, about z), then tilt (pitch down positive), then roll
// (right-handed about the optical axis: positive roll turns the camera clockwise as seen from
// behind it, so the scene appears turned counter-clockwise in the image).
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "mapnav/geometry/types.h"

namespace mapnav {

enum class LensModel {
  Pinhole,             ///< perspective, optional OpenCV radial-tangential distortion (k1 k2 p1 p2 [k3])
  PaperFisheye,        ///< Wallace 1985, 3.5.1: unit sphere, then perpendicular projection onto the
                       ///< image plane tangent at the optical axis: r = f · sin(θ)
  EquidistantFisheye,  ///< OpenCV cv::fisheye: r = f · θd, θd = θ(1 + k1θ² + k2θ⁴ + k3θ⁶ + k4θ⁸)
};
std::string_view toString(LensModel model);  ///< "pinhole", "fisheye-orthographic", "fisheye-equidistant"
std::optional<LensModel> lensModelFromString(std::string_view text);

struct CameraIntrinsics {
  int width = 512;    ///< image width, pixels
  int height = 480;   ///< image height, pixels
  double fx = 500.0;  ///< focal length, pixels
  double fy = 500.0;
  double cx = 255.5;  ///< principal point, pixels
  double cy = 239.5;
  /// Pinhole: k1 k2 p1 p2 [k3] (OpenCV order) or empty; equidistant fisheye: k1 k2 k3 k4 or empty;
  /// the paper's fisheye: empty.
  std::vector<double> distortion;

  bool operator==(const CameraIntrinsics&) const = default;
};

struct CameraMount {
  Vec2 offset = Vec2::Zero();  ///< optical centre's x (forward), y (left) in the vehicle frame, m
  double height_m = 1.5;       ///< optical centre above the ground, m
  double tilt_rad = 0.38;      ///< pitch below the horizon, positive looks down
  double roll_rad = 0.0;
  double yaw_rad = 0.0;        ///< left positive

  bool operator==(const CameraMount&) const = default;
};

class Camera {
 public:
  virtual ~Camera() = default;

  LensModel model() const { return model_; }
  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  const CameraMount& mount() const { return mount_; }
  int width() const { return intrinsics_.width; }
  int height() const { return intrinsics_.height; }

  /// Vehicle-frame point → pixel; nothing when the lens cannot image it (behind a pin-hole, beyond
  /// the fish-eye's field). The pixel may lie outside the image: see inImage().
  std::optional<Vec2> project(const Vec3& vehicle_point) const;
  /// Ground point (z = 0, vehicle frame) → pixel.
  std::optional<Vec2> projectGround(const Vec2& ground_point) const {
    return project(Vec3(ground_point.x(), ground_point.y(), 0.0));
  }
  /// Pixel → unit direction of its ray in the vehicle frame; nothing outside the lens' field.
  std::optional<Vec3> ray(const Vec2& pixel) const;
  /// Pixel → the ground point (vehicle frame) its ray meets; nothing at or above the horizon.
  std::optional<Vec2> backproject(const Vec2& pixel) const;
  /// Within [-0.5, width - 0.5] × [-0.5, height - 0.5] (the image's pixel area).
  bool inImage(const Vec2& pixel) const;
  /// The optical centre in the vehicle frame.
  Vec3 center() const;
  /// Rotation camera frame → vehicle frame.
  const Mat3& rotation() const { return vehicle_from_camera_; }

 protected:
  Camera(LensModel model, CameraIntrinsics intrinsics, CameraMount mount);
  /// Camera-frame point → pixel (the lens model).
  virtual std::optional<Vec2> projectCamera(const Vec3& p) const = 0;
  /// Pixel → camera-frame direction (not necessarily unit).
  virtual std::optional<Vec3> unprojectCamera(const Vec2& pixel) const = 0;

 private:
  LensModel model_;
  CameraIntrinsics intrinsics_;
  CameraMount mount_;
  Mat3 vehicle_from_camera_;
};

/// Throws InvalidInput naming the bad field (size ≤ 0, focal ≤ 0, wrong number of distortion
/// coefficients for the model, non-finite values, height ≤ 0).
std::unique_ptr<Camera> createCamera(LensModel model, const CameraIntrinsics& intrinsics, const CameraMount& mount);

/// How wide something of radius `radius_m` standing on the ground at `ground_point` (vehicle frame)
/// looks at its foot: the image distance, px, between the two ground points `radius_m` to either
/// side of it across the line of sight from the optical centre. Nothing when either is not imaged.
std::optional<double> groundWidthPx(const Camera& camera, const Vec2& ground_point, double radius_m);

/// The ground region the camera sees between `near_m` and `far_m` ahead of the optical centre
/// (vehicle-frame x distance), as a counter-clockwise polygon in the vehicle frame: the paper's
/// trapezoid for a pin-hole, a curved region for a fish-eye (its outline sampled along the image
/// border). Empty when no ground is in view.
Polygon2 viewFootprint(const Camera& camera, double near_m, double far_m);

/// Every connected part of that region, largest first (viewFootprint is the first). There is one
/// part for any usual mount; a camera looking up with only its bottom corners below the horizon, for
/// one, can see two. The region is also limited to 1000 km either side of the optical centre (a
/// camera looking sideways sees the ground out to the horizon), and is empty for a camera that sees
/// straight up (zenith in the image). Both throw InvalidInput unless 0 ≤ near_m < far_m (finite).
std::vector<Polygon2> viewFootprintParts(const Camera& camera, double near_m, double far_m);

}  // namespace mapnav
