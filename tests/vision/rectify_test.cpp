#include "mapnav/vision/rectify.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/sim/world.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {


// maps/cameras/terregator_fisheye.json
std::unique_ptr<Camera> terregatorFisheye() {
  CameraIntrinsics in;
  in.width = 512;
  in.height = 480;
  in.fx = in.fy = 257.0;
  in.cx = 255.5;
  in.cy = 239.5;
  CameraMount mount;
  mount.height_m = 1.5;
  mount.tilt_rad = degToRad(20.0);
  return createCamera(LensModel::PaperFisheye, in, mount);
}

// A clean frame: flat colours, no noise, shadows, leaves, slab gaps or haze.
WorldOptions cleanWorld() {
  WorldOptions o;
  o.pavement_noise = 0;
  o.ground_noise = 0;
  o.slab_spacing_m = 0;
  o.crack_density = 0;
  o.dust = 0;
  o.shadow_density = 0;
  o.leaf_density = 0;
  o.illumination_drift = 0;
  o.white_balance_drift = 0;
  o.haze_distance_m = 0;
  o.noise_sigma = 0;
  return o;
}

// Concrete (178, 176, 168) against grass (70, 120, 50) and black (outside the frame).
bool roadColoured(const std::uint8_t* p) { return p[0] > 120 && p[0] + 20 > p[1]; }

struct EdgeFit {
  double slope = 0;  // columns per row
  double angle_deg = 0;  // from the image's vertical axis
  int rows = 0;
};

// Least squares col = a·row + b.
EdgeFit fit(const std::vector<std::pair<double, double>>& row_col) {
  double sr = 0, sc = 0, srr = 0, src = 0;
  const double n = static_cast<double>(row_col.size());
  for (const auto& [r, c] : row_col) {
    sr += r;
    sc += c;
    srr += r * r;
    src += r * c;
  }
  EdgeFit f;
  f.slope = (n * src - sr * sc) / (n * srr - sr * sr);
  f.angle_deg = radToDeg(std::atan(f.slope));
  f.rows = static_cast<int>(row_col.size());
  return f;
}

// Per row, the first and last road-coloured column of a rectified frame, fitted as two lines.
// Rows whose road run touches a black (unseen) pixel or the image border are skipped.
std::pair<EdgeFit, EdgeFit> roadEdges(const Image& rect) {
  std::vector<std::pair<double, double>> left, right;
  for (int r = 0; r < rect.height; ++r) {
    int first = -1, last = -1;
    for (int c = 0; c < rect.width; ++c) {
      if (roadColoured(rect.pixel(c, r))) {
        if (first < 0) first = c;
        last = c;
      }
    }
    if (first <= 0 || last >= rect.width - 1) continue;
    auto seen = [&](int c) {
      const std::uint8_t* p = rect.pixel(c, r);
      return p[0] + p[1] + p[2] > 30;
    };
    // The neighbours outside the road must be seen grass, not the black outside the frame.
    if (!seen(first - 1) || !seen(last + 1)) continue;
    if (last - first < 20) continue;
    left.emplace_back(r, first - 0.5);
    right.emplace_back(r, last + 0.5);
  }
  return {fit(left), fit(right)};
}

void expectStraightParallelEdges(const Camera& camera, const char* label) {
  const Map& map = testing::campusWithoutLandmarks();
  const World world(map, cleanWorld());
  // On R1, 3 m past I1, looking along it (east): a 2.5 m wide straight road for 47 m.
  const Frame frame = world.render(camera, Pose2(53, 40, 0), 0.0);
  RectifyOptions options;
  options.y_min_m = -4.0;
  options.y_max_m = 4.0;
  const Rectifier rectifier(camera, options);
  const Image rect = rectifier.apply(frame.rgb);
  ASSERT_EQ(rect.width, 400);
  ASSERT_EQ(rect.height, 700);
  const auto [left, right] = roadEdges(rect);
  const double between = std::abs(left.angle_deg - right.angle_deg);
  std::printf("[%s] rows used %d/%d, left edge %.3f deg, right edge %.3f deg from vertical, between %.3f deg\n", label,
              left.rows, right.rows, left.angle_deg, right.angle_deg, between);
  ASSERT_GT(left.rows, 100);
  ASSERT_GT(right.rows, 100);
  EXPECT_LE(between, 1.0);
  EXPECT_LE(std::abs(left.angle_deg), 1.0);
  EXPECT_LE(std::abs(right.angle_deg), 1.0);
}

TEST(Rectifier, StraightRoadEdgesAreParallelForThePinholeCamera) {
  expectStraightParallelEdges(*testing::terregatorPinhole(), "pinhole");
}

TEST(Rectifier, StraightRoadEdgesAreParallelForThePapersFisheyeCamera) {
  expectStraightParallelEdges(*terregatorFisheye(), "fisheye");
}

TEST(Rectifier, RoadWidthInTheRectifiedImageIsTheMapsWidth) {
  const auto camera = testing::terregatorPinhole();
  const Map& map = testing::campusWithoutLandmarks();
  const World world(map, cleanWorld());
  const Frame frame = world.render(*camera, Pose2(53, 40, 0), 0.0);
  const Rectifier rectifier(*camera);
  const Image mask = rectifier.apply(frame.mask);
  ASSERT_EQ(mask.channels, 1);
  // 6 m ahead: row (15 − 6) / 0.02 − 0.5.
  const int row = static_cast<int>(std::lround(rectifier.pixelAt(Vec2(6.0, 0.0)).y()));
  int count = 0;
  for (int c = 0; c < mask.width; ++c) count += mask.pixel(c, row)[0] > 127 ? 1 : 0;
  EXPECT_NEAR(count * 0.02, 2.5, 0.06);
}

TEST(Rectifier, GridGeometryAndUnseenPixelsAreBlack) {
  const auto camera = testing::terregatorPinhole();
  const Rectifier rectifier(*camera);
  EXPECT_EQ(rectifier.width(), 600);
  EXPECT_EQ(rectifier.height(), 700);
  EXPECT_VEC2_NEAR(rectifier.groundAt(0, 0), Vec2(14.99, 5.99), 1e-12);
  EXPECT_VEC2_NEAR(rectifier.pixelAt(rectifier.groundAt(123, 456)), Vec2(123, 456), 1e-9);
  Image white(512, 480, 3);
  std::fill(white.data.begin(), white.data.end(), std::uint8_t{255});
  const Image rect = rectifier.apply(white);
  // 1 m ahead is below the pin-hole's view (it sees 2 to 12 m): black. 6 m straight ahead: white.
  const Vec2 near = rectifier.pixelAt(Vec2(1.2, 0.0));
  EXPECT_EQ(rect.pixel(static_cast<int>(near.x()), static_cast<int>(near.y()))[0], 0);
  const Vec2 mid = rectifier.pixelAt(Vec2(6.0, 0.0));
  EXPECT_EQ(rect.pixel(static_cast<int>(mid.x()), static_cast<int>(mid.y()))[1], 255);
  EXPECT_GT(rectifier.coverage(), 0.05);
  EXPECT_LT(rectifier.coverage(), 0.6);
}

TEST(Rectifier, RejectsBadOptionsAndFrames) {
  const auto camera = testing::terregatorPinhole();
  RectifyOptions bad;
  bad.metres_per_pixel = 0;
  EXPECT_THROW(bad.validate(), InvalidInput);
  bad = RectifyOptions{};
  bad.x_max_m = 0.5;
  EXPECT_THROW(Rectifier(*camera, bad), InvalidInput);
  const Rectifier rectifier(*camera);
  EXPECT_THROW((void)rectifier.apply(Image(100, 100, 3)), InvalidInput);
}

}  // namespace
}  // namespace mapnav
