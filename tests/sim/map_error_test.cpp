#include "mapnav/sim/map_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/sim/world_io.h"
#include "mapnav/testing/maps.h"

namespace mapnav {
namespace {

// A straight road 2000 m along +x: the world's centre line's y at x is the lateral offset there.
Map longRoad() {
  MapData d = testing::straightRoad("long", 2000, 3.0, "concrete", "grass");
  d.surfaces = testing::concreteAndGrass();
  return Map(std::move(d));
}

std::string text(const Issues& issues) {
  std::string out;
  for (const Issue& i : issues) out += formatIssue(i, "mission.json") + "\n";
  return out;
}

// The world's centre line's lateral offset at x (its y there: the map's is 0).
double lateralAt(const Polyline2& line, double x) {
  const std::vector<Vec2>& p = line.points();
  for (std::size_t i = 1; i < p.size(); ++i) {
    if ((p[i - 1].x() - x) * (p[i].x() - x) <= 0 && p[i].x() != p[i - 1].x()) {
      const double u = (x - p[i - 1].x()) / (p[i].x() - p[i - 1].x());
      return p[i - 1].y() + u * (p[i].y() - p[i - 1].y());
    }
  }
  ADD_FAILURE() << "x " << x << " is beyond the line";
  return 0;
}

TEST(MapErrorOptions, TheDefaultsAreValidAndChangeNothing) {
  const MapErrorOptions defaults;
  EXPECT_NO_THROW(defaults.validate());
  EXPECT_TRUE(defaults.none());
  const Map map = longRoad();
  EXPECT_EQ(perturbedMap(map, defaults).data(), map.data());
  MapErrorOptions bad;
  bad.offset_sigma_m = -0.1;
  try {
    bad.validate();
    FAIL() << "a negative sigma was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("offset_sigma_m"), std::string::npos) << e.what();
  }
}

// Over 40 seeds' worlds of one long straight road, sampled every 5 m: the lateral offsets have the
// asked standard deviation, and offsets L apart correlate by exp(-1/2), 3 L apart by ~0.
TEST(MapError, TheRoadsLateralOffsetsHaveTheAskedSigmaAndCorrelation) {
  const Map map = longRoad();
  const MapData before = map.data();
  MapErrorOptions o;
  o.offset_sigma_m = 0.5;
  o.offset_length_m = 30;
  double sum_sq = 0, lag1 = 0, lag3 = 0;
  int n = 0, n1 = 0, n3 = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    o.seed = seed;
    const Map world = perturbedMap(map, o);
    const Polyline2& line = world.roads().front().centerline;
    std::vector<double> y;
    for (double x = 100; x <= 1900; x += 5) y.push_back(lateralAt(line, x));
    for (std::size_t i = 0; i < y.size(); ++i) {
      sum_sq += y[i] * y[i];
      ++n;
      if (i + 6 < y.size()) lag1 += y[i] * y[i + 6], ++n1;    // 30 m apart
      if (i + 18 < y.size()) lag3 += y[i] * y[i + 18], ++n3;  // 90 m apart
    }
  }
  const double variance = sum_sq / n;
  EXPECT_NEAR(std::sqrt(variance), 0.5, 0.05);
  EXPECT_NEAR(lag1 / n1 / variance, std::exp(-0.5), 0.08);
  EXPECT_NEAR(lag3 / n3 / variance, std::exp(-4.5), 0.08);
  EXPECT_EQ(map.data(), before) << "the map itself was changed";
}

// The field moves the roads' ends with their intersections (they stay joined), a landmark with the
// ground beside its road, and the same seed gives the same world.
TEST(MapError, RoadsStayJoinedAtTheirIntersectionsAndTheSameSeedGivesTheSameWorld) {
  const Map& campus = testing::campusMap();
  MapErrorOptions o;
  o.offset_sigma_m = 1.0;
  o.offset_length_m = 20;
  o.seed = 7;
  const Map world = perturbedMap(campus, o);
  const MapErrorField field(o);
  for (const Road& road : world.roads()) {
    const Road& authored = campus.road(road.id);
    for (const auto& [end, id] : {std::pair{road.centerline.points().front(), road.from},
                                  std::pair{road.centerline.points().back(), road.to}}) {
      const Vec2 original = id == road.from ? authored.centerline.points().front() : authored.centerline.points().back();
      EXPECT_LT((end - (original + field.offset(original))).norm(), 1e-9) << road.id;
      if ((original - campus.intersection(id).position).norm() < 1e-9) {
        EXPECT_LT((end - world.intersection(id).position).norm(), 1e-9) << road.id << " left " << id;
      }
    }
    EXPECT_EQ(road.width, authored.width) << "width_sigma 0 changed " << road.id;
  }
  for (std::size_t i = 0; i < campus.landmarks().size(); ++i) {
    const Vec2 p = campus.landmarks()[i].position;
    EXPECT_LT((world.landmarks()[i].position - (p + field.offset(p))).norm(), 1e-9);
  }
  EXPECT_EQ(perturbedMap(campus, o).data(), world.data());
  o.seed = 8;
  EXPECT_NE(perturbedMap(campus, o).data(), world.data());
}

// The pull-back inverts the displacement: a map pose moved by the field (its position by D, its
// direction by I + dD/dp, differentiated here by a wider central difference than pullBack's) comes
// back to itself; the field of none() options is the identity.
TEST(MapError, ThePullBackOfAMovedPoseIsThePoseOnTheMap) {
  MapErrorOptions o;
  o.offset_sigma_m = 1.0;
  o.offset_length_m = 10;  // slopes up to ~0.2: a hard case for the iteration
  o.seed = 9;
  const MapErrorField field(o);
  for (const Pose2& on_map : {Pose2(0, 0, 0), Pose2(13.5, -7.25, 2.0), Pose2(-40, 22, -1.2)}) {
    const Vec2 p = on_map.translation(), d(std::cos(on_map.heading()), std::sin(on_map.heading()));
    const double h = 0.01;
    const Vec2 moved_dir = d + (field.offset(p + h * d) - field.offset(p - h * d)) / (2 * h);
    const Pose2 world(p + field.offset(p), std::atan2(moved_dir.y(), moved_dir.x()));
    EXPECT_GT((world.translation() - p).norm(), 0.05);  // the field moved it
    const Pose2 back = field.pullBack(world);
    EXPECT_NEAR((back.translation() - p).norm(), 0.0, 1e-7);
    EXPECT_NEAR(normalizeAngle(back.heading() - on_map.heading()), 0.0, 1e-4);
  }
  const MapErrorField none{MapErrorOptions{}};
  const Pose2 q(3, 4, 0.5);
  EXPECT_EQ(none.pullBack(q).translation(), q.translation());
  EXPECT_EQ(none.pullBack(q).heading(), q.heading());
}

TEST(MapError, EachRoadsWidthIsScaledByOnePlusSigmaTimesAClampedNormal) {
  MapData d;
  d.surfaces = testing::concreteAndGrass();
  for (int i = 0; i < 200; ++i) {
    const std::string a = "A" + std::to_string(i), b = "B" + std::to_string(i);
    d.intersections.push_back({a, IntersectionKind::End, Vec2(0, 10.0 * i), std::nullopt});
    d.intersections.push_back({b, IntersectionKind::End, Vec2(5, 10.0 * i), std::nullopt});
    Road r;
    r.id = "R" + std::to_string(i);
    r.from = a;
    r.to = b;
    r.centerline = Polyline2({Vec2(0, 10.0 * i), Vec2(5, 10.0 * i)});
    r.width = 2.0;
    r.surface = "concrete";
    r.left = r.right = "grass";
    d.roads.push_back(r);
  }
  const Map map(std::move(d));
  MapErrorOptions o;
  o.width_sigma = 0.1;
  const Map world = perturbedMap(map, o);
  double sum = 0, sum_sq = 0;
  for (const Road& r : world.roads()) {
    const double z = (r.width / 2.0 - 1.0) / 0.1;
    EXPECT_LE(std::abs(z), 2.0 + 1e-12) << r.id;
    sum += z;
    sum_sq += z * z;
    EXPECT_EQ(r.centerline, map.road(r.id).centerline) << "offset_sigma 0 moved " << r.id;
  }
  EXPECT_NEAR(sum / 200, 0.0, 0.25);
  EXPECT_NEAR(std::sqrt(sum_sq / 200), 1.0, 0.15);  // a clamped normal's: 0.98
}

TEST(MapError, TheWorldBlockReadsItsMapErrorAndNamesEachBadMember) {
  Issues issues;
  const std::string block = R"({"shadow_k": 0.5, "map_error": {"offset_sigma_m": 0.4, "seed": 9}})";
  const WorldOptions world = parseWorldOptions(block, "/world", issues);
  const MapErrorOptions error = parseMapErrorOptions(block, "/world", issues);
  EXPECT_TRUE(issues.empty()) << text(issues);
  EXPECT_EQ(world.shadow_k, 0.5);
  EXPECT_EQ(error.offset_sigma_m, 0.4);
  EXPECT_EQ(error.offset_length_m, MapErrorOptions{}.offset_length_m);
  EXPECT_EQ(error.seed, 9u);
  EXPECT_TRUE(parseMapErrorOptions(R"({"shadow_k": 0.5})", "/world", issues).none());

  parseMapErrorOptions(R"({"map_error": {"offset_sigma_m": -1, "sigma": 2}})", "/world", issues);
  ASSERT_EQ(issues.size(), 2u) << text(issues);
  EXPECT_EQ(issues[0].where, "/world/map_error/offset_sigma_m");
  EXPECT_EQ(issues[1].where, "/world/map_error/sigma");
  issues.clear();
  parseMapErrorOptions(R"({"map_error": 3})", "/world", issues);
  ASSERT_EQ(issues.size(), 1u) << text(issues);
  EXPECT_EQ(issues[0].where, "/world/map_error");
}

// The world's `gnss` object is the vehicle's receiver, GnssReceiverOptions by name; none: no receiver.
TEST(WorldBlock, ItsGnssObjectIsTheVehiclesReceiver) {
  Issues issues;
  const std::string block = R"({"shadow_k": 0.5, "gnss": {"sigma_m": 2, "seed": 4}})";
  EXPECT_EQ(parseWorldOptions(block, "/world", issues).shadow_k, 0.5);
  const std::optional<GnssReceiverOptions> gnss = parseGnssOptions(block, "/world", issues);
  EXPECT_TRUE(issues.empty()) << text(issues);
  ASSERT_TRUE(gnss);
  EXPECT_EQ(gnss->sigma_m, 2.0);
  EXPECT_EQ(gnss->bias_sigma_m, GnssReceiverOptions{}.bias_sigma_m);
  EXPECT_EQ(gnss->seed, 4u);
  EXPECT_FALSE(parseGnssOptions(R"({"shadow_k": 0.5})", "/world", issues));
  parseGnssOptions(R"({"gnss": {"sigma_m": -1}})", "/world", issues);
  ASSERT_EQ(issues.size(), 1u) << text(issues);
  EXPECT_EQ(issues[0].where, "/world/gnss/sigma_m");
}

}  // namespace
}  // namespace mapnav
