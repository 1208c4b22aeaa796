// Finding predicted landmarks: on frames ray-cast here, independently of the simulator.
#include "mapnav/vision/landmarks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "mapnav/core/error.h"
#include "mapnav/map/predict.h"
#include "mapnav/testing/support.h"
#include "../../vision/src/subpixel.h"

namespace mapnav {
namespace {

std::unique_ptr<Camera> landmarkCamera() {
  CameraIntrinsics in;
  in.width = 512;
  in.height = 480;
  in.fx = in.fy = 400;
  in.cx = 255.5;
  in.cy = 239.5;
  CameraMount mount;
  mount.height_m = 1.2;
  mount.tilt_rad = degToRad(15);
  return createCamera(LensModel::Pinhole, in, mount);
}

// A straight 3 m concrete path along x with grass beside it, and one landmark.
Map pathWith(const Landmark& landmark) {
  MapData m;
  m.name = "path";
  m.surfaces = {{"concrete", {Vec3(178, 176, 168), Vec3(10, 10, 10)}}, {"grass", {Vec3(70, 120, 50), Vec3(14, 18, 12)}}};
  m.intersections = {{"A", IntersectionKind::End, Vec2(-50, 0), std::nullopt}, {"B", IntersectionKind::End, Vec2(50, 0), std::nullopt}};
  Road r;
  r.id = "R1";
  r.from = "A";
  r.to = "B";
  r.centerline = Polyline2({Vec2(-50, 0), Vec2(50, 0)});
  r.width = 3;
  r.surface = "concrete";
  r.left = r.right = "grass";
  m.roads = {r};
  m.landmarks = {landmark};
  return Map(m);
}

// The frame a vehicle at `pose` sees: every pixel's ray meets the landmark's cylinder (dark grey),
// or the ground (concrete within 1.5 m of y = 0, grass beyond), or the sky; seeded noise of 4 levels.
Image rayCast(const Camera& camera, const Pose2& pose, const Landmark& l, std::uint64_t seed) {
  Image image(camera.width(), camera.height(), 3);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0, 4);
  const Vec3 c = camera.center();
  const Vec2 axis = pose.inverseTransform(l.position);  // the cylinder's axis, vehicle frame
  for (int v = 0; v < camera.height(); ++v) {
    for (int u = 0; u < camera.width(); ++u) {
      Vec3 colour(150, 190, 235);  // sky
      const auto dir = camera.ray(Vec2(u, v));
      if (dir && dir->z() < 0) {
        const double t_ground = -c.z() / dir->z();
        const Vec2 g = (c + t_ground * *dir).head<2>();
        const bool paved = std::abs(pose.transform(g).y()) <= 1.5;
        colour = paved ? Vec3(178, 176, 168) : Vec3(70, 120, 50);
        // The ray against the vertical cylinder: |c.xy + t d.xy - axis| = r.
        const Vec2 o = c.head<2>() - axis, d = dir->head<2>();
        const double a = d.squaredNorm(), b = 2 * o.dot(d), cc = o.squaredNorm() - l.radius * l.radius;
        const double disc = b * b - 4 * a * cc;
        if (disc >= 0) {
          const double t = (-b - std::sqrt(disc)) / (2 * a);
          const double z = c.z() + t * dir->z();
          if (t > 0 && t < t_ground && z >= 0 && z <= l.height) colour = Vec3(60, 60, 66);
        }
      }
      for (int k = 0; k < 3; ++k) {
        image.pixel(u, v)[k] = static_cast<std::uint8_t>(std::clamp(std::lround(colour(k) + noise(rng)), 0L, 255L));
      }
    }
  }
  return image;
}

VisionFrame landmarkFrame(const Image& image, const Camera& camera) {
  VisionFrame f;
  f.width = image.width;
  f.height = image.height;
  f.rgb = image.data.data();
  f.camera = &camera;
  return f;
}

TEST(FindLandmarks, APoleIsFoundAtItsTrueBaseFromAPredictionHalfAMetreOff) {
  const auto camera = landmarkCamera();
  const Landmark pole{"P1", LandmarkKind::Pole, Vec2(5, 2.0), 0.1, 3.0, "", {}};
  const Map map = pathWith(pole);
  const Pose2 truth(0, 0, 0);
  const Image image = rayCast(*camera, truth, pole, 5);
  // The Map believes the vehicle 0.5 m further along (sigma 0.3 m) and 0.1 m to the left.
  Prediction p = predictView(map, Pose2(0.5, 0.1, 0), *camera);
  p.view.pose_covariance = Vec3(0.09, 0.01, std::pow(degToRad(1), 2)).asDiagonal();
  const Prediction from_truth = predictView(map, truth, *camera);
  ASSERT_EQ(p.view.landmarks.size(), 1u);
  ASSERT_EQ(from_truth.view.landmarks.size(), 1u);
  const Vec2 expected = from_truth.view.landmarks[0].image_base;
  ASSERT_GT((p.view.landmarks[0].image_base - expected).norm(), 8.0);  // a real search
  const auto found = findLandmarks(landmarkFrame(image, *camera), p.view);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].id, "P1");
  ASSERT_TRUE(found[0].found) << found[0].reason;
  EXPECT_LT((found[0].image_base - expected).norm(), 1.5) << found[0].image_base.transpose() << " vs " << expected.transpose();
  EXPECT_GT(found[0].covariance(0, 0), 0.0);
}

TEST(FindLandmarks, ALandmarkThatIsNotThereIsReportedAsNotThere) {
  const auto camera = landmarkCamera();
  const Landmark pole{"P1", LandmarkKind::Pole, Vec2(5, 2.0), 0.1, 3.0, "", {}};
  const Map map = pathWith(pole);
  // The frame shows no pole (it stands 40 m away), the prediction expects it at 5 m.
  const Landmark elsewhere{"P1", LandmarkKind::Pole, Vec2(45, 2.0), 0.1, 3.0, "", {}};
  const Image image = rayCast(*camera, Pose2(0, 0, 0), elsewhere, 6);
  Prediction p = predictView(map, Pose2(0, 0, 0), *camera);
  p.view.pose_covariance = Vec3(0.09, 0.01, std::pow(degToRad(1), 2)).asDiagonal();
  const auto found = findLandmarks(landmarkFrame(image, *camera), p.view);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_FALSE(found[0].found);
  EXPECT_FALSE(found[0].reason.empty());
}

// The sub-pixel peak the finder, the ground's step and the edge tracker share: the vertex of a
// parabola sampled at -1, 0, 1, exact for a parabola, clamped to half a sample, and 0 where the
// samples do not bend down or are not finite.
TEST(ParabolaPeak, FindsTheVertexOfASampledParabolaAndNothingElse) {
  for (const double x0 : {-0.45, -0.2, 0.0, 0.3, 0.5}) {
    const auto y = [&](double x) { return 7.0 - 2.5 * (x - x0) * (x - x0); };
    EXPECT_NEAR(parabolaPeak(y(-1), y(0), y(1)), x0, 1e-12) << x0;
  }
  EXPECT_EQ(parabolaPeak(0.0, 1.0, 1.9), 0.5);  // the vertex 9.5 samples right: clamped
  EXPECT_EQ(parabolaPeak(1.0, 1.0, 1.0), 0.0);  // flat
  EXPECT_EQ(parabolaPeak(2.0, 1.0, 2.0), 0.0);  // a valley
  EXPECT_EQ(parabolaPeak(-std::numeric_limits<double>::infinity(), 1.0, 0.5), 0.0);
  EXPECT_EQ(parabolaPeak(std::nan(""), 1.0, 0.5), 0.0);
}

TEST(LandmarkFinderOptions, DefaultsAreValidAndBadFieldsAreNamed) {
  EXPECT_NO_THROW(LandmarkFinderOptions{}.validate());
  LandmarkFinderOptions o;
  o.max_search_px = 2;
  try {
    o.validate();
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("max_search_px"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mapnav
