// The fast route query (bidirectional A* with landmark bounds) against the reference (Dijkstra over
// the whole graph) on random pairs, with random blocked roads and intersections and random turn
// penalties, on a grid and on an irregular map with one-way roads; and every route checked to be a
// drivable path (connected legs, one-way roads driven their way, nothing blocked) whose cost,
// recomputed from its legs, is the cost reported.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "mapnav/map/generate.h"
#include "mapnav/navigator/route.h"

namespace mapnav {
namespace {

// A jittered grid of `n` × `n` intersections 30 m apart, joined to their right and upper neighbours
// (each road kept with probability 0.85) and across some cells by a diagonal, every road bent at
// its middle (so turns are of many angles), one in ten one-way, cost factors in [1, 2).
Map irregularMap(int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-4.0, 4.0), unit(0.0, 1.0), factor(1.0, 2.0);
  MapData m = makeGridMap(GridMapOptions{2, 2, 40, 2});  // for its surfaces
  m.name = "irregular";
  m.intersections.clear();
  m.roads.clear();
  auto id = [n](int c, int r) { return "N" + std::to_string(c * n + r); };
  std::vector<Vec2> at;
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < n; ++r) {
      at.emplace_back(30.0 * c + jitter(rng), 30.0 * r + jitter(rng));
      m.intersections.push_back({id(c, r), IntersectionKind::Other, at.back(), std::nullopt});
    }
  }
  auto road = [&](int c0, int r0, int c1, int r1) {
    const Vec2 a = at[c0 * n + r0], b = at[c1 * n + r1];
    const Vec2 d = b - a, bend = 0.5 * (a + b) + jitter(rng) / 4.0 * Vec2(-d.y(), d.x()) / d.norm();
    Road x;
    x.id = "R" + std::to_string(m.roads.size());
    x.from = id(c0, r0);
    x.to = id(c1, r1);
    x.centerline = Polyline2({a, bend, b});
    x.surface = "concrete";
    x.left = x.right = "grass";
    x.oneway = unit(rng) < 0.1;
    x.cost_factor = factor(rng);
    m.roads.push_back(x);
  };
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < n; ++r) {
      if (c + 1 < n && unit(rng) < 0.85) road(c, r, c + 1, r);
      if (r + 1 < n && unit(rng) < 0.85) road(c, r, c, r + 1);
      if (c + 1 < n && r + 1 < n && unit(rng) < 0.2) {
        if (unit(rng) < 0.5) road(c, r, c + 1, r + 1); else road(c + 1, r, c, r + 1);
      }
    }
  }
  return Map(m);
}

// Walks the route's legs from `from` and fails the test where they are not a drivable path that
// avoids `blocked`; returns the cost the legs add up to (drive × cost factor + turn penalties).
double checkedCost(const Map& map, const Route& route, const RouteOptions& o) {
  const std::set<std::string> blocked(o.blocked.begin(), o.blocked.end());
  auto arc = [&](const RoadPosition& p) {
    const Road& r = map.road(p.road);
    return p.node == r.from ? p.meters : r.centerline.length() - p.meters;
  };
  EXPECT_FALSE(route.legs.empty());
  std::string road = route.from.road, node;  // the road driven, the node it was entered at
  double s = arc(route.from), cost = 0;      // arc length along it where the vehicle is
  for (std::size_t i = 0; i < route.legs.size(); ++i) {
    const Leg& leg = route.legs[i];
    const Road& r = map.road(road);
    EXPECT_FALSE(blocked.contains(road)) << road;
    if (leg.action == LegAction::Turn) {
      EXPECT_FALSE(blocked.contains(leg.at)) << leg.at;
      EXPECT_TRUE(leg.at == r.from || leg.at == r.to) << leg.at << " is not an end of " << road;
      const Road& onto = map.road(leg.road);
      EXPECT_TRUE(leg.at == onto.from || (leg.at == onto.to && !onto.oneway)) << "onto " << onto.id << " at " << leg.at;
      const bool u_turn = onto.id == road;
      cost += u_turn ? o.u_turn_penalty_m : std::abs(leg.angle) / (kPi / 2) * o.turn_penalty_m_per_90deg;
      road = onto.id;
      node = leg.at;
      s = leg.at == onto.from ? 0.0 : onto.centerline.length();
      continue;
    }
    EXPECT_EQ(leg.road, road);
    const bool last = i + 1 == route.legs.size();
    // The end driven to: the goal on the last leg, else the end the next turn is at.
    const double s_end = last ? arc(route.to) : (route.legs[i + 1].at == r.from ? 0.0 : r.centerline.length());
    if (!last && r.from == r.to) ADD_FAILURE() << "a loop road in the test map";
    EXPECT_NEAR(leg.meters, std::abs(s_end - s), 1e-9) << road;
    EXPECT_TRUE(!r.oneway || s_end >= s) << road << " driven against its one-way direction";
    if (last) {
      EXPECT_EQ(road, route.to.road);
    }
    cost += leg.meters * r.cost_factor;
    s = s_end;
  }
  return cost;
}

// 200 seeded random queries on `map`: 0–3 blocked roads or intersections, turn penalties 0–20 m
// per 90 degrees and U-turns 0–100 m. Both searches must agree on whether there is a route and on
// its cost, and every route must pass checkedCost.
void compareOnRandomPairs(const Map& map, std::uint32_t seed) {
  RoadGraph graph(map);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::size_t> pick_road(0, map.roads().size() - 1);
  std::uniform_int_distribution<std::size_t> pick_node(0, map.intersections().size() - 1);
  std::uniform_int_distribution<int> blocks(0, 3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int routes = 0, blocked_queries = 0;
  for (int i = 0; i < 200; ++i) {
    const Road& a = map.roads()[pick_road(rng)];
    const Road& b = map.roads()[pick_road(rng)];
    const RoadPosition from{a.id, a.from, unit(rng) * a.centerline.length()};
    const RoadPosition to{b.id, b.to, unit(rng) * b.centerline.length()};
    RouteOptions fast;
    fast.turn_penalty_m_per_90deg = 20 * unit(rng);
    fast.u_turn_penalty_m = 100 * unit(rng);
    for (int k = blocks(rng); k > 0; --k) {
      fast.blocked.push_back(unit(rng) < 0.5 ? map.roads()[pick_road(rng)].id : map.intersections()[pick_node(rng)].id);
    }
    RouteOptions reference = fast;
    reference.use_astar = false;
    const RouteResult r = graph.route(from, to, fast), ref = graph.route(from, to, reference);
    const std::string what = toString(from) + " -> " + toString(to);
    ASSERT_EQ(r.route.has_value(), ref.route.has_value()) << what << ": " << r.reason << " / " << ref.reason;
    EXPECT_EQ(r.reason, ref.reason) << what;
    if (!r.route) continue;
    ++routes;
    blocked_queries += !fast.blocked.empty();
    EXPECT_NEAR(r.route->cost, ref.route->cost, 1e-9 * (1 + ref.route->cost)) << what;
    EXPECT_NEAR(checkedCost(map, *r.route, fast), r.route->cost, 1e-6) << what;
    EXPECT_NEAR(checkedCost(map, *ref.route, reference), ref.route->cost, 1e-6) << what;
  }
  // The pairs must mostly have routes, many with blocks, for the comparison to say something.
  EXPECT_GT(routes, 150);
  EXPECT_GT(blocked_queries, 80);
}

TEST(FastQuery, SameCostsAsDijkstraOnAGridWithBlocksAndTurnPenalties) {
  MapData data = makeGridMap(GridMapOptions{50, 50, 30, 2});  // 2500 intersections
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> factor(1.0, 2.0);
  for (Road& r : data.roads) r.cost_factor = factor(rng);
  compareOnRandomPairs(Map(data), 7);
}

TEST(FastQuery, SameCostsAsDijkstraOnAnIrregularMapWithOneWayRoads) {
  compareOnRandomPairs(irregularMap(45, 13), 17);  // 2025 intersections
}

TEST(FastQuery, ABlockedRoadOnTheBestRouteIsNeverUsed) {
  const Map map(makeGridMap(GridMapOptions{20, 20, 30, 2}));
  RoadGraph graph(map);
  const RoadPosition from{"H0_5", "I0_5", 10}, to{"H18_5", "I18_5", 10};
  const RouteResult straight = graph.route(from, to);
  ASSERT_TRUE(straight.route);
  // Along row 5: 20 m to I1_5, 17 roads of 30 m, 10 m along H18_5; no turn.
  EXPECT_NEAR(straight.route->cost, 20 + 17 * 30 + 10, 1e-9);
  RouteOptions options;
  options.blocked = {"H9_5"};
  const RouteResult around = graph.route(from, to, options);
  ASSERT_TRUE(around.route) << around.reason;
  for (const std::string& road : around.route->roads) EXPECT_NE(road, "H9_5");
  // Round the block by the next row: 60 m more and four 90-degree turns of 5 m.
  EXPECT_NEAR(around.route->cost, 20 + 17 * 30 + 10 + 60 + 4 * 5, 1e-9);
  EXPECT_NEAR(checkedCost(map, *around.route, options), around.route->cost, 1e-9);
}

}  // namespace
}  // namespace mapnav
