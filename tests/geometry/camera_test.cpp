#include "mapnav/geometry/camera.h"

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "mapnav/core/error.h"
#include "mapnav/geometry/polygon.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

// The Terregator-like pin-hole of maps/cameras/terregator_pinhole.json: 512 × 480, f = 904 px,
// optical centre 1.5 m up, tilted 22° down.
constexpr double kF = 904.0;
constexpr double kH = 1.5;
const double kTilt = degToRad(22.0);

CameraIntrinsics intrinsics(double f, std::vector<double> distortion = {}) {
  CameraIntrinsics in;
  in.width = 512;
  in.height = 480;
  in.fx = f;
  in.fy = f;
  in.cx = 255.5;
  in.cy = 239.5;
  in.distortion = std::move(distortion);
  return in;
}

CameraMount mount(double tilt, double height = kH, double yaw = 0.0, double roll = 0.0) {
  CameraMount m;
  m.height_m = height;
  m.tilt_rad = tilt;
  m.yaw_rad = yaw;
  m.roll_rad = roll;
  return m;
}

std::unique_ptr<Camera> pinhole(double f = kF, double tilt = kTilt, std::vector<double> distortion = {}) {
  return createCamera(LensModel::Pinhole, intrinsics(f, std::move(distortion)), mount(tilt));
}

// ---- the mount ----------------------------------------------------------------------------------------

TEST(CameraMount, RotationMapsTheCameraAxesAsDocumented) {
  const auto level = pinhole(kF, 0.0);
  const Mat3& r = level->rotation();
  EXPECT_TRUE(r.col(0).isApprox(Vec3(0, -1, 0), 1e-15));  // camera x (right) → vehicle −y
  EXPECT_TRUE(r.col(1).isApprox(Vec3(0, 0, -1), 1e-15));  // camera y (down) → vehicle −z
  EXPECT_TRUE(r.col(2).isApprox(Vec3(1, 0, 0), 1e-15));   // camera z (optical axis) → vehicle x

  // Tilt then yaw: the optical axis is (cos β cos ψ, cos β sin ψ, −sin β), whatever the roll.
  const double yaw = degToRad(30.0);
  const auto turned = createCamera(LensModel::Pinhole, intrinsics(kF), mount(kTilt, kH, yaw, degToRad(15.0)));
  const Vec3 axis = turned->rotation() * Vec3::UnitZ();
  EXPECT_NEAR((axis - Vec3(std::cos(kTilt) * std::cos(yaw), std::cos(kTilt) * std::sin(yaw), -std::sin(kTilt))).norm(),
              0.0, 1e-15);
  EXPECT_NEAR((turned->rotation().transpose() * turned->rotation() - Mat3::Identity()).norm(), 0.0, 1e-15);
  EXPECT_NEAR(turned->rotation().determinant(), 1.0, 1e-15);

  CameraMount offset = mount(kTilt);
  offset.offset = Vec2(0.7, -0.2);
  const auto moved = createCamera(LensModel::Pinhole, intrinsics(kF), offset);
  EXPECT_EQ(moved->center(), Vec3(0.7, -0.2, kH));
}

TEST(CameraMount, PositiveRollTurnsTheCameraClockwiseInTheImage) {
  // Roll +10°: the camera's right side goes down, so the scene turns counter-clockwise in the
  // picture: a ground point straight ahead and below the principal point moves to its right.
  const auto rolled = createCamera(LensModel::Pinhole, intrinsics(kF), mount(kTilt, kH, 0.0, degToRad(10.0)));
  const auto px = rolled->projectGround(Vec2(3.0, 0.0));
  ASSERT_TRUE(px);
  EXPECT_GT(px->x(), 255.5);
  EXPECT_GT(px->y(), 239.5);
  // The horizon rises to the right: a far point ahead-right is higher in the image than ahead-left.
  const auto right = rolled->project(Vec3(1e4, -2e3, kH));
  const auto left = rolled->project(Vec3(1e4, 2e3, kH));
  ASSERT_TRUE(right && left);
  EXPECT_LT(right->y(), left->y());
}

// ---- the pin-hole, by hand ----------------------------------------------------------------------------

TEST(CameraPinhole, ProjectsTheGroundAheadOntoTheCentreColumn) {
  const auto cam = pinhole();
  for (double d : {1.0, 2.0, 3.0, 5.0, 8.0, 12.0, 30.0, 200.0}) {
    SCOPED_TRACE(d);
    // The ray to (d, 0, 0) is atan(h / d) below the horizon, atan(h / d) − β below the optical axis.
    const double v = 239.5 + kF * std::tan(std::atan(kH / d) - kTilt);
    const auto px = cam->projectGround(Vec2(d, 0.0));
    ASSERT_TRUE(px);
    EXPECT_NEAR(px->x(), 255.5, 1e-9);
    EXPECT_NEAR(px->y(), v, 1e-9);
  }
  // The paper's Terregator numbers: the bottom edge of the image sees 2.0 m, the top edge 12.0 m.
  EXPECT_NEAR(cam->backproject(Vec2(255.5, 479.5))->x(), 2.0001, 1e-4);
  EXPECT_NEAR(cam->backproject(Vec2(255.5, -0.5))->x(), 11.9886, 1e-4);
}

TEST(CameraPinhole, PointsLeftOfTheAxisAppearLeftOfTheCentre) {
  const auto cam = pinhole();
  const double d = 5.0;
  const double y = 0.5;
  // Depth along the optical axis (cos β, 0, −sin β) of (d, y, −h): d cos β + h sin β; camera x = −y.
  const double depth = d * std::cos(kTilt) + kH * std::sin(kTilt);
  const auto left = cam->projectGround(Vec2(d, y));
  const auto right = cam->projectGround(Vec2(d, -y));
  ASSERT_TRUE(left && right);
  EXPECT_LT(left->x(), 255.5);
  EXPECT_GT(right->x(), 255.5);
  EXPECT_NEAR(left->x(), 255.5 - kF * y / depth, 1e-9);
  EXPECT_NEAR(right->x(), 255.5 + kF * y / depth, 1e-9);
  EXPECT_NEAR(left->y(), right->y(), 1e-9);
}

TEST(CameraPinhole, HorizonRowAndPrincipalPoint) {
  // A wide lens so that the horizon (v = cy − f tan β) is inside the image.
  const double f = 300.0;
  const auto cam = pinhole(f);
  const double horizon = 239.5 - f * std::tan(kTilt);  // 118.3
  const auto far = cam->project(Vec3(1e9, 0.0, kH));    // level with the optical centre, far away
  ASSERT_TRUE(far);
  EXPECT_NEAR(far->y(), horizon, 1e-6);
  const auto far_left = cam->project(Vec3(1e9, 3e8, kH));
  ASSERT_TRUE(far_left);
  EXPECT_NEAR(far_left->y(), horizon, 1e-6);

  for (double u : {0.0, 255.5, 511.0}) {
    EXPECT_FALSE(cam->backproject(Vec2(u, horizon - 1.0)));
    EXPECT_FALSE(cam->backproject(Vec2(u, 0.0)));
    const auto below = cam->backproject(Vec2(u, horizon + 1.0));
    ASSERT_TRUE(below);
    EXPECT_GT(below->x(), 100.0);
  }
  // The principal point sees the ground where the optical axis meets it, h / tan β ahead.
  const auto g = cam->backproject(Vec2(255.5, 239.5));
  ASSERT_TRUE(g);
  EXPECT_VEC2_NEAR(*g, Vec2(kH / std::tan(kTilt), 0.0), 1e-12);
}

TEST(CameraPinhole, PointsBehindProjectToNothing) {
  const auto cam = pinhole();
  EXPECT_FALSE(cam->projectGround(Vec2(-5.0, 0.0)));
  EXPECT_FALSE(cam->project(Vec3(-1.0, 0.3, kH)));
  EXPECT_FALSE(cam->project(cam->center()));
  // Behind the image plane (in front of the vehicle, but above and behind the tilted camera's plane).
  EXPECT_FALSE(cam->project(Vec3(0.1, 0.0, 10.0)));
  // Out of the image but in front: a pixel, not nothing.
  const auto side = cam->projectGround(Vec2(3.0, 20.0));
  ASSERT_TRUE(side);
  EXPECT_FALSE(cam->inImage(*side));
}

TEST(CameraPinhole, InImageIsThePixelArea) {
  const auto cam = pinhole();
  EXPECT_TRUE(cam->inImage(Vec2(-0.5, -0.5)));
  EXPECT_TRUE(cam->inImage(Vec2(511.5, 479.5)));
  EXPECT_FALSE(cam->inImage(Vec2(-0.51, 10)));
  EXPECT_FALSE(cam->inImage(Vec2(10, 479.51)));
}

// ---- round trips, every model -------------------------------------------------------------------------

struct LensCase {
  std::string name;
  LensModel model;
  CameraIntrinsics intrinsics;
  CameraMount mount;
};

std::vector<LensCase> lensCases() {
  const std::vector<double> rad_tan{-0.2, 0.05, 0.001, -0.001};
  const std::vector<double> equidistant{0.05, -0.01, 0.002, -0.0005};
  CameraMount yawed = mount(degToRad(25.0), 1.2, degToRad(-20.0), degToRad(5.0));
  yawed.offset = Vec2(0.4, 0.1);
  return {
      {"pinhole", LensModel::Pinhole, intrinsics(kF), mount(kTilt)},
      {"pinhole wide", LensModel::Pinhole, intrinsics(300.0), mount(kTilt)},
      {"pinhole k1 k2 p1 p2", LensModel::Pinhole, intrinsics(300.0, rad_tan), mount(kTilt)},
      {"pinhole k1 k2 p1 p2 k3", LensModel::Pinhole, intrinsics(250.0, {-0.2, 0.05, 0.001, -0.001, -0.002}), yawed},
      {"paper fisheye", LensModel::PaperFisheye, intrinsics(257.0), mount(degToRad(20.0))},
      {"paper fisheye yawed", LensModel::PaperFisheye, intrinsics(230.0), yawed},
      {"equidistant", LensModel::EquidistantFisheye, intrinsics(180.0), mount(degToRad(20.0))},
      {"equidistant k1-k4", LensModel::EquidistantFisheye, intrinsics(180.0, equidistant), mount(degToRad(20.0))},
      {"equidistant k1-k4 yawed", LensModel::EquidistantFisheye, intrinsics(160.0, equidistant), yawed},
  };
}

TEST(CameraLens, ProjectOfBackprojectIsThePixel) {
  for (const LensCase& c : lensCases()) {
    SCOPED_TRACE(c.name);
    const auto cam = createCamera(c.model, c.intrinsics, c.mount);
    int ground = 0;
    int sky = 0;
    for (double v = -0.5; v <= 479.5; v += 12.0) {
      for (double u = -0.5; u <= 511.5; u += 16.0) {
        const Vec2 pixel(u, v);
        const auto ray = cam->ray(pixel);
        const auto g = cam->backproject(pixel);
        if (!ray) {
          EXPECT_FALSE(g);
          continue;
        }
        EXPECT_NEAR(ray->norm(), 1.0, 1e-12);
        if (ray->z() >= 0.0) {  // at or above the horizon
          EXPECT_FALSE(g);
          ++sky;
          continue;
        }
        ASSERT_TRUE(g) << u << ", " << v;
        ++ground;
        const auto back = cam->projectGround(*g);
        ASSERT_TRUE(back) << u << ", " << v;
        EXPECT_LE((*back - pixel).norm(), 1e-6) << u << ", " << v;
        // The ray's direction also projects back to the pixel.
        const auto along = cam->project(cam->center() + 3.0 * *ray);
        ASSERT_TRUE(along);
        EXPECT_LE((*along - pixel).norm(), 1e-6) << u << ", " << v;
      }
    }
    EXPECT_GT(ground, 200);
    if (c.name != "pinhole") {
      EXPECT_GT(sky, 0);
    }
  }
}

TEST(CameraLens, BackprojectOfProjectIsTheGroundPoint) {
  for (const LensCase& c : lensCases()) {
    SCOPED_TRACE(c.name);
    const auto cam = createCamera(c.model, c.intrinsics, c.mount);
    int seen = 0;
    for (double x = -3.0; x <= 30.0; x += 0.75) {
      for (double y = -15.0; y <= 15.0; y += 0.75) {
        const Vec2 point(x, y);
        const auto px = cam->projectGround(point);
        if (!px || !cam->inImage(*px)) continue;
        ++seen;
        const auto back = cam->backproject(*px);
        ASSERT_TRUE(back) << x << ", " << y;
        EXPECT_LE((*back - point).norm(), 1e-9 * std::max(1.0, point.norm())) << x << ", " << y;
      }
    }
    EXPECT_GT(seen, 30);
  }
}

// ---- the fish-eyes, by hand ---------------------------------------------------------------------------

// The vehicle-frame point 4 m from the optical centre at camera-frame direction (θ off the axis,
// azimuth φ in the image).
Vec3 atAngle(const Camera& cam, double theta, double phi) {
  const Vec3 d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  return cam.center() + 4.0 * (cam.rotation() * d);
}

TEST(CameraLens, PaperFisheyeIsPerpendicularProjectionOfTheUnitSphere) {
  CameraIntrinsics in = intrinsics(257.0);
  in.fy = 250.0;  // different scales, as the paper's x and y scale factors
  const auto cam = createCamera(LensModel::PaperFisheye, in, mount(degToRad(20.0), kH, degToRad(10.0)));
  const auto axis = cam->project(cam->center() + 7.0 * (cam->rotation() * Vec3::UnitZ()));
  ASSERT_TRUE(axis);
  EXPECT_VEC2_NEAR(*axis, Vec2(255.5, 239.5), 1e-9);
  for (double theta : {0.1, 0.5, 1.0, 1.4, 1.55}) {
    for (double phi : {0.0, 0.7, 2.0, -2.5}) {
      SCOPED_TRACE(theta);
      const auto px = cam->project(atAngle(*cam, theta, phi));
      ASSERT_TRUE(px);
      // Radius f·sin θ, along the azimuth.
      EXPECT_VEC2_NEAR(*px, Vec2(255.5 + 257.0 * std::sin(theta) * std::cos(phi), 239.5 + 250.0 * std::sin(theta) * std::sin(phi)),
                       1e-9);
    }
  }
  // The front hemisphere only.
  EXPECT_FALSE(cam->project(atAngle(*cam, 1.7, 0.3)));
  EXPECT_FALSE(cam->project(cam->center() - 2.0 * (cam->rotation() * Vec3::UnitZ())));
  // Pixels outside the unit circle have no ray.
  EXPECT_FALSE(cam->ray(Vec2(255.5 + 258.0, 239.5)));
  EXPECT_FALSE(cam->ray(Vec2(-0.5, -0.5)));
  const auto edge = cam->ray(Vec2(255.5 + 257.0, 239.5));  // 90° off the axis
  ASSERT_TRUE(edge);
  EXPECT_NEAR(edge->dot(cam->rotation() * Vec3::UnitZ()), 0.0, 1e-12);
}

TEST(CameraLens, EquidistantFisheyeIsOpenCvs) {
  const double k1 = 0.05;
  const double k2 = -0.01;
  const double k3 = 0.002;
  const double k4 = -0.0005;
  const auto cam = createCamera(LensModel::EquidistantFisheye, intrinsics(180.0, {k1, k2, k3, k4}), mount(degToRad(20.0)));
  const auto axis = cam->project(cam->center() + 2.0 * (cam->rotation() * Vec3::UnitZ()));
  ASSERT_TRUE(axis);
  EXPECT_VEC2_NEAR(*axis, Vec2(255.5, 239.5), 1e-12);
  for (double theta : {0.05, 0.4, 1.0, 1.5, 1.75}) {  // 1.75 rad = 100°: beyond the hemisphere
    for (double phi : {0.0, 0.9, -2.2}) {
      SCOPED_TRACE(theta);
      const double t2 = theta * theta;
      const double theta_d = theta * (1 + k1 * t2 + k2 * t2 * t2 + k3 * t2 * t2 * t2 + k4 * t2 * t2 * t2 * t2);
      const auto px = cam->project(atAngle(*cam, theta, phi));
      ASSERT_TRUE(px);
      EXPECT_VEC2_NEAR(*px, Vec2(255.5 + 180.0 * theta_d * std::cos(phi), 239.5 + 180.0 * theta_d * std::sin(phi)), 1e-9);
      // And back: the ray is θ off the axis.
      const auto ray = cam->ray(*px);
      ASSERT_TRUE(ray);
      EXPECT_NEAR(std::acos(std::clamp(ray->dot(cam->rotation() * Vec3::UnitZ()), -1.0, 1.0)), theta, 1e-9);
    }
  }
  // Without coefficients r = f·θ, up to (not including) straight behind.
  const auto plain = createCamera(LensModel::EquidistantFisheye, intrinsics(100.0), mount(0.0));
  const auto side = plain->project(atAngle(*plain, 0.5 * kPi, 0.0));
  ASSERT_TRUE(side);
  EXPECT_VEC2_NEAR(*side, Vec2(255.5 + 100.0 * 0.5 * kPi, 239.5), 1e-9);
  const auto back = plain->project(atAngle(*plain, 3.0, 1.0));
  ASSERT_TRUE(back);
  EXPECT_NEAR((*back - Vec2(255.5, 239.5)).norm(), 300.0, 1e-9);
  EXPECT_FALSE(plain->project(plain->center() - 2.0 * (plain->rotation() * Vec3::UnitZ())));
  // Coefficients that fold θd(θ) back: nothing is imaged beyond the fold, no pixel past it has a ray.
  const auto folding = createCamera(LensModel::EquidistantFisheye, intrinsics(100.0, {-0.2, 0.0, 0.0, 0.0}), mount(0.0));
  // θd = θ − 0.2 θ³ is largest at θ = 1/sqrt(0.6) = 1.29 rad, θd = 0.861.
  EXPECT_TRUE(folding->project(atAngle(*folding, 1.2, 0.0)));
  EXPECT_FALSE(folding->project(atAngle(*folding, 1.4, 0.0)));
  EXPECT_FALSE(folding->ray(Vec2(255.5 + 87.0, 239.5)));
  EXPECT_TRUE(folding->ray(Vec2(255.5 + 85.0, 239.5)));
}

TEST(CameraLens, DistortedPinholeMatchesTheOpenCvFormula) {
  const double k1 = -0.2, k2 = 0.05, p1 = 0.001, p2 = -0.001, k3 = 0.01;
  const auto cam = pinhole(300.0, 0.0, {k1, k2, p1, p2, k3});
  // A level camera: vehicle (X, Y, Z) is camera (−Y, −Z + h, X).
  const Vec3 p(4.0, -1.2, kH - 0.8);
  const double x = 1.2 / 4.0;
  const double y = 0.8 / 4.0;
  const double r2 = x * x + y * y;
  const double radial = 1 + k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2;
  const double xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
  const double yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
  const auto px = cam->project(p);
  ASSERT_TRUE(px);
  EXPECT_VEC2_NEAR(*px, Vec2(255.5 + 300.0 * xd, 239.5 + 300.0 * yd), 1e-9);
  // Strong barrel distortion folds r(1 + k1 r²) back beyond r = 1/sqrt(3·0.5): not imaged there.
  const auto barrel = pinhole(300.0, 0.0, {-0.5, 0.0, 0.0, 0.0});
  EXPECT_TRUE(barrel->project(Vec3(4.0, -0.8 * 4.0 / std::sqrt(1.5), kH)));
  EXPECT_FALSE(barrel->project(Vec3(4.0, -1.2 * 4.0 / std::sqrt(1.5), kH)));
}

// ---- validation ---------------------------------------------------------------------------------------

std::string rejection(LensModel model, const CameraIntrinsics& in, const CameraMount& m) {
  try {
    createCamera(model, in, m);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "accepted";
}

TEST(CameraLens, CreateCameraRejectsBadInputsNamingTheField) {
  const CameraMount m = mount(kTilt);
  auto with = [](auto change) {
    CameraIntrinsics in = intrinsics(kF);
    change(in);
    return in;
  };
  EXPECT_EQ(rejection(LensModel::Pinhole, with([](auto& in) { in.fx = -3; }), m), "CameraIntrinsics::fx = -3: must be finite and > 0");
  EXPECT_EQ(rejection(LensModel::Pinhole, with([](auto& in) { in.fy = 0; }), m), "CameraIntrinsics::fy = 0: must be finite and > 0");
  EXPECT_EQ(rejection(LensModel::Pinhole, with([](auto& in) { in.fy = std::nan(""); }), m),
            "CameraIntrinsics::fy = nan: must be finite and > 0");
  EXPECT_EQ(rejection(LensModel::Pinhole, with([](auto& in) { in.width = 0; }), m), "CameraIntrinsics::width = 0: must be > 0");
  EXPECT_EQ(rejection(LensModel::Pinhole, with([](auto& in) { in.height = -480; }), m),
            "CameraIntrinsics::height = -480: must be > 0");
  EXPECT_EQ(rejection(LensModel::Pinhole, with([](auto& in) { in.cx = INFINITY; }), m), "CameraIntrinsics::cx = inf: must be finite");
  EXPECT_EQ(rejection(LensModel::Pinhole, with([](auto& in) { in.distortion = {0.1, 0.2, 0.3}; }), m),
            "CameraIntrinsics::distortion has 3 coefficients: a pinhole takes 0, 4 (k1 k2 p1 p2) or 5 (k1 k2 p1 p2 k3) "
            "coefficients");
  EXPECT_EQ(rejection(LensModel::Pinhole, with([](auto& in) { in.distortion = {0.1, 0.2, 0.3, NAN}; }), m),
            "CameraIntrinsics::distortion[3] = nan: must be finite");
  EXPECT_NE(rejection(LensModel::PaperFisheye, with([](auto& in) { in.distortion = {0.1, 0.2, 0.3, 0.4}; }), m).find(
                "CameraIntrinsics::distortion has 4 coefficients"),
            std::string::npos);
  EXPECT_NE(rejection(LensModel::EquidistantFisheye, with([](auto& in) { in.distortion = {0.1, 0.2, 0.3, 0.4, 0.5}; }), m)
                .find("CameraIntrinsics::distortion has 5 coefficients"),
            std::string::npos);
  EXPECT_EQ(rejection(LensModel::Pinhole, intrinsics(kF, {0.1, 0.2, 0.3, 0.4}), m), "accepted");
  EXPECT_EQ(rejection(LensModel::Pinhole, intrinsics(kF, {0.1, 0.2, 0.3, 0.4, 0.5}), m), "accepted");
  EXPECT_EQ(rejection(LensModel::EquidistantFisheye, intrinsics(kF, {0.1, 0.2, 0.3, 0.4}), m), "accepted");

  CameraMount bad = m;
  bad.height_m = 0;
  EXPECT_EQ(rejection(LensModel::Pinhole, intrinsics(kF), bad), "CameraMount::height_m = 0: must be finite and > 0");
  bad = m;
  bad.tilt_rad = INFINITY;
  EXPECT_EQ(rejection(LensModel::Pinhole, intrinsics(kF), bad), "CameraMount::tilt_rad = inf: must be finite");
  bad = m;
  bad.offset.y() = NAN;
  EXPECT_EQ(rejection(LensModel::Pinhole, intrinsics(kF), bad), "CameraMount::offset.y = nan: must be finite");
  EXPECT_NE(rejection(static_cast<LensModel>(7), intrinsics(kF), m).find("LensModel = 7"), std::string::npos);
}

TEST(CameraLens, ModelNames) {
  for (LensModel model : {LensModel::Pinhole, LensModel::PaperFisheye, LensModel::EquidistantFisheye}) {
    EXPECT_EQ(lensModelFromString(toString(model)), model);
  }
  EXPECT_EQ(toString(LensModel::PaperFisheye), "fisheye-orthographic");
  EXPECT_FALSE(lensModelFromString("fisheye"));
  const auto cam = createCamera(LensModel::EquidistantFisheye, intrinsics(200.0, {0.1, 0, 0, 0}), mount(0.3));
  EXPECT_EQ(cam->model(), LensModel::EquidistantFisheye);
  EXPECT_EQ(cam->intrinsics(), intrinsics(200.0, {0.1, 0, 0, 0}));
  EXPECT_EQ(cam->mount(), mount(0.3));
  EXPECT_EQ(cam->width(), 512);
  EXPECT_EQ(cam->height(), 480);
}

// ---- the view footprint -------------------------------------------------------------------------------

// Where the ray of the pixel (u, v) of an untilted-by-roll, unyawed pin-hole meets the ground. With
// a = (u − cx)/f, b = (v − cy)/f the camera-frame direction (a, b, 1) is, in the vehicle frame,
// (cos β − b sin β, −a, −(sin β + b cos β)); it meets z = 0 at t = h / (sin β + b cos β).
Vec2 groundOfPixel(double u, double v, double f, double tilt, double h) {
  const double a = (u - 255.5) / f;
  const double b = (v - 239.5) / f;
  const double t = h / (std::sin(tilt) + b * std::cos(tilt));
  return {t * (std::cos(tilt) - b * std::sin(tilt)), -t * a};
}

// Every vertex of `actual` within `tolerance` of a vertex of `expected` and the other way round.
::testing::AssertionResult sameVertices(const Polygon2& actual, const Polygon2& expected, double tolerance) {
  auto covered = [tolerance](const Polygon2& from, const Polygon2& in) {
    for (const Vec2& p : from) {
      bool found = false;
      for (const Vec2& q : in) found = found || (p - q).norm() <= tolerance;
      if (!found) return false;
    }
    return true;
  };
  if (actual.size() == expected.size() && covered(actual, expected) && covered(expected, actual)) {
    return ::testing::AssertionSuccess();
  }
  ::testing::AssertionResult failure = ::testing::AssertionFailure();
  failure << "got";
  for (const Vec2& p : actual) failure << " (" << p.x() << ", " << p.y() << ")";
  failure << ", expected";
  for (const Vec2& p : expected) failure << " (" << p.x() << ", " << p.y() << ")";
  return failure;
}

TEST(CameraFootprint, PinholeIsThePapersTrapezoid) {
  const auto cam = pinhole();
  const Polygon2 footprint = viewFootprint(*cam, 0.5, 50.0);
  // The image corners' rays (pixel-area corners): near corners at x = 2.0001, y = ±0.6843; far
  // corners at x = 11.9886, y = ±3.3069.
  const Vec2 near_left = groundOfPixel(-0.5, 479.5, kF, kTilt, kH);
  const Vec2 near_right = groundOfPixel(511.5, 479.5, kF, kTilt, kH);
  const Vec2 far_right = groundOfPixel(511.5, -0.5, kF, kTilt, kH);
  const Vec2 far_left = groundOfPixel(-0.5, -0.5, kF, kTilt, kH);
  EXPECT_NEAR(near_left.x(), 2.0001, 1e-4);
  EXPECT_NEAR(near_left.y(), 0.6843, 1e-4);
  EXPECT_NEAR(far_left.x(), 11.9886, 1e-4);
  EXPECT_NEAR(far_left.y(), 3.3069, 1e-4);
  EXPECT_TRUE(sameVertices(footprint, {near_right, far_right, far_left, near_left}, 1e-3));
  EXPECT_GT(signedArea(footprint), 0.0);
  EXPECT_TRUE(isSimple(footprint));
  // Counter-clockwise, starting anywhere: the successor of the near-right corner is the far-right one.
  for (std::size_t i = 0; i < footprint.size(); ++i) {
    if ((footprint[i] - near_right).norm() < 1e-3) {
      EXPECT_VEC2_NEAR(footprint[(i + 1) % footprint.size()], far_right, 1e-3);
    }
  }
}

TEST(CameraFootprint, ClipsToNearAndFar) {
  const auto cam = pinhole();
  const Vec2 near_left = groundOfPixel(-0.5, 479.5, kF, kTilt, kH);
  const Vec2 far_left = groundOfPixel(-0.5, -0.5, kF, kTilt, kH);
  // The left edge of the trapezoid (the ground line through its left corners) at x.
  auto leftAt = [&](double x) {
    const double s = (x - near_left.x()) / (far_left.x() - near_left.x());
    return near_left.y() + s * (far_left.y() - near_left.y());
  };
  const Polygon2 footprint = viewFootprint(*cam, 3.0, 8.0);
  EXPECT_TRUE(sameVertices(footprint, {{3.0, -leftAt(3.0)}, {8.0, -leftAt(8.0)}, {8.0, leftAt(8.0)}, {3.0, leftAt(3.0)}}, 1e-3));
  EXPECT_GT(signedArea(footprint), 0.0);
  // Far beyond what the image sees: the trapezoid; nearer than the bottom edge: the same.
  EXPECT_EQ(viewFootprint(*cam, 0.0, 1e4).size(), 4u);
  // Nothing between 0.5 m and 1.5 m is in view.
  EXPECT_TRUE(viewFootprint(*cam, 0.5, 1.5).empty());
  EXPECT_THROW(viewFootprint(*cam, 5.0, 5.0), InvalidInput);
  EXPECT_THROW(viewFootprint(*cam, -1.0, 5.0), InvalidInput);
  EXPECT_THROW(viewFootprint(*cam, 1.0, NAN), InvalidInput);
}

TEST(CameraFootprint, HorizonInViewEndsAtFar) {
  // Wide lens: the horizon crosses the image at v = 118; the sky is cut at 20 m.
  const auto cam = pinhole(300.0);
  const Polygon2 footprint = viewFootprint(*cam, 1.0, 20.0);
  ASSERT_FALSE(footprint.empty());
  EXPECT_GT(signedArea(footprint), 0.0);
  EXPECT_TRUE(isSimple(footprint));
  double max_x = -1e9;
  for (const Vec2& p : footprint) max_x = std::max(max_x, p.x());
  EXPECT_NEAR(max_x, 20.0, 1e-9);
  // The far edge ends where the image's side edges (a = ±256/300) meet the ground 20 m ahead:
  // (h cos β − h b sin β) / (sin β + b cos β) = 20 gives b = (h cos β − 20 sin β) / (20 cos β + h sin β)
  // = −0.31935, and there y = ±h a / (sin β + b cos β) = ±16.3034.
  const double a = 256.0 / 300.0;
  const double b = (kH * std::cos(kTilt) - 20.0 * std::sin(kTilt)) / (20.0 * std::cos(kTilt) + kH * std::sin(kTilt));
  const double y = kH * a / (std::sin(kTilt) + b * std::cos(kTilt));
  EXPECT_NEAR(y, 16.3034, 1e-4);
  const Vec2 near_left = groundOfPixel(-0.5, 479.5, 300.0, kTilt, kH);
  const auto at = [&](double x) {  // the left side line at x
    return near_left.y() + (x - near_left.x()) / (20.0 - near_left.x()) * (y - near_left.y());
  };
  EXPECT_TRUE(sameVertices(footprint, {{1.0, at(1.0)}, {1.0, -at(1.0)}, {20.0, -y}, {20.0, y}}, 1e-3));
}

TEST(CameraFootprint, EmptyWhenLookingAtTheSky) {
  const auto up = pinhole(kF, degToRad(-30.0));
  EXPECT_TRUE(viewFootprint(*up, 0.5, 30.0).empty());
  const auto fisheye_up = createCamera(LensModel::EquidistantFisheye, intrinsics(500.0), mount(degToRad(-60.0)));
  EXPECT_TRUE(viewFootprint(*fisheye_up, 0.5, 30.0).empty());
}

TEST(CameraFootprint, YawTurnsTheFootprintLeft) {
  const double yaw = degToRad(30.0);
  const auto straight = pinhole();
  const auto turned = createCamera(LensModel::Pinhole, intrinsics(kF), mount(kTilt, kH, yaw));
  const Polygon2 a = viewFootprint(*straight, 0.0, 1e3);
  const Polygon2 b = viewFootprint(*turned, 0.0, 1e3);
  EXPECT_NEAR(centroid(a).y(), 0.0, 1e-9);
  EXPECT_GT(centroid(b).y(), 2.0);
  // Without clipping, the yawed footprint is the straight one turned 30° about the camera's foot.
  Polygon2 rotated;
  for (const Vec2& p : a) rotated.push_back(Eigen::Rotation2Dd(yaw) * p);
  EXPECT_TRUE(sameVertices(b, rotated, 1e-6));
  EXPECT_GT(signedArea(b), 0.0);
  // Clipped at 8 m ahead (vehicle x): every vertex within the band.
  for (const Vec2& p : viewFootprint(*turned, 2.5, 8.0)) {
    EXPECT_GE(p.x(), 2.5 - 1e-9);
    EXPECT_LE(p.x(), 8.0 + 1e-9);
  }
}

TEST(CameraFootprint, RollOf90DegreesSwapsTheImageSides) {
  // Rolled 90° the 512 × 480 image sees what a 480 × 512 one with fx, fy swapped sees.
  CameraIntrinsics in = intrinsics(kF);
  in.fy = 850.0;
  const auto rolled = createCamera(LensModel::Pinhole, in, mount(kTilt, kH, 0.0, degToRad(90.0)));
  CameraIntrinsics swapped = in;
  std::swap(swapped.width, swapped.height);
  std::swap(swapped.fx, swapped.fy);
  std::swap(swapped.cx, swapped.cy);
  const auto upright = createCamera(LensModel::Pinhole, swapped, mount(kTilt));
  const Polygon2 a = viewFootprint(*rolled, 0.5, 100.0);
  const Polygon2 b = viewFootprint(*upright, 0.5, 100.0);
  EXPECT_EQ(a.size(), 4u);
  EXPECT_TRUE(sameVertices(a, b, 1e-6));
  // Rolled 90° the image is tall: nearer near edge and farther far edge than unrolled.
  const Polygon2 c = viewFootprint(*createCamera(LensModel::Pinhole, in, mount(kTilt)), 0.5, 100.0);
  auto extent = [](const Polygon2& ring) {
    double lo = 1e9, hi = -1e9;
    for (const Vec2& p : ring) {
      lo = std::min(lo, p.x());
      hi = std::max(hi, p.x());
    }
    return std::pair(lo, hi);
  };
  EXPECT_LT(extent(a).first, extent(c).first);
  EXPECT_GT(extent(a).second, extent(c).second);
}

TEST(CameraFootprint, OffsetMountClipsFromTheOpticalCentre) {
  CameraMount m = mount(kTilt);
  m.offset = Vec2(1.0, 0.5);
  const auto cam = createCamera(LensModel::Pinhole, intrinsics(kF), m);
  const Polygon2 moved = viewFootprint(*cam, 3.0, 8.0);
  Polygon2 expected;
  for (const Vec2& p : viewFootprint(*pinhole(), 3.0, 8.0)) expected.push_back(p + Vec2(1.0, 0.5));
  EXPECT_TRUE(sameVertices(moved, expected, 1e-9));
}

TEST(CameraFootprint, FisheyesGiveCurvedSimpleRegions) {
  const std::vector<double> equidistant{0.05, -0.01, 0.002, -0.0005};
  struct Case {
    const char* name;
    LensModel model;
    CameraIntrinsics in;
    CameraMount m;
  } cases[] = {
      {"paper", LensModel::PaperFisheye, intrinsics(257.0), mount(degToRad(20.0))},
      {"paper yawed", LensModel::PaperFisheye, intrinsics(257.0), mount(degToRad(20.0), kH, degToRad(-40.0))},
      {"equidistant", LensModel::EquidistantFisheye, intrinsics(180.0, equidistant), mount(degToRad(20.0))},
      {"distorted pinhole", LensModel::Pinhole, intrinsics(300.0, {-0.2, 0.05, 0.001, -0.001}), mount(kTilt)},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const auto cam = createCamera(c.model, c.in, c.m);
    const Polygon2 footprint = viewFootprint(*cam, 1.0, 12.0);
    ASSERT_GE(footprint.size(), 5u);
    EXPECT_GT(signedArea(footprint), 0.0);
    EXPECT_TRUE(isSimple(footprint));
    for (const Vec2& p : footprint) {
      EXPECT_GE(p.x(), 1.0 - 1e-9);
      EXPECT_LE(p.x(), 12.0 + 1e-9);
    }
    // Ground points that are in the image and in the band are inside (to the outline's sampling).
    for (double x = 1.5; x <= 11.5; x += 1.0) {
      for (double y = -6.0; y <= 6.0; y += 1.0) {
        const auto px = cam->projectGround(Vec2(x, y));
        if (!px) continue;
        const bool inside = contains(footprint, Vec2(x, y));
        const bool safely_in_image = px->x() > 3 && px->x() < 508 && px->y() > 3 && px->y() < 476;
        if (safely_in_image) {
          EXPECT_TRUE(inside) << x << ", " << y;
        }
        if (inside) {
          EXPECT_TRUE(cam->inImage(*px) || boundaryDistance(footprint, Vec2(x, y)) < 0.05) << x << ", " << y;
        }
      }
    }
  }
}

TEST(CameraFootprint, PartsOfARegionTheBandCuts) {
  // The paper's fish-eye looking 37° up, a tall image: the middle of the bottom edge looks
  // asin(163/250) − 37° = 3.7° below the horizon, at the ground 23 m ahead, but the bottom corners
  // look farther down. Between 2 m and 11 m only the ground seen near the two corners is in view.
  CameraIntrinsics in;
  in.width = 244;
  in.height = 326;
  in.fx = 275.0;
  in.fy = 250.0;
  in.cx = 121.5;
  in.cy = 162.5;
  const auto cam = createCamera(LensModel::PaperFisheye, in, mount(degToRad(-37.0)));
  EXPECT_NEAR(cam->backproject(Vec2(121.5, 325.5))->x(), 23.2, 0.1);
  const std::vector<Polygon2> parts = viewFootprintParts(*cam, 2.0, 11.0);
  ASSERT_EQ(parts.size(), 2u);
  for (const Polygon2& part : parts) {
    EXPECT_GT(signedArea(part), 0.0);
    EXPECT_TRUE(isSimple(part));
    for (const Vec2& p : part) {
      EXPECT_GE(p.x(), 2.0 - 1e-9);
      EXPECT_LE(p.x(), 11.0 + 1e-9);
    }
  }
  // Mirror images of each other, one on each side.
  EXPECT_NEAR(signedArea(parts[0]), signedArea(parts[1]), 1e-6);
  EXPECT_NEAR(centroid(parts[0]).x(), centroid(parts[1]).x(), 1e-6);
  EXPECT_NEAR(centroid(parts[0]).y(), -centroid(parts[1]).y(), 1e-6);
  EXPECT_GT(std::abs(centroid(parts[0]).y()), 3.0);
  EXPECT_EQ(viewFootprint(*cam, 2.0, 11.0), parts[0]);
  // Out to 40 m the two join.
  EXPECT_EQ(viewFootprintParts(*cam, 2.0, 40.0).size(), 1u);
}

TEST(CameraFootprint, LookingSidewaysReachesTheLateralLimit) {
  // Yawed 90° left and level, the pin-hole sees the ground to its left out to the horizon; the
  // region stops 1000 km out.
  const auto cam = createCamera(LensModel::Pinhole, intrinsics(300.0), mount(degToRad(5.0), kH, degToRad(90.0)));
  const Polygon2 footprint = viewFootprint(*cam, 0.0, 5.0);
  ASSERT_FALSE(footprint.empty());
  EXPECT_TRUE(isSimple(footprint));
  double max_y = 0.0;
  for (const Vec2& p : footprint) max_y = std::max(max_y, p.y());
  EXPECT_DOUBLE_EQ(max_y, 1e6);
  EXPECT_TRUE(contains(footprint, Vec2(2.5, 100.0)));
  EXPECT_FALSE(contains(footprint, Vec2(2.5, -1.0)));
  // Looking straight up: nothing.
  EXPECT_TRUE(viewFootprint(*createCamera(LensModel::EquidistantFisheye, intrinsics(100.0), mount(degToRad(-90.0))), 0.0, 5.0)
                  .empty());
}

}  // namespace
}  // namespace mapnav
