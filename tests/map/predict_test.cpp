#include "mapnav/map/predict.h"

#include <gtest/gtest.h>

#include <set>

#include "map_fixtures.h"
#include "mapnav/core/error.h"
#include "mapnav/map/generate.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

constexpr double kHeight = 1.5;
constexpr double kTilt = 0.35;  // rad, about 20 degrees down
constexpr double kF = 500.0, kCx = 319.5, kCy = 239.5;

std::unique_ptr<Camera> pinhole(double tilt = kTilt) {
  CameraIntrinsics in;
  in.width = 640;
  in.height = 480;
  in.fx = in.fy = kF;
  in.cx = kCx;
  in.cy = kCy;
  CameraMount mount;
  mount.height_m = kHeight;
  mount.tilt_rad = tilt;
  return createCamera(LensModel::Pinhole, in, mount);
}

// The pin-hole formulas, written out independently of the camera code: a ground point (x, y) in
// the vehicle frame seen by a camera at height h pitched down by β.
Vec2 pinholePixel(const Vec2& g) {
  const double Z = g.x() * std::cos(kTilt) + kHeight * std::sin(kTilt);
  const double X = -g.y();
  const double Y = kHeight * std::cos(kTilt) - g.x() * std::sin(kTilt);
  return {kCx + kF * X / Z, kCy + kF * Y / Z};
}

Intersection node(const std::string& id, IntersectionKind kind, Vec2 p) { return {id, kind, p, std::nullopt}; }

Road road(const std::string& id, const std::string& from, const std::string& to, std::vector<Vec2> line, double width = 2.0) {
  Road r;
  r.id = id;
  r.from = from;
  r.to = to;
  r.centerline = Polyline2(std::move(line));
  r.width = width;
  r.surface = "concrete";
  r.left = "grass";
  r.right = "dirt";
  return r;
}

MapData withSurfaces(MapData m) {
  m.name = "test";
  m.surfaces = {{"concrete", {Vec3(178, 176, 168), Vec3(10, 10, 10)}},
                {"grass", {Vec3(70, 120, 50), Vec3(10, 10, 10)}},
                {"dirt", {Vec3(122, 96, 66), Vec3(10, 10, 10)}}};
  return m;
}

// A 100 m straight road along x, the vehicle at its middle looking along it.
MapData straightRoad() {
  MapData m;
  m.intersections = {node("A", IntersectionKind::End, {-50, 0}), node("B", IntersectionKind::End, {50, 0})};
  m.roads = {road("R1", "A", "B", {{-50, 0}, {50, 0}})};
  return withSurfaces(m);
}

const InterestSegment* segment(const Prediction& p, const std::string& id) {
  for (const InterestSegment& s : p.view.segments) {
    if (s.id == id) return &s;
  }
  return nullptr;
}

TEST(StraightRoadAhead, GivesTwoParallelSegmentsOneWidthApartAtThePinholePixels) {
  const Map map(straightRoad());
  const auto camera = pinhole();
  const Prediction p = predictView(map, Pose2(0, 0, 0), *camera);
  ASSERT_EQ(p.view.regions.size(), 1u);
  EXPECT_EQ(p.view.regions[0].kind, "straight road");
  ASSERT_EQ(p.view.segments.size(), 2u);
  const InterestSegment* left = segment(p, "R1.left.0");
  const InterestSegment* right = segment(p, "R1.right.0");
  ASSERT_TRUE(left && right);
  for (const Vec2& q : {left->vehicle.a, left->vehicle.b}) EXPECT_NEAR(q.y(), 1.0, 1e-9);
  for (const Vec2& q : {right->vehicle.a, right->vehicle.b}) EXPECT_NEAR(q.y(), -1.0, 1e-9);
  for (const InterestSegment* s : {left, right}) {
    EXPECT_VEC2_NEAR(s->image.a, pinholePixel(s->vehicle.a), 1e-6);
    EXPECT_VEC2_NEAR(s->image.b, pinholePixel(s->vehicle.b), 1e-6);
    EXPECT_LE(s->vehicle.b.x(), 15.0 + 1e-9);  // clipped to the far range
  }
  // Walking from A to B the grass is on the left of the left edge, the dirt right of the right edge.
  EXPECT_EQ(left->left_surface, "grass");
  EXPECT_EQ(left->right_surface, "concrete");
  EXPECT_EQ(right->right_surface, "dirt");
  EXPECT_EQ(left->left_rgb, Vec3(70, 120, 50));
  ASSERT_EQ(p.view.relations.size(), 1u);
  EXPECT_EQ(p.view.relations[0].type, SegmentRelation::Type::Parallel);
  EXPECT_NEAR(p.view.relations[0].separation_m, 2.0, 1e-9);
}

// A point (x, y, z) of the vehicle frame through the same pin-hole, written out independently.
Vec2 pinholePixel3(const Vec3& q) {
  const double Z = q.x() * std::cos(kTilt) + (kHeight - q.z()) * std::sin(kTilt);
  const double Y = (kHeight - q.z()) * std::cos(kTilt) - q.x() * std::sin(kTilt);
  return {kCx + kF * -q.y() / Z, kCy + kF * Y / Z};
}

TEST(StraightRoadAhead, ListsTheLandmarksInViewNearestFirstWithTheirBaseAndTopPixels) {
  MapData data = straightRoad();
  data.landmarks = {Landmark{"P1", LandmarkKind::Pole, Vec2(6, 2), 0.1, 5.0, "", {}},
                    Landmark{"B1", LandmarkKind::Bench, Vec2(-5, 2), 0.8, 0.8, "", {}},     // behind the camera
                    Landmark{"M1", LandmarkKind::Manhole, Vec2(30, 0), 0.3, 0.0, "", {}},   // beyond the 15 m range
                    Landmark{"X1", LandmarkKind::Bollard, Vec2(8, 9), 0.08, 0.9, "", {}},   // out of the field
                    Landmark{"T1", LandmarkKind::Tree, Vec2(4, -2.5), 0.15, 6.0, "", {}}};
  const Map map(data);
  const auto camera = pinhole();
  const Prediction p = predictView(map, Pose2(0, 0, 0), *camera);
  ASSERT_EQ(p.view.landmarks.size(), 2u);
  const PredictedLandmark& tree = p.view.landmarks[0];
  const PredictedLandmark& pole = p.view.landmarks[1];
  EXPECT_EQ(tree.id, "T1");
  EXPECT_EQ(tree.kind, "tree");
  EXPECT_EQ(pole.id, "P1");
  EXPECT_EQ(p.landmarks[1], &map.landmarks()[0]);
  EXPECT_VEC2_NEAR(pole.vehicle, Vec2(6, 2), 1e-12);
  EXPECT_VEC2_NEAR(pole.image_base, pinholePixel(Vec2(6, 2)), 1e-6);
  EXPECT_VEC2_NEAR(pole.image_top, pinholePixel3(Vec3(6, 2, 5)), 1e-6);
  EXPECT_NEAR(tree.image_top.y(), pinholePixel3(Vec3(4, -2.5, 6)).y(), 1e-6);
  // Its diameter: the ground points 0.1 m to either side across the line of sight, (6, 2) ± 0.1 (−2, 6)/√40.
  const Vec2 across = Vec2(-2, 6) / std::sqrt(40.0) * 0.1;
  EXPECT_NEAR(pole.width_px, (pinholePixel(Vec2(6, 2) + across) - pinholePixel(Vec2(6, 2) - across)).norm(), 1e-6);
  EXPECT_EQ(pole.height_m, 5.0);
  // Seen from 3 m further along the road, the pole is 3 m nearer, and so is every pixel.
  const Prediction q = predictView(map, Pose2(3, 0, 0), *camera);
  ASSERT_GE(q.view.landmarks.size(), 1u);
  EXPECT_EQ(q.view.landmarks[0].id, "P1");
  EXPECT_VEC2_NEAR(q.view.landmarks[0].image_base, pinholePixel(Vec2(3, 2)), 1e-6);
}

TEST(StraightRoadAhead, SegmentIdsStayTheSameAsTheVehicleMoves) {
  const Map map(straightRoad());
  const auto camera = pinhole();
  for (double x : {-20.0, 0.0, 17.5}) {
    const Prediction p = predictView(map, Pose2(x, 0.3, 0.05), *camera);
    EXPECT_TRUE(segment(p, "R1.left.0")) << x;
    EXPECT_TRUE(segment(p, "R1.right.0")) << x;
  }
}

// Vision gets vehicle- and image-frame geometry only: moving the whole world (map and pose) by a
// rigid motion leaves the token unchanged.
TEST(StraightRoadAhead, TheVisionTokenDependsOnlyOnWhereTheVehicleIsRelativeToTheRoads) {
  const auto camera = pinhole();
  const Prediction here = predictView(Map(straightRoad()), Pose2(3, 0.2, 0.1), *camera);
  const Pose2 motion(120, -45, 0.8);
  MapData moved = straightRoad();
  for (Intersection& x : moved.intersections) x.position = motion.transform(x.position);
  for (Road& r : moved.roads) {
    std::vector<Vec2> line;
    for (const Vec2& q : r.centerline.points()) line.push_back(motion.transform(q));
    r.centerline = Polyline2(line);
  }
  const Prediction there = predictView(Map(moved), motion * Pose2(3, 0.2, 0.1), *camera);
  ASSERT_EQ(here.view.segments.size(), there.view.segments.size());
  for (std::size_t i = 0; i < here.view.segments.size(); ++i) {
    EXPECT_EQ(here.view.segments[i].id, there.view.segments[i].id);
    EXPECT_VEC2_NEAR(here.view.segments[i].vehicle.a, there.view.segments[i].vehicle.a, 1e-9);
    EXPECT_VEC2_NEAR(here.view.segments[i].image.b, there.view.segments[i].image.b, 1e-6);
  }
}

// Roads of 20 m from a centre at (10, 0) in the given directions (degrees), the vehicle on the
// road coming from the west at the origin, looking east.
MapData junction(IntersectionKind kind, const std::vector<double>& branch_deg) {
  MapData m;
  m.intersections = {node("X", kind, {10, 0}), node("W", IntersectionKind::End, {-10, 0})};
  m.roads = {road("RW", "W", "X", {{-10, 0}, {10, 0}})};
  int i = 0;
  for (double deg : branch_deg) {
    const std::string id = "B" + std::to_string(i++);
    const Vec2 end = Vec2(10, 0) + 20 * unitVector(degToRad(deg));
    m.intersections.push_back(node("E" + id, IntersectionKind::End, end));
    m.roads.push_back(road(id, "X", "E" + id, {{10, 0}, end}));
  }
  return withSurfaces(m);
}

std::vector<double> crossingAngles(const Prediction& p) {
  std::vector<double> out;
  for (const SegmentRelation& r : p.view.relations) {
    if (r.type == SegmentRelation::Type::Crossing) out.push_back(radToDeg(r.angle_rad));
  }
  return out;
}

bool hasAngle(const std::vector<double>& angles, double deg) {
  return std::any_of(angles.begin(), angles.end(), [&](double a) { return std::abs(a - deg) < 1e-6; });
}

TEST(CrossIntersectionAhead, CornersCrossAtNinetyDegrees) {
  const Map map(junction(IntersectionKind::Cross, {0, 90, -90}));
  const Prediction p = predictView(map, Pose2(0, 0, 0), *pinhole());
  ASSERT_FALSE(p.empty());
  EXPECT_TRUE(std::any_of(p.view.regions.begin(), p.view.regions.end(),
                          [](const PredictedRegion& r) { return r.kind == "cross intersection"; }));
  // The near-left corner: RW's left edge (y = 1) meets the north road B1's left edge (x = 9) at (9, 1).
  bool corner = false;
  for (const SegmentRelation& r : p.view.relations) {
    const std::set<std::string> pair{r.a, r.b};
    if (r.type == SegmentRelation::Type::Crossing && pair == std::set<std::string>{"RW.left.0", "B1.left.0"}) {
      corner = true;
      EXPECT_NEAR(radToDeg(r.angle_rad), 90.0, 1e-9);
      EXPECT_VEC2_NEAR(r.point, Vec2(9, 1), 1e-9);
    }
  }
  EXPECT_TRUE(corner);
  // The edges stop where the crossing road begins: RW.left ends at x = 9, not at the centre.
  const InterestSegment* rw_left = segment(p, "RW.left.0");
  ASSERT_TRUE(rw_left);
  EXPECT_NEAR(std::max(rw_left->vehicle.a.x(), rw_left->vehicle.b.x()), 9.0, 1e-9);
}

TEST(TIntersectionAhead, StemAndTopCrossAtNinetyDegrees) {
  const Map map(junction(IntersectionKind::T, {90, -90}));  // the road ends at a road across it
  const Prediction p = predictView(map, Pose2(0, 0, 0), *pinhole());
  EXPECT_TRUE(std::any_of(p.view.regions.begin(), p.view.regions.end(),
                          [](const PredictedRegion& r) { return r.kind == "T intersection"; }));
  const auto angles = crossingAngles(p);
  EXPECT_TRUE(hasAngle(angles, 90.0));
  for (double a : angles) EXPECT_NEAR(a, 90.0, 1e-6);
}

TEST(TIntersectionAhead, IsPavedLikeItsWidestRoadWhateverTheRoadOrder) {
  // A 2 m concrete road along x meets a 3 m brick road ending at it from the north. The junction's
  // roads are listed by heading (east 0°, north 90°, west 180°), so the concrete comes first, yet the
  // junction is brick: the simulator paints it so.
  MapData m;
  m.intersections = {node("W", IntersectionKind::End, {-30, 0}), node("T", IntersectionKind::T, {0, 0}),
                     node("E", IntersectionKind::End, {30, 0}), node("N", IntersectionKind::End, {0, 30})};
  m.roads = {road("RW", "W", "T", {{-30, 0}, {0, 0}}), road("RE", "T", "E", {{0, 0}, {30, 0}}),
             road("RN", "N", "T", {{0, 30}, {0, 0}}, 3.0)};
  m.roads[2].surface = "brick";
  m = withSurfaces(m);
  m.surfaces.push_back({"brick", {Vec3(150, 72, 56), Vec3(16, 11, 10)}});
  const Map map(m);
  ASSERT_EQ(map.roadsAt("T").front().road->id, "RE");
  EXPECT_EQ(intersectionSurface(map, map.intersection("T")), "brick");
  EXPECT_EQ(intersectionSurface(map, map.intersection("W")), "concrete");
  // Looking south down the brick road from 6 m short of the junction.
  const Prediction p = predictView(map, Pose2(0, 6, degToRad(-90)), *pinhole());
  const auto t = std::find_if(p.view.regions.begin(), p.view.regions.end(),
                              [](const PredictedRegion& r) { return r.id == "T"; });
  ASSERT_NE(t, p.view.regions.end());
  EXPECT_EQ(t->surface, "brick");
  EXPECT_EQ(t->rgb, Vec3(150, 72, 56));
}

TEST(YIntersectionAhead, BranchesSixtyDegreesApartCrossAtSixtyAndThirtyDegrees) {
  const Map map(junction(IntersectionKind::Y, {30, -30}));
  const Prediction p = predictView(map, Pose2(0, 0, 0), *pinhole());
  EXPECT_TRUE(std::any_of(p.view.regions.begin(), p.view.regions.end(),
                          [](const PredictedRegion& r) { return r.kind == "Y intersection"; }));
  const auto angles = crossingAngles(p);
  // The branches' inner edges meet at 60 degrees, 1 / sin(30°) = 2 m beyond the centre.
  EXPECT_TRUE(hasAngle(angles, 60.0));
  for (const SegmentRelation& r : p.view.relations) {
    if (r.type == SegmentRelation::Type::Crossing && std::abs(radToDeg(r.angle_rad) - 60.0) < 1e-6) {
      EXPECT_VEC2_NEAR(r.point, Vec2(12, 0), 1e-9);
    }
  }
  // The stem's edges meet the outer branch edges at 30 degrees.
  EXPECT_TRUE(hasAngle(angles, 30.0));
}

TEST(PredictView, APoseOffEveryRoadGivesAnEmptyPrediction) {
  const Map map(straightRoad());
  const Prediction p = predictView(map, Pose2(0, 200, kPi / 2), *pinhole());
  EXPECT_TRUE(p.empty());
  EXPECT_FALSE(p.view.footprint.empty());
}

TEST(PredictView, ACameraLookingAboveTheHorizonGivesAnEmptyPrediction) {
  const Map map(straightRoad());
  const Prediction p = predictView(map, Pose2(0, 0, 0), *pinhole(-0.8));  // 46 degrees up
  EXPECT_TRUE(p.empty());
  EXPECT_TRUE(p.view.footprint.empty());
  EXPECT_TRUE(p.footprint_world.empty());
}

TEST(PredictView, OnAGridLookingAlongARoadSeesItsEdges) {
  const Map map = [] {
    GridMapOptions o;
    o.columns = o.rows = 3;
    return Map(makeGridMap(o));
  }();
  const Prediction p = predictView(map, Pose2(3, 0, 0), *pinhole());
  EXPECT_TRUE(segment(p, "H0_0.left.0") || segment(p, "H0_0.right.0"));
}

TEST(PredictView, TheFootprintFollowsTheCameraAndTheRange) {
  // A ViewPredictor keeps the last camera's footprint (in the vehicle frame): another tilt right
  // after must give what a fresh predictor gives, and so must another range (another predictor).
  const Map map = [] {
    GridMapOptions o;
    o.columns = o.rows = 3;
    return Map(makeGridMap(o));
  }();
  const Pose2 pose(3, 0, 0);
  const auto steep = pinhole(0.6), shallow = pinhole(0.3);
  PredictOptions shorter;
  shorter.far_m = 6.0;
  const auto fresh = [&](const Camera& camera, const PredictOptions& options) {
    return ViewPredictor(map, options).predict(pose, camera).view.footprint;
  };
  const Polygon2 steep_first = fresh(*steep, {}), shallow_first = fresh(*shallow, {});
  const Polygon2 short_first = fresh(*shallow, shorter);
  ASSERT_GE(steep_first.size(), 3u);
  EXPECT_NE(steep_first, shallow_first);  // the tilt moves the footprint
  EXPECT_NE(shallow_first, short_first);  // and so does the range
  ViewPredictor kept(map), kept_shorter(map, shorter);
  EXPECT_EQ(kept.predict(pose, *steep).view.footprint, steep_first);
  EXPECT_EQ(kept.predict(Pose2(4, 1, 0.5), *steep).view.footprint, steep_first);  // not the pose
  EXPECT_EQ(kept.predict(pose, *shallow).view.footprint, shallow_first);
  EXPECT_EQ(kept_shorter.predict(pose, *shallow).view.footprint, short_first);
  EXPECT_EQ(kept.predict(pose, *steep).view.footprint, steep_first);
}

// Two predictions are the same, to the last bit.
void expectSamePrediction(const Prediction& a, const Prediction& b, const std::string& what) {
  EXPECT_EQ(a.footprint_world, b.footprint_world) << what;
  ASSERT_EQ(a.view.segments.size(), b.view.segments.size()) << what;
  for (std::size_t i = 0; i < a.view.segments.size(); ++i) {
    EXPECT_EQ(a.view.segments[i].id, b.view.segments[i].id) << what;
    EXPECT_EQ(a.view.segments[i].image.a, b.view.segments[i].image.a) << what;
    EXPECT_EQ(a.view.segments[i].image.b, b.view.segments[i].image.b) << what;
    EXPECT_EQ(a.segments_world[i].a, b.segments_world[i].a) << what;
    EXPECT_EQ(a.segments_world[i].b, b.segments_world[i].b) << what;
  }
  ASSERT_EQ(a.view.regions.size(), b.view.regions.size()) << what;
  for (std::size_t i = 0; i < a.view.regions.size(); ++i) {
    EXPECT_EQ(a.view.regions[i].id, b.view.regions[i].id) << what;
    EXPECT_EQ(a.view.regions[i].kind, b.view.regions[i].kind) << what;
    EXPECT_EQ(a.view.regions[i].segments, b.view.regions[i].segments) << what;
    EXPECT_EQ(a.regions_world[i], b.regions_world[i]) << what;
  }
  EXPECT_EQ(a.view.relations.size(), b.view.relations.size()) << what;
}

TEST(ViewPredictor, KeepsWhatThePoseDoesNotChangeAndGivesPredictViewsAnswers) {
  // Along every road of the campus (curves, plazas, T and Y intersections), both ways, twice: the
  // second pass takes each road's and intersection's segments from the store. Two predictors with
  // different options must each give what predictView gives with theirs. A pose every 7 m (every
  // 21 m under the sanitizers, where predicting runs 5-10 times slower).
  const Map& map = testing::campusMap();
  PredictOptions coarse;
  coarse.simplify_tolerance_m = 0.5;
  ViewPredictor fine_predictor(map), coarse_predictor(map, coarse);
  const auto camera = pinhole();
  int frames = 0, segments = 0, curves = 0, differ = 0;
  for (int pass = 0; pass < 2; ++pass) {
    for (const Road& road : map.roads()) {
      for (double s = 1.0; s < road.centerline.length(); s += testing::kUnderSanitizers ? 21.0 : 7.0) {
        for (const double turn : {0.0, kPi}) {
          const Pose2 pose(road.centerline.pointAt(s), road.centerline.headingAt(s) + turn);
          const std::string what = road.id + " at " + std::to_string(s) + (turn == 0 ? " forward" : " back");
          const Prediction fine = fine_predictor.predict(pose, *camera);
          const Prediction rough = coarse_predictor.predict(pose, *camera);
          expectSamePrediction(fine, predictView(map, pose, *camera), what);
          expectSamePrediction(rough, predictView(map, pose, *camera, coarse), what + " (coarse)");
          if (::testing::Test::HasFailure()) return;
          ++frames;
          segments += static_cast<int>(fine.view.segments.size());
          for (const PredictedRegion& r : fine.view.regions) curves += r.kind == "curve" ? 1 : 0;
          differ += fine.view.segments.size() != rough.view.segments.size() ? 1 : 0;
        }
      }
    }
  }
  EXPECT_GT(frames, testing::kUnderSanitizers ? 40 : 100);
  EXPECT_GT(segments, 2 * frames);  // the views have something in them
  EXPECT_GT(curves, 0);
  EXPECT_GT(differ, 0);  // the options matter, so a store shared between them would show
}

TEST(ViewPredictor, BadOptionsAreRefused) {
  const Map map(straightRoad());
  PredictOptions bad;
  bad.far_m = 0.5;
  EXPECT_THROW(ViewPredictor(map, bad), InvalidInput);
}

TEST(PredictOptions, DefaultsAreValidAndBadFieldsAreNamed) {
  EXPECT_NO_THROW(PredictOptions{}.validate());
  PredictOptions o;
  o.far_m = 0.5;
  try {
    o.validate();
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "PredictOptions::far_m = 0.5: must be > near_m");
  }
  o = {};
  o.crossing_min_angle_deg = 4;  // not above parallel_tolerance_deg (5)
  EXPECT_TRUE(testing::throwsInvalidInputNaming(
      [&] { o.validate(); }, "PredictOptions::crossing_min_angle_deg = 4: must be > parallel_tolerance_deg"));
  o.crossing_min_angle_deg = 91;
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { o.validate(); },
                                                "PredictOptions::crossing_min_angle_deg = 91: must be in (0, 90]"));
  o = {};
  o.parallel_tolerance_deg = 45;
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { o.validate(); },
                                                "PredictOptions::parallel_tolerance_deg = 45: must be in [0, 45)"));
}

TEST(MakeGridMap, BadOptionsAreNamed) {
  GridMapOptions o;
  o.rows = 1;
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { makeGridMap(o); }, "GridMapOptions::rows = 1: must be >= 2"));
  o = {};
  o.spacing_m = 4;
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { makeGridMap(o); }, "GridMapOptions::spacing_m = 4: must be > 2 width_m"));
}

TEST(MakeGridMap, HasTheRoadCountItPromisesAndIsValid) {
  GridMapOptions o;
  o.columns = 4;
  o.rows = 3;
  const MapData data = makeGridMap(o);
  EXPECT_EQ(data.roads.size(), 4u * 2 + 3u * 3);
  const Map map(data);  // throws if invalid
  EXPECT_TRUE(map.warnings().empty());
  EXPECT_EQ(map.intersection("I1_1").kind, IntersectionKind::Cross);
  EXPECT_EQ(map.intersection("I0_1").kind, IntersectionKind::T);
  EXPECT_EQ(map.intersection("I3_2").kind, IntersectionKind::L);
}

}  // namespace
}  // namespace mapnav
