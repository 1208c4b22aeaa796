// The map's landmarks in the synthetic world: where a pole's pixels, shadow and truth
// are, computed by hand for a pin-hole looking along a straight concrete sidewalk.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "world_options_checks.h"
#include "mapnav/core/error.h"
#include "mapnav/image/png.h"
#include "mapnav/sim/world.h"
#include "mapnav/sim/world_io.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

// 320 × 240, f = 200 px, the optical centre 1.5 m above the vehicle's origin. Level (tilt 0), a
// vehicle point (X, Y, Z) is at u = 159.5 − 200·Y/X, v = 119.5 + 200·(1.5 − Z)/X.
std::unique_ptr<Camera> pinhole(double tilt_rad) {
  CameraIntrinsics in;
  in.width = 320;
  in.height = 240;
  in.fx = in.fy = 200.0;
  in.cx = 159.5;
  in.cy = 119.5;
  CameraMount mount;
  mount.height_m = 1.5;
  mount.tilt_rad = tilt_rad;
  return createCamera(LensModel::Pinhole, in, mount);
}

Landmark landmark(const std::string& id, LandmarkKind kind, Vec2 position, double radius, double height) {
  Landmark l;
  l.id = id;
  l.kind = kind;
  l.position = position;
  l.radius = radius;
  l.height = height;
  return l;
}

// A straight concrete sidewalk 3 m wide along the world's x axis between lawns, with these landmarks.
Map sidewalk(std::vector<Landmark> landmarks) {
  MapData data;
  data.name = "sidewalk";
  data.surfaces = testing::campusMap().data().surfaces;
  data.intersections.push_back({"I1", IntersectionKind::End, Vec2(-40, 0), std::nullopt});
  data.intersections.push_back({"I2", IntersectionKind::End, Vec2(120, 0), std::nullopt});
  Road road;
  road.id = "R";
  road.from = "I1";
  road.to = "I2";
  road.centerline = Polyline2({Vec2(-40, 0), Vec2(120, 0)});
  road.width = 3.0;
  road.surface = "concrete";
  road.left = road.right = "grass";
  data.roads.push_back(road);
  data.landmarks = std::move(landmarks);
  return Map(data, "sidewalk");
}

// Every texture, the canopies, drift and noise off: the pavement and the lawn flat colours.
WorldOptions flat() {
  WorldOptions o;
  o.pavement_noise = o.ground_noise = o.crack_density = o.dust = o.shadow_density = o.leaf_density = 0;
  o.slab_spacing_m = o.illumination_drift = o.white_balance_drift = o.haze_distance_m = o.noise_sigma = 0;
  return o;
}

bool shows(const Image& mask, int u, int v) { return mask.pixel(u, v)[0] == 255; }

// A pole (r 0.1, 3.5 m) 10 m ahead on the sidewalk's centre line. Its silhouette's half-angle is
// asin(0.1 / 10): ±2.0 px about u = 159.5, so columns 158 … 161. Its front (9.90 … 9.93 m ahead)
// meets the ground at v = 119.5 + 300 / X = 149.7 … 149.8 and its top at v = 119.5 − 400 / X =
// 79.1 … 79.2: rows 80 … 149.
TEST(WorldLandmarks, APoleCoversTheColumnsAndRowsComputedByHand) {
  const Map map = sidewalk({landmark("P", LandmarkKind::Pole, Vec2(10, 0), 0.1, 3.5)});
  const auto cam = pinhole(0.0);
  const Frame f = World(map, flat()).render(*cam, Pose2(0, 0, 0), 0.0);
  const Frame bare = World(sidewalk({}), flat()).render(*cam, Pose2(0, 0, 0), 0.0);
  int covered = 0;
  for (int v = 0; v < 240; ++v)
    for (int u = 0; u < 320; ++u) {
      const bool pole = u >= 158 && u <= 161 && v >= 80 && v <= 149;
      EXPECT_EQ(shows(f.landmark_mask, u, v), pole) << u << ", " << v;
      covered += pole ? 1 : 0;
    }
  EXPECT_EQ(covered, 4 * 70);
  // In front of the road the pole is no road; beside it the road is (out to its end, 120 m ahead at
  // v = 122).
  for (int v = 125; v <= 149; ++v) {
    for (int u = 158; u <= 161; ++u) {
      EXPECT_TRUE(shows(bare.mask, u, v)) << u << ", " << v;
      EXPECT_FALSE(shows(f.mask, u, v)) << u << ", " << v;
    }
    EXPECT_TRUE(shows(f.mask, 157, v));
    EXPECT_TRUE(shows(f.mask, 162, v));
  }
  // Grey metal, not the sky behind its top nor the concrete behind its foot.
  for (int v : {90, 140}) {
    const std::uint8_t* p = f.rgb.pixel(160, v);
    EXPECT_LT(std::abs(p[0] - p[2]), 25) << v;
    EXPECT_NE(p[2], bare.rgb.pixel(160, v)[2]) << v;
  }
}

// Truth: the pole's base is the front of its circle toward the eye, (9.9, 0, 0); its top (9.9, 0,
// 3.5). A thinner pole 20 m ahead, 2 m tall, hides behind it whole (±0.5 px, rows 115 … 134): not
// listed. A manhole cover (r 0.3) at (6, 0.5): its centre at (142.83, 169.5), in the paving. A
// bench (half-length 0.8) at (12, −3) along the road, its back away from it: the point of its
// footprint nearest the eye's ground point is (12 − 0.8, −3 + 0.25), its top 0.8 m above.
TEST(WorldLandmarks, TheTruthListsTheHandComputedPixels) {
  const Map map = sidewalk({landmark("P", LandmarkKind::Pole, Vec2(10, 0), 0.1, 3.5),
                            landmark("H", LandmarkKind::Pole, Vec2(20, 0), 0.05, 2.0),
                            landmark("M", LandmarkKind::Manhole, Vec2(6, 0.5), 0.3, 0.0),
                            landmark("S", LandmarkKind::Bench, Vec2(12, -3), 0.8, 0.8)});
  const auto cam = pinhole(0.0);
  const Frame f = World(map, flat()).render(*cam, Pose2(0, 0, 0), 0.0);
  ASSERT_EQ(f.landmarks.size(), 3u);
  const LandmarkInView& pole = f.landmarks[0];
  EXPECT_EQ(pole.index, 0u);
  EXPECT_NEAR(pole.base_px.x(), 159.5, 1e-9);
  EXPECT_NEAR(pole.base_px.y(), 119.5 + 300 / 9.9, 1e-9);
  ASSERT_TRUE(pole.top_px);
  EXPECT_NEAR(pole.top_px->y(), 119.5 - 400 / 9.9, 1e-9);
  EXPECT_TRUE(pole.base_visible);
  EXPECT_EQ(pole.pixels, 280);

  const LandmarkInView& cover = f.landmarks[1];
  EXPECT_EQ(cover.index, 2u);
  EXPECT_NEAR(cover.base_px.x(), 159.5 - 200 * 0.5 / 6, 1e-9);
  EXPECT_NEAR(cover.base_px.y(), 169.5, 1e-9);
  EXPECT_TRUE(cover.top_px && (*cover.top_px - cover.base_px).norm() < 1e-12);
  EXPECT_TRUE(cover.base_visible);
  // Its pixels: those whose ground point is within 0.3 m of its centre (a hair either side left open).
  int inside = 0, near_edge = 0;
  for (int v = 120; v < 240; ++v)
    for (int u = 0; u < 320; ++u) {
      const double x = 300.0 / (v - 119.5), y = -x * (u - 159.5) / 200.0;
      const double d = std::hypot(x - 6, y - 0.5);
      inside += d < 0.3 - 1e-4 ? 1 : 0;
      near_edge += std::abs(d - 0.3) <= 1e-4 ? 1 : 0;
      if (d < 0.3 - 1e-4) {
        EXPECT_TRUE(shows(f.landmark_mask, u, v));
        EXPECT_TRUE(shows(f.mask, u, v));  // a cover in the paving is paving
      }
    }
  EXPECT_GE(cover.pixels, inside);
  EXPECT_LE(cover.pixels, inside + near_edge);
  EXPECT_GT(inside, 20);

  const LandmarkInView& bench = f.landmarks[2];
  EXPECT_EQ(bench.index, 3u);
  EXPECT_NEAR(bench.base_px.x(), 159.5 + 200 * 2.75 / 11.2, 1e-9);
  EXPECT_NEAR(bench.base_px.y(), 119.5 + 300 / 11.2, 1e-9);
  ASSERT_TRUE(bench.top_px);
  EXPECT_NEAR(bench.top_px->y(), 119.5 + 200 * 0.7 / 11.2, 1e-9);
  EXPECT_TRUE(bench.base_visible);
  EXPECT_GT(bench.pixels, 100);
}

// A pole (r 0.1, 3 m) at (5, −1) with the sun in the south-east, 45° up: its shadow is the points
// within 0.1 m of the segment from (5, −1) to (5 − 3/√2, −1 + 3/√2), across the sidewalk toward the
// camera. Ground pixels well inside it are k·C tinted (C the sunlit colour, from a world without the
// pole); every other pixel, outside it by more than its soft edge, keeps its colour.
TEST(WorldLandmarks, APolesShadowDarkensTheGroundWhereComputedAndNowhereElse) {
  const Vec2 base(5, -1), tip = base + Vec2(-1, 1) * (3 / std::sqrt(2.0));
  const Map map = sidewalk({landmark("P", LandmarkKind::Pole, base, 0.1, 3.0)});
  WorldOptions o = flat();
  o.sun_azimuth_rad = -kPi / 4;
  o.sun_elevation_rad = kPi / 4;
  const World world(map, o);
  const auto cam = pinhole(0.6);
  const Pose2 pose(0, 0, 0);
  const Frame f = world.render(*cam, pose, 0.0);
  const Frame sun = World(sidewalk({}), o).render(*cam, pose, 0.0);
  const auto segDist = [&](const Vec2& p) {
    const Vec2 ab = tip - base;
    const double s = std::clamp((p - base).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    return (p - (base + s * ab)).norm();
  };
  const std::array<double, 3> tint{1 - o.shadow_blue_shift, 1, 1 + o.shadow_blue_shift};
  int full = 0, unchanged = 0;
  for (int v = 0; v < 240; ++v)
    for (int u = 0; u < 320; ++u) {
      const auto g = cam->backproject(Vec2(u, v));
      if (!g || shows(f.landmark_mask, u, v)) continue;
      // The pixel's size on the ground: the farthest of its neighbours' ground points.
      double fp = 0;
      for (const Vec2& n : {Vec2(u + 1, v), Vec2(u - 1, v), Vec2(u, v + 1), Vec2(u, v - 1)})
        if (const auto gn = cam->backproject(n)) fp = std::max(fp, (*gn - *g).norm());
      const double d = segDist(pose.transform(*g));
      if (d < 0.1 - std::max(fp, 0.06) / 2 - 1e-3) {
        ++full;
        for (int c = 0; c < 3; ++c)
          EXPECT_LE(std::abs(f.rgb.pixel(u, v)[c] - o.shadow_k * tint[c] * sun.rgb.pixel(u, v)[c]), 1.0) << u << ", " << v;
      } else if (d > 0.1 + std::min(1.0, std::max(fp, 0.06)) / 2 + 1e-3) {
        ++unchanged;
        for (int c = 0; c < 3; ++c) ASSERT_EQ(f.rgb.pixel(u, v)[c], sun.rgb.pixel(u, v)[c]) << u << ", " << v;
      }
    }
  EXPECT_GT(full, 100);
  EXPECT_GT(unchanged, 60000);
  // shadowAt: on the segment, beside it, beyond its tip and on the sun's side of the pole.
  EXPECT_DOUBLE_EQ(world.shadowAt(Vec2(4, 0)), 1.0);
  EXPECT_DOUBLE_EQ(world.shadowAt(tip - Vec2(-1, 1) * 0.05), 1.0);
  EXPECT_DOUBLE_EQ(world.shadowAt(Vec2(4.2, 0)), 0.0);
  EXPECT_DOUBLE_EQ(world.shadowAt(tip + Vec2(-1, 1) * 0.15), 0.0);
  EXPECT_DOUBLE_EQ(world.shadowAt(Vec2(5.5, -1.5)), 0.0);
}

// Behind the camera, and 40 m to the side of a camera looking along the sidewalk (its shadow
// falling away, west): neither is tested, listed or drawn, and the frame is the bare world's.
TEST(WorldLandmarks, LandmarksOutOfViewCostNothingAndAreNotListed) {
  const Map map = sidewalk({landmark("B", LandmarkKind::Pole, Vec2(-5, 0), 0.1, 5.0),
                            landmark("S", LandmarkKind::Tree, Vec2(10, 40), 0.15, 6.0)});
  WorldOptions o;
  o.sun_azimuth_rad = 0;  // in the east, ahead: shadows fall west, behind
  const auto cam = pinhole(0.2);
  const World world(map, o);
  const RayTable rays(*cam);
  EXPECT_TRUE(world.landmarksInView(rays, Pose2(0, 0, 0)).empty());
  const Frame f = world.render(rays, Pose2(0, 0, 0), 1.0);
  const Frame bare = World(sidewalk({}), o).render(rays, Pose2(0, 0, 0), 1.0);
  EXPECT_TRUE(f.rgb == bare.rgb);
  EXPECT_TRUE(f.mask == bare.mask);
  EXPECT_TRUE(f.landmarks.empty());
  EXPECT_EQ(std::count(f.landmark_mask.data.begin(), f.landmark_mask.data.end(), 0), 320 * 240);
  // Turned toward them, both are.
  EXPECT_EQ(world.landmarksInView(rays, Pose2(0, 0, kPi)), std::vector<std::size_t>{0});
  EXPECT_EQ(world.landmarksInView(rays, Pose2(0, 0, 1.33)), std::vector<std::size_t>{1});
}

Map everyKind() {
  return sidewalk({landmark("T", LandmarkKind::Tree, Vec2(16, 3.0), 0.15, 6.0),
                   landmark("P", LandmarkKind::Pole, Vec2(11, -1.8), 0.1, 5.0),
                   landmark("B", LandmarkKind::Bollard, Vec2(8, 1.7), 0.08, 0.9),
                   landmark("S", LandmarkKind::Bench, Vec2(14, -2.6), 0.8, 0.8),
                   landmark("M", LandmarkKind::Manhole, Vec2(10, 0.2), 0.3, 0.0)});
}

TEST(WorldLandmarks, EveryThreadCountRendersTheSameFrame) {
  WorldOptions o;
  o.seed = 9;
  o.shadow_density = 0.3;
  o.paved_edge_samples = 3;  // the edge pass skips the bodies
  const auto cam = pinhole(0.25);
  const Pose2 pose(2, 0.4, 0.05);
  const Frame one = World(everyKind(), o).render(*cam, pose, 3.0);
  ASSERT_EQ(one.landmarks.size(), 5u);
  for (int threads : {2, 3, 0}) {
    o.threads = threads;
    const Frame f = World(everyKind(), o).render(*cam, pose, 3.0);
    EXPECT_TRUE(f.rgb == one.rgb) << threads;
    EXPECT_TRUE(f.mask == one.mask) << threads;
    EXPECT_TRUE(f.landmark_mask == one.landmark_mask) << threads;
    ASSERT_EQ(f.landmarks.size(), one.landmarks.size());
    for (std::size_t i = 0; i < f.landmarks.size(); ++i) {
      EXPECT_EQ(f.landmarks[i].pixels, one.landmarks[i].pixels);
      EXPECT_EQ(f.landmarks[i].base_px, one.landmarks[i].base_px);
    }
  }
}

TEST(WorldLandmarks, TheSunIsValidatedAndRead) {
  WorldOptions o;
  o.sun_elevation_rad = 0.05;
  EXPECT_THROW(o.validate(), InvalidInput);
  o.sun_elevation_rad = 1.6;
  EXPECT_TRUE(simtest::rejectedNaming(o, "sun_elevation_rad"));
  o = {};
  o.sun_azimuth_rad = std::nan("");
  EXPECT_THROW(o.validate(), InvalidInput);
  Issues issues;
  const WorldOptions read = parseWorldOptions(R"({"sun_azimuth_rad": 1.5, "sun_elevation_rad": 0.9})", "/world", issues);
  EXPECT_TRUE(issues.empty());
  EXPECT_EQ(read.sun_azimuth_rad, 1.5);
  EXPECT_EQ(read.sun_elevation_rad, 0.9);
}

// Pictures for people: run with --gtest_also_run_disabled_tests; writes /tmp/world_landmarks_*.png.
TEST(WorldLandmarks, DISABLED_WritePictures) {
  const World world(everyKind());
  const auto cam = pinhole(0.2);
  writePng(world.render(*cam, Pose2(0, 0, 0), 0.0).rgb, "/tmp/world_landmarks_ahead.png");
  writePng(world.render(*cam, Pose2(26, 1, kPi), 0.0).rgb, "/tmp/world_landmarks_back.png");
  writePng(world.render(*cam, Pose2(9, -0.5, -0.6), 0.0).rgb, "/tmp/world_landmarks_bench.png");
}

}  // namespace
}  // namespace mapnav
