// Numerical guards: degenerate geometry (zero-length segments, collinear
// intersection shapes, roads meeting at 0°, an intersection with 8 roads), UTM-sized coordinates
// and cameras looking at the sky. None may crash or give a NaN pose; what is invalid is reported
// with its JSON Pointer.
#include <gtest/gtest.h>

#include <cmath>

#include "mapnav/core/error.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/localization/localize.h"
#include "mapnav/localization/pose_filter.h"
#include "mapnav/map/map_io.h"
#include "mapnav/map/predict.h"
#include "mapnav/map/validation.h"
#include "mapnav/navigator/road_position.h"
#include "mapnav/navigator/route.h"
#include "mapnav/testing/support.h"
#include "mapnav/tokens/detected_object.h"

namespace mapnav {
namespace {

bool finite(const Pose2& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.heading()); }
bool finite(const Vec2& v) { return std::isfinite(v.x()) && std::isfinite(v.y()); }

// Every number a prediction holds is finite.
::testing::AssertionResult allFinite(const Prediction& p) {
  for (const InterestSegment& s : p.view.segments) {
    for (const Vec2& v : {s.vehicle.a, s.vehicle.b, s.image.a, s.image.b}) {
      if (!finite(v)) return ::testing::AssertionFailure() << "segment " << s.id << " is not finite";
    }
  }
  for (const Vec2& v : p.footprint_world) {
    if (!finite(v)) return ::testing::AssertionFailure() << "the footprint is not finite";
  }
  for (const PredictedRegion& r : p.view.regions) {
    for (const Polygon2& poly : r.vehicle) {
      for (const Vec2& v : poly) {
        if (!finite(v)) return ::testing::AssertionFailure() << "region " << r.id << " is not finite";
      }
    }
  }
  return ::testing::AssertionSuccess();
}

// A star: N roads of 20 m from I0 at `centre`, at the given headings (degrees), to dead ends E1..EN.
MapData star(const Vec2& centre, const std::vector<double>& headings_deg, IntersectionKind kind) {
  MapData m;
  m.name = "star";
  m.surfaces = {{"concrete", Appearance{Vec3(178, 176, 168), Vec3(10, 10, 10)}},
                {"grass", Appearance{Vec3(70, 120, 50), Vec3(14, 18, 12)}}};
  m.intersections.push_back({"I0", kind, centre, std::nullopt});
  for (std::size_t i = 0; i < headings_deg.size(); ++i) {
    const double h = degToRad(headings_deg[i]);
    const Vec2 end = centre + 20.0 * Vec2(std::cos(h), std::sin(h));
    const std::string n = std::to_string(i + 1);
    m.intersections.push_back({"E" + n, IntersectionKind::End, end, std::nullopt});
    Road r;
    r.id = "R" + n;
    r.from = "I0";
    r.to = "E" + n;
    r.centerline = Polyline2({centre, end});
    r.width = 2.0;
    r.surface = "concrete";
    r.left = r.right = "grass";
    m.roads.push_back(r);
  }
  return m;
}

std::vector<Issue> errorsOf(const MapData& data) {
  Issues issues;
  buildMap(data, "test.json", issues);
  std::vector<Issue> errors;
  for (const Issue& i : issues) {
    if (i.severity == Severity::Error) errors.push_back(i);
  }
  return errors;
}

Map build(const MapData& data) {
  Issues issues;
  auto map = buildMap(data, "test.json", issues);
  if (!map) throw ValidationError("test.json", issues);
  return std::move(*map);
}

// The vehicle on road `road` of `map`, `meters` from I0, facing I0.
Pose2 facingCentre(const Map& map, const std::string& road, double meters) {
  const Polyline2& line = map.road(road).centerline;
  const Vec2 at = line.pointAt(meters);
  return Pose2(at, line.headingAt(meters) + kPi);
}

// ---- degenerate geometry ----------------------------------------------------------------------

TEST(DegenerateGeometry, ZeroLengthSegmentIsReportedAtItsPoint) {
  MapData m = star(Vec2(0, 0), {0, 90, 180, 270}, IntersectionKind::Cross);
  m.roads[1].centerline = Polyline2({Vec2(0, 0), Vec2(0, 10), Vec2(0, 10), Vec2(0, 20)});
  const auto errors = errorsOf(m);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].check, "roads.repeated_point");
  EXPECT_EQ(errors[0].where, "/roads/1/centerline/2");
}

TEST(DegenerateGeometry, RoadOfZeroLengthIsReported) {
  MapData m = star(Vec2(0, 0), {0, 90, 180, 270}, IntersectionKind::Cross);
  m.intersections[1].position = Vec2(0, 0);  // E1 on I0
  m.roads[0].centerline = Polyline2({Vec2(0, 0), Vec2(0, 0)});
  const auto errors = errorsOf(m);
  ASSERT_FALSE(errors.empty());
  EXPECT_EQ(errors[0].check, "roads.repeated_point");
  EXPECT_EQ(errors[0].where, "/roads/0/centerline/1");
}

TEST(DegenerateGeometry, CollinearIntersectionShapeIsReported) {
  MapData m = star(Vec2(0, 0), {0, 90, 180, 270}, IntersectionKind::Cross);
  m.intersections[0].shape = Polygon2{Vec2(-1, -1), Vec2(0, 0), Vec2(1, 1), Vec2(2, 2)};  // no area
  const auto errors = errorsOf(m);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].where, "/intersections/0/shape");
  EXPECT_EQ(errors[0].check, "intersections.self_intersecting_shape");
  EXPECT_NE(errors[0].message.find("encloses no area"), std::string::npos) << errors[0].message;
}

TEST(DegenerateGeometry, ABowTieShapeWithZeroSignedAreaCrossesItself) {
  MapData m = star(Vec2(0, 0), {0, 90, 180, 270}, IntersectionKind::Cross);
  m.intersections[0].shape = Polygon2{Vec2(-1, -1), Vec2(1, 1), Vec2(1, -1), Vec2(-1, 1)};  // area +2 − 2 = 0
  const auto errors = errorsOf(m);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].check, "intersections.self_intersecting_shape");
  EXPECT_NE(errors[0].message.find("crosses itself"), std::string::npos) << errors[0].message;
}

TEST(DegenerateGeometry, CollinearPointsOnAShapesEdgeAreFine) {
  MapData m = star(Vec2(0, 0), {0, 90, 180, 270}, IntersectionKind::Cross);
  // A 2 m square with extra points on two of its edges.
  m.intersections[0].shape = Polygon2{Vec2(-1, -1), Vec2(0, -1), Vec2(1, -1), Vec2(1, 0), Vec2(1, 1), Vec2(-1, 1)};
  EXPECT_TRUE(errorsOf(m).empty());
  const Map map = build(m);
  const auto camera = testing::terregatorPinhole();
  for (const std::string road : {"R1", "R2", "R3", "R4"}) {
    EXPECT_TRUE(allFinite(predictView(map, facingCentre(map, road, 3.0), *camera))) << road;
  }
}

TEST(DegenerateGeometry, RoadsMeetingAtZeroDegreesAreReportedNotNaN) {
  // R1 and R2 leave I0 in the same direction: their first metres lie on top of each other.
  MapData m = star(Vec2(0, 0), {0, 90, 180, 270}, IntersectionKind::Cross);
  m.intersections[2].position = Vec2(20, 6);
  m.roads[1].centerline = Polyline2({Vec2(0, 0), Vec2(10, 0), Vec2(20, 6)});
  Issues issues;
  const auto map = buildMap(m, "test.json", issues);
  std::vector<Issue> errors;
  for (const Issue& i : issues) {
    if (i.severity == Severity::Error) errors.push_back(i);
  }
  ASSERT_FALSE(errors.empty()) << "overlapping roads must not load";
  EXPECT_EQ(errors[0].check, "roads.crossing_without_intersection");
  EXPECT_EQ(errors[0].where.rfind("/roads/", 0), 0u) << errors[0].where;
}

TEST(DegenerateGeometry, RoadsMeetingAtAGrazingAngleGiveFiniteViewsAndRoutes) {
  // Two roads 1° apart at I0 (they separate within the intersection): valid, and nothing divides by
  // the sine of the angle between them into a NaN.
  const Map map = build(star(Vec2(0, 0), {0, 1, 180}, IntersectionKind::Y));
  const auto camera = testing::terregatorPinhole();
  for (const std::string road : {"R1", "R2", "R3"}) {
    for (double s : {0.5, 2.0, 6.0}) {
      const Prediction p = predictView(map, facingCentre(map, road, s), *camera);
      EXPECT_TRUE(allFinite(p)) << road << " " << s;
    }
  }
  RoadGraph graph(map);
  const RouteResult r = graph.route(parseRoadPosition("R1@I0+5"), parseRoadPosition("R2@I0+5"));
  ASSERT_TRUE(r.route) << r.reason;
  EXPECT_TRUE(std::isfinite(r.route->length_m));
  for (const Leg& leg : r.route->legs) EXPECT_TRUE(std::isfinite(leg.angle) && std::isfinite(leg.meters));
}

TEST(DegenerateGeometry, EightRoadsAtOneIntersection) {
  const Map map = build(star(Vec2(0, 0), {0, 45, 90, 135, 180, 225, 270, 315}, IntersectionKind::Plaza));
  const auto camera = testing::terregatorPinhole();
  RoadGraph graph(map);
  for (int i = 1; i <= 8; ++i) {
    const std::string road = "R" + std::to_string(i);
    const Prediction p = predictView(map, facingCentre(map, road, 4.0), *camera);
    EXPECT_TRUE(allFinite(p)) << road;
    EXPECT_FALSE(p.empty()) << road;
    for (int j = 1; j <= 8; ++j) {
      if (j == i) continue;
      const RouteResult r = graph.route(parseRoadPosition(road + "@I0+4"), parseRoadPosition("R" + std::to_string(j) + "@I0+4"));
      ASSERT_TRUE(r.route) << road << " to R" << j << ": " << r.reason;
      EXPECT_NEAR(r.route->length_m, 8.0, 1e-9);
      const int steps = ((j - i) % 8 + 8) % 8;  // 45° steps counter-clockwise from road i to road j
      const double turn = steps <= 4 ? 180.0 - 45.0 * steps : -(180.0 - 45.0 * (8 - steps));
      ASSERT_EQ(r.route->legs.size(), 3u);
      EXPECT_NEAR(radToDeg(std::abs(r.route->legs[1].angle)), std::abs(turn), 1e-6) << road << " to R" << j;
    }
  }
}

// ---- UTM-sized coordinates --------------------------------------------------------------------

const Vec2 kUtm(500000.0, 5000000.0);

TEST(HugeCoordinates, MapLoadsAndPredictsAsAtTheOrigin) {
  const Map here = build(star(Vec2(0, 0), {0, 90, 180, 270}, IntersectionKind::Cross));
  const Map far = build(star(kUtm, {0, 90, 180, 270}, IntersectionKind::Cross));
  const auto camera = testing::terregatorPinhole();
  const Pose2 pose_here = facingCentre(here, "R1", 6.0);
  const Pose2 pose_far(pose_here.translation() + kUtm, pose_here.heading());
  const Prediction a = predictView(here, pose_here, *camera);
  const Prediction b = predictView(far, pose_far, *camera);
  EXPECT_TRUE(allFinite(b));
  ASSERT_EQ(a.view.segments.size(), b.view.segments.size());
  ASSERT_FALSE(a.view.segments.empty());
  for (std::size_t i = 0; i < a.view.segments.size(); ++i) {
    EXPECT_EQ(a.view.segments[i].id, b.view.segments[i].id);
    EXPECT_VEC2_NEAR(a.view.segments[i].vehicle.a, b.view.segments[i].vehicle.a, 1e-6);
    EXPECT_VEC2_NEAR(a.view.segments[i].vehicle.b, b.view.segments[i].vehicle.b, 1e-6);
    EXPECT_VEC2_NEAR(a.view.segments[i].image.a, b.view.segments[i].image.a, 1e-4);
  }
}

TEST(HugeCoordinates, RoutingIsAsAtTheOrigin) {
  const Map far = build(star(kUtm, {0, 90, 180, 270}, IntersectionKind::Cross));
  RoadGraph graph(far);
  const RouteResult r = graph.route(parseRoadPosition("R1@I0+3"), parseRoadPosition("R2@I0+5"));
  ASSERT_TRUE(r.route) << r.reason;
  EXPECT_NEAR(r.route->length_m, 8.0, 1e-6);
  ASSERT_EQ(r.route->legs.size(), 3u);
  EXPECT_NEAR(radToDeg(r.route->legs[1].angle), -90.0, 1e-6);  // west-bound on R1, right onto R2 (north)
  EXPECT_VEC2_NEAR(r.route->line.front(), kUtm + Vec2(3, 0), 1e-6);
  EXPECT_VEC2_NEAR(r.route->line.back(), kUtm + Vec2(0, 5), 1e-6);
}

// A perfect detection of what the camera sees from `truth`, matched from a prior 0.3 m to the left
// and 2° off, on the star at `centre`.
CurrentPosition matchFromOffsetPrior(const Vec2& centre, const Pose2& truth_rel) {
  const Map map = build(star(centre, {0, 90, 180, 270}, IntersectionKind::Cross));
  const auto camera = testing::terregatorPinhole();
  const Pose2 truth(truth_rel.translation() + centre, truth_rel.heading());
  const Prediction seen = predictView(map, truth, *camera);
  DetectedObject detected;
  for (const InterestSegment& s : seen.view.segments) {
    DetectedLine line;
    line.label = s.id;
    line.score = 1;
    line.image = s.image;
    line.vehicle = s.vehicle;
    detected.lines.push_back(line);
  }
  const Pose2 prior(truth.translation() + Vec2(0.0, 0.3), truth.heading() + degToRad(2.0));
  PoseFilter filter(prior, Mat3(Vec3(0.25, 0.25, 0.01).asDiagonal()));
  return localize(filter, MotionIncrement{}, predictView(map, prior, *camera), detected);
}

TEST(HugeCoordinates, MatchingCorrectsAnOffsetPriorAsAtTheOrigin) {
  const Pose2 truth(Vec2(8.0, 0.0), kPi);  // on R1, facing I0
  const CurrentPosition here = matchFromOffsetPrior(Vec2(0, 0), truth);
  const CurrentPosition far = matchFromOffsetPrior(kUtm, truth);
  ASSERT_TRUE(finite(far.pose));
  EXPECT_TRUE(far.covariance.allFinite());
  EXPECT_EQ(here.status, PositionStatus::Corrected) << here.reason;
  EXPECT_EQ(far.status, PositionStatus::Corrected) << far.reason;
  EXPECT_NEAR(here.pose.y(), 0.0, 0.02);  // across the road: corrected
  EXPECT_VEC2_NEAR(far.pose.translation() - kUtm, here.pose.translation(), 1e-3);
  EXPECT_NEAR(far.pose.heading(), here.pose.heading(), 1e-5);
  EXPECT_NEAR(far.covariance(0, 0), here.covariance(0, 0), 1e-6);
  EXPECT_NEAR(far.covariance(1, 1), here.covariance(1, 1), 1e-6);
}

// ---- cameras looking at the sky ---------------------------------------------------------------

TEST(SkyCamera, LookingUpPredictsNothingAndLocalizesByOdometry) {
  const Map map = build(star(Vec2(0, 0), {0, 90, 180, 270}, IntersectionKind::Cross));
  for (double tilt : {-30.0, -90.0}) {
    const auto camera = testing::terregatorPinhole(tilt);
    const Pose2 pose = facingCentre(map, "R1", 6.0);
    const Prediction p = predictView(map, pose, *camera);
    EXPECT_TRUE(p.empty()) << tilt;
    EXPECT_TRUE(p.footprint_world.empty()) << tilt;
    PoseFilter filter(pose, Mat3(Vec3(0.01, 0.01, 0.001).asDiagonal()));
    const CurrentPosition position = localize(filter, MotionIncrement{0.3, 0.0}, p, DetectedObject{});
    EXPECT_TRUE(finite(position.pose)) << tilt;
    EXPECT_EQ(position.status, PositionStatus::OdometryOnly) << tilt;
    EXPECT_NEAR(position.pose.x(), pose.x() - 0.3, 1e-9);  // it drove 0.3 m west
  }
}

TEST(SkyCamera, RowsAboveTheHorizonDoNotBackProject) {
  // Level camera: the horizon is the principal point's row, v = 239.5.
  const auto level = testing::terregatorPinhole(0.0);
  for (double v : {0.0, 100.0, 239.0, 239.5}) {
    for (double u : {0.0, 255.5, 511.0}) EXPECT_FALSE(level->backproject(Vec2(u, v))) << u << "," << v;
  }
  for (double v : {250.0, 300.0, 479.0}) {
    const auto ground = level->backproject(Vec2(255.5, v));
    ASSERT_TRUE(ground) << v;
    EXPECT_TRUE(finite(*ground));
    // Similar triangles: 1.5 m high, (v − 239.5) px below the horizon at f = 904 px.
    const double ahead = ground->x() - level->center().x();
    EXPECT_NEAR(ahead, 1.5 * 904.0 / (v - 239.5), 1e-6 * ahead) << v;
  }
  // Looking up 30°: every row is sky.
  const auto up = testing::terregatorPinhole(-30.0);
  for (double v = 0; v < 480; v += 31) EXPECT_FALSE(up->backproject(Vec2(255.5, v))) << v;
}

}  // namespace
}  // namespace mapnav
