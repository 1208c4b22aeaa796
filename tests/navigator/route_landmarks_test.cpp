// The A* lower bounds' landmark distances (navigator/src/route_network.h, internal): on a chain of
// straight roads whose headings change at every intersection, the bound between the chain's inner
// ends is the drive plus the turns (exact: one path), and without turn penalties the drive alone.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "../../navigator/src/route_network.h"
#include "mapnav/map/generate.h"

namespace mapnav::route_detail {
namespace {

constexpr double kDeg = kPi / 180;

// Roads R0..R4 of 10 m from I0 to I5, R_i at heading headings[i] (degrees), and the headings the
// network is built with (each traversal straight: the same heading arriving and leaving).
struct Chain {
  Map map;
  std::vector<double> in, out;
};

Chain chain(const std::vector<double>& headings) {
  MapData m = makeGridMap(GridMapOptions{2, 2, 40, 2});  // for its surfaces
  m.intersections.clear();
  m.roads.clear();
  Vec2 at(0, 0);
  m.intersections.push_back({"I0", IntersectionKind::Other, at, std::nullopt});
  std::vector<double> in, out;
  for (std::size_t i = 0; i < headings.size(); ++i) {
    const double a = headings[i] * kDeg;
    const Vec2 next = at + 10.0 * Vec2(std::cos(a), std::sin(a));
    m.intersections.push_back({"I" + std::to_string(i + 1), IntersectionKind::Other, next, std::nullopt});
    Road r;
    r.id = "R" + std::to_string(i);
    r.from = "I" + std::to_string(i);
    r.to = "I" + std::to_string(i + 1);
    r.centerline = Polyline2({at, next});
    r.surface = "concrete";
    r.left = r.right = "grass";
    m.roads.push_back(r);
    for (const double h : {a, a + kPi}) {  // forward, then backward
      in.push_back(h);
      out.push_back(h);
    }
    at = next;
  }
  return Chain{Map(m), in, out};
}

TEST(Landmarks, BoundsAlongAChainAreTheDriveAndTheTurnsOntoEachRoad) {
  // Turns of 10, 15, 25 and 0 degrees at I1..I4; 9 m per 90 degrees is 0.1 m a degree.
  const Chain c = chain({0, 10, -5, 20, 20});
  const Network n = Network::build(c.map, c.in, c.out);
  const TurnCosts turns{9, 50};
  const Landmarks with = chooseLandmarks(n, 8, turns), without = chooseLandmarks(n, 8, TurnCosts{});
  // From I1 (where a route that starts on R0 leaves it) to I5: 40 m and turns of 1.0 + 1.5 + 2.5 + 0 m.
  EXPECT_NEAR(with.bound(1, 5), 40 + 5.0, 1e-9);
  EXPECT_NEAR(without.bound(1, 5), 40, 1e-9);
  // Back from I4 to I1: R3, R2 and R1 driven backwards, turned onto at I4 (straight on from R4),
  // I3 (25 deg) and I2 (15 deg).
  EXPECT_NEAR(with.bound(4, 1), 30 + 0 + 2.5 + 1.5, 1e-9);
  // R0 forward can only be turned onto by a U-turn at I0 (a dead end): 10 m and 50 m from I0 to I1.
  EXPECT_NEAR(with.bound(0, 1), 10 + 50, 1e-9);
  // Lower penalties are not covered by landmarks made with higher ones; equal or higher are.
  EXPECT_TRUE(boundsHold(turns, TurnCosts{9, 50}));
  EXPECT_TRUE(boundsHold(turns, TurnCosts{12, 60}));
  EXPECT_FALSE(boundsHold(turns, TurnCosts{8, 50}));
  EXPECT_FALSE(boundsHold(turns, TurnCosts{9, 40}));
}

}  // namespace
}  // namespace mapnav::route_detail
