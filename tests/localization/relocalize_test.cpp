// Re-localisation (relocalize.h): the region agreement on a hand-counted grid, and the search on the
// cross of four roads: a displaced estimate found again across the road, with the along-road
// ambiguity of a straight road in the covariance and resolved where the cross is in view.
#include "mapnav/localization/relocalize.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "map_fixtures.h"
#include "mapnav/core/error.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/polyline2.h"
#include "mapnav/map/map.h"
#include "mapnav/map/predict.h"

namespace mapnav {
namespace {

Polygon2 rectangle(double x0, double x1, double y0, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

// A footprint of 10 x 10 m and a road 2 m wide along it: on the 0.1 m grid the road's cell rows are
// those whose centres (-4.95, -4.85, ...) lie in [-1, 1], 20 of them; a region shifted 0.5 m left
// covers rows in [-0.5, 1.5], 20 too, 15 of them the road's. IoU 15 / 25.
TEST(RegionAgreement, IsTheIoUOfTheRegionAndThePavedAreaOnTheGrid) {
  PredictedObject view;
  view.footprint = rectangle(0, 10, -5, 5);
  view.regions.push_back(PredictedRegion{"R1", "straight road", "concrete", Vec3::Zero(), {rectangle(0, 10, -1, 1)}, {}});
  const RegionAgreement shifted = regionAgreement(view, rectangle(0, 10, -0.5, 1.5), 0.1);
  EXPECT_NEAR(shifted.iou, 15.0 / 25.0, 1e-12);
  EXPECT_NEAR(shifted.area_ratio, 1.0, 1e-12);
  const RegionAgreement same = regionAgreement(view, rectangle(0, 10, -1, 1), 0.1);
  EXPECT_NEAR(same.iou, 1.0, 1e-12);
  // Half as wide, inside the road: IoU and area ratio 1/2; a region beyond the footprint counts
  // within it only.
  const RegionAgreement half = regionAgreement(view, rectangle(0, 10, -0.5, 0.5), 0.1);
  EXPECT_NEAR(half.iou, 0.5, 1e-12);
  EXPECT_NEAR(half.area_ratio, 0.5, 1e-12);
  EXPECT_NEAR(regionAgreement(view, rectangle(-50, 50, -1, 1), 0.1).iou, 1.0, 1e-12);
  EXPECT_NEAR(regionAgreement(view, rectangle(-1e12, 1e12, -1, 1), 0.1).iou, 1.0, 1e-12);  // near the horizon
  // Nothing detected, or nothing to compare with.
  EXPECT_EQ(regionAgreement(view, Polygon2{}, 0.1).iou, 0.0);
  EXPECT_EQ(regionAgreement(view, rectangle(0, 10, 3, 4), 0.1).iou, 0.0);
  EXPECT_EQ(regionAgreement(PredictedObject{}, rectangle(0, 10, -1, 1), 0.1).iou, 0.0);
}

class RelocalizeOnTheCross : public ::testing::Test {
 protected:
  RelocalizeOnTheCross()
      : map_(testing::crossOfFourRoads()), predictor_(map_), camera_(testing::terregatorPinhole()) {}
  // What a perfect Vision finds from `truth`: the cross's paved area (four 2 m roads, 20 m each way
  // from (0, 0)) in the vehicle frame; the footprint cuts it.
  static Polygon2 roadSeenFrom(const Pose2& truth) {
    const Polygon2 world{{-20, -1}, {-1, -1}, {-1, -20}, {1, -20}, {1, -1}, {20, -1},
                         {20, 1},   {1, 1},   {1, 20},   {-1, 20}, {-1, 1}, {-20, 1}};
    Polygon2 out;
    for (const Vec2& p : world) out.push_back(truth.inverseTransform(p));
    return out;
  }
  // `truth` moved along its heading and to its left.
  static Pose2 displaced(const Pose2& truth, double along, double left, double heading_deg) {
    return Pose2(truth.translation() + truth.rotation() * Vec2(along, left), truth.heading() + degToRad(heading_deg));
  }
  // The error of `estimate` in `truth`'s axes: along, across, heading (rad).
  static Vec3 error(const Pose2& estimate, const Pose2& truth) {
    const Vec2 d = truth.rotation().transpose() * (estimate.translation() - truth.translation());
    return {d.x(), d.y(), normalizeAngle(estimate.heading() - truth.heading())};
  }

  Map map_;
  ViewPredictor predictor_;
  std::unique_ptr<Camera> camera_;
};

// A road 100 m long, 2 m wide, along x from (-50, 0) to (50, 0).
MapData straightRoad() {
  MapData m = testing::crossOfFourRoads();
  m.name = "straight road";
  m.intersections = {{"A", IntersectionKind::End, Vec2(-50, 0), std::nullopt},
                     {"B", IntersectionKind::End, Vec2(50, 0), std::nullopt}};
  m.roads.resize(1);
  m.roads[0].from = "A";
  m.roads[0].to = "B";
  m.roads[0].centerline = Polyline2({Vec2(-50, 0), Vec2(50, 0)});
  return m;
}

// In the middle of the straight road the view (2-12 m ahead) and every hypothesis's hold straight
// road only: the road's edges say where across it the vehicle is and its heading, nothing says
// where along it. The ties spread evenly over the +-3 m searched along: 1-sigma about 6 / sqrt(12).
// (The hypotheses move along the estimate's heading: with a heading error they would also move
// across the road and tie over a shorter stretch.)
TEST_F(RelocalizeOnTheCross, AStraightRoadFixesAcrossAndHeadingAndLeavesAlongInTheCovariance) {
  const Map straight(straightRoad());
  ViewPredictor predictor(straight);
  const Pose2 truth(0.0, 0.0, 0.0);
  const Pose2 estimate = displaced(truth, 0.5, 0.75, 0.0);
  const Polygon2 road{{-50, -1}, {50, -1}, {50, 1}, {-50, 1}};
  const RelocalizeResult r = relocalize(predictor, *camera_, estimate, road);
  ASSERT_TRUE(r.clear) << r.reason;
  EXPECT_LT(r.estimate.iou, 0.6) << r.reason;  // 1.25 of 2.75 m: 0.45, less what the footprint cuts
  EXPECT_GT(r.best, 0.95) << r.reason;
  const Vec3 e = error(r.pose, truth);
  EXPECT_LT(std::abs(e.y()), 0.13) << r.reason;                  // half a grid step
  EXPECT_LT(std::abs(radToDeg(e.z())), 1.6) << r.reason;         // half a heading step
  EXPECT_NEAR(r.spread.x(), 6.0 / std::sqrt(12.0), 0.1) << r.reason;  // along: the ties spread over metres
  EXPECT_LT(r.spread.y(), 0.3) << r.reason;
  // In the world frame the large variance lies along the road (x here), the small one across it (y).
  EXPECT_GT(r.covariance(0, 0), 1.0);
  EXPECT_LT(r.covariance(1, 1), 0.09);
}

// 8 m before the cross, heading east toward it: its crossing road is in view and fixes along too.
TEST_F(RelocalizeOnTheCross, TheCrossInViewFixesAlongToo) {
  const Pose2 truth(-8.0, 0.0, 0.0);
  const Pose2 estimate = displaced(truth, 1.0, -0.5, -3.0);
  const RelocalizeResult r = relocalize(predictor_, *camera_, estimate, roadSeenFrom(truth));
  ASSERT_TRUE(r.clear) << r.reason;
  const Vec3 e = error(r.pose, truth);
  EXPECT_LT(std::abs(e.x()), 0.26) << r.reason;
  EXPECT_LT(std::abs(e.y()), 0.13) << r.reason;
  EXPECT_LT(std::abs(radToDeg(e.z())), 1.6) << r.reason;
  EXPECT_LT(r.spread.x(), 0.3) << r.reason;
}

TEST_F(RelocalizeOnTheCross, AnEstimateThatExplainsTheRegionIsNotMoved) {
  const Pose2 truth(-8.0, 0.0, 0.0);
  const RelocalizeResult r = relocalize(predictor_, *camera_, truth, roadSeenFrom(truth));
  EXPECT_FALSE(r.clear);
  EXPECT_GT(r.estimate.iou, 0.95);
  EXPECT_NE(r.reason.find("the estimate explains it about as well"), std::string::npos) << r.reason;
  // A region three times the road's area (the verges taken for road) is Vision's error.
  const RelocalizeResult wide =
      relocalize(predictor_, *camera_, displaced(truth, 0, 1.0, 0), Polygon2{{2, -3}, {12, -3}, {12, 3}, {2, 3}});
  EXPECT_FALSE(wide.clear);
  EXPECT_NE(wide.reason.find("not the road's size"), std::string::npos) << wide.reason;
}

TEST(RelocalizeOptions, DefaultsAreValidAndABadFieldIsNamed) {
  EXPECT_NO_THROW(RelocalizeOptions{}.validate());
  RelocalizeOptions bad;
  bad.step_m = 0;
  try {
    bad.validate();
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("step_m"), std::string::npos) << e.what();
  }
  bad = RelocalizeOptions{};
  bad.max_area_ratio = 0.5;
  EXPECT_THROW(bad.validate(), InvalidInput);
}

}  // namespace
}  // namespace mapnav
