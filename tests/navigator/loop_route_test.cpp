// Routes that start, end or pass on loop roads (a road whose two ends are the same intersection),
// in both directions, against an independent brute-force shortest path: Bellman-Ford over the
// directed traversals of the roads, with the headings taken from the centre lines' end segments
// and the start and goal handled here, written without the navigator's search code. Both of the
// navigator's searches (the bidirectional A* and the Dijkstra reference) must report the same cost,
// length and legs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "mapnav/map/generate.h"
#include "mapnav/navigator/route.h"

namespace mapnav {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A jittered 4 × 4 grid of intersections 50 m apart, neighbours joined by roads bent at their
// middle (each kept with probability 0.8), and loop roads at about half the intersections: a
// triangle (or a bent quadrilateral) reaching up to 20 m into the cell above and right of the
// intersection, so no two roads cross. One road in seven is one-way (loops included).
Map loopMap(std::uint32_t seed) {
  constexpr int n = 4;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-3.0, 3.0), unit(0.0, 1.0), factor(1.0, 2.0), reach(8.0, 20.0);
  MapData m = makeGridMap(GridMapOptions{2, 2, 40, 2});  // for its surfaces
  m.intersections.clear();
  m.roads.clear();
  std::vector<Vec2> at;
  for (int i = 0; i < n * n; ++i) {
    at.emplace_back(50.0 * (i / n) + jitter(rng), 50.0 * (i % n) + jitter(rng));
    m.intersections.push_back({"N" + std::to_string(i), IntersectionKind::Other, at.back(), std::nullopt});
  }
  auto add = [&](int a, int b, std::vector<Vec2> line) {
    Road r;
    r.id = (a == b ? "L" : "R") + std::to_string(m.roads.size());
    r.from = "N" + std::to_string(a);
    r.to = "N" + std::to_string(b);
    r.centerline = Polyline2(std::move(line));
    r.width = 1.5;
    r.surface = "concrete";
    r.left = r.right = "grass";
    r.oneway = unit(rng) < 1.0 / 7;
    r.cost_factor = factor(rng);
    m.roads.push_back(std::move(r));
  };
  for (int i = 0; i < n * n; ++i) {
    for (const int j : {i + n, (i % n) + 1 < n ? i + 1 : -1}) {  // right and upper neighbours
      if (j < 0 || j >= n * n || unit(rng) >= 0.8) continue;
      const Vec2 a = at[i], b = at[j], d = b - a;
      add(i, j, {a, 0.5 * (a + b) + jitter(rng) * Vec2(-d.y(), d.x()) / d.norm(), b});
    }
    if (unit(rng) < 0.5) {
      const Vec2 x = at[i];
      std::vector<Vec2> loop{x, x + Vec2(reach(rng), 4 + 2 * unit(rng))};
      if (unit(rng) < 0.5) loop.push_back(x + Vec2(12 + 4 * unit(rng), 12 + 4 * unit(rng)));
      loop.push_back(x + Vec2(4 + 2 * unit(rng), reach(rng)));
      loop.push_back(x);
      if (unit(rng) < 0.5) std::reverse(loop.begin(), loop.end());  // either way round
      add(i, i, loop);
    }
  }
  return Map(m);
}

// The independent reference: Bellman-Ford over traversals t = 2 r (from → to) and 2 r + 1 (back).
struct BruteForce {
  const Map& map;
  RouteOptions options;

  const Road& road(std::size_t t) const { return map.roads()[t / 2]; }
  bool fwd(std::size_t t) const { return t % 2 == 0; }
  bool drivable(std::size_t t) const { return fwd(t) || !road(t).oneway; }
  const std::string& startNode(std::size_t t) const { return fwd(t) ? road(t).from : road(t).to; }
  const std::string& endNode(std::size_t t) const { return fwd(t) ? road(t).to : road(t).from; }
  double length(std::size_t t) const { return road(t).centerline.length(); }
  static double heading(const Vec2& a, const Vec2& b) { return std::atan2(b.y() - a.y(), b.x() - a.x()); }
  double headingIn(std::size_t t) const {  // arriving at the end node
    const auto& p = road(t).centerline.points();
    return fwd(t) ? heading(p[p.size() - 2], p.back()) : heading(p[1], p[0]);
  }
  double headingOut(std::size_t t) const {  // leaving the start node
    const auto& p = road(t).centerline.points();
    return fwd(t) ? heading(p[0], p[1]) : heading(p.back(), p[p.size() - 2]);
  }
  double angle(std::size_t t, std::size_t u) const {
    double a = std::fmod(headingOut(u) - headingIn(t), 2 * kPi);
    if (a > kPi) a -= 2 * kPi;
    if (a <= -kPi) a += 2 * kPi;
    return a;
  }
  double turn(std::size_t t, std::size_t u) const {
    if (t / 2 == u / 2 && t != u) return options.u_turn_penalty_m;
    return std::abs(angle(t, u)) / (kPi / 2) * options.turn_penalty_m_per_90deg;
  }

  // The expected legs as text ("drive R3 12.345678" and "turn N4 R3"), the cost and the length.
  struct Answer {
    double cost = kInf, length = 0;
    std::vector<std::string> legs;
  };
  static std::string drive(const std::string& road, double meters) {
    char text[80];
    std::snprintf(text, sizeof text, "drive %s %.6f", road.c_str(), meters);
    return text;
  }

  Answer solve(const RoadPosition& from, const RoadPosition& to) const {
    const Road& sr = map.road(from.road);
    const Road& gr = map.road(to.road);
    const std::size_t si = static_cast<std::size_t>(&sr - map.roads().data());
    const std::size_t gi = static_cast<std::size_t>(&gr - map.roads().data());
    const double s0 = from.node == sr.from ? from.meters : sr.centerline.length() - from.meters;
    const double s1 = to.node == gr.from ? to.meters : gr.centerline.length() - to.meters;
    const std::size_t n = 2 * map.roads().size();
    std::vector<double> dist(n, kInf);
    std::vector<std::size_t> pred(n, n);
    for (const std::size_t t : {2 * si, 2 * si + 1}) {
      if (drivable(t)) dist[t] = (fwd(t) ? length(t) - s0 : s0) * sr.cost_factor;
    }
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t t = 0; t < n; ++t) {
        if (dist[t] == kInf) continue;
        for (std::size_t u = 0; u < n; ++u) {
          if (!drivable(u) || startNode(u) != endNode(t)) continue;
          const double d = dist[t] + turn(t, u) + length(u) * road(u).cost_factor;
          if (d < dist[u] - 1e-12) {
            dist[u] = d;
            pred[u] = t;
            changed = true;
          }
        }
      }
    }
    Answer best;
    if (si == gi && (s1 >= s0 || !sr.oneway)) {
      best.cost = std::abs(s1 - s0) * sr.cost_factor;
      best.length = std::abs(s1 - s0);
      best.legs = {drive(sr.id, best.length)};
    }
    for (std::size_t t = 0; t < n; ++t) {
      for (const std::size_t onto : {2 * gi, 2 * gi + 1}) {
        if (dist[t] == kInf || !drivable(onto) || startNode(onto) != endNode(t)) continue;
        const double last = fwd(onto) ? s1 : length(onto) - s1;
        const double cost = dist[t] + turn(t, onto) + last * gr.cost_factor;
        if (!(cost < best.cost)) continue;
        best.cost = cost;
        std::vector<std::size_t> chain;
        for (std::size_t v = t; v != n; v = pred[v]) chain.insert(chain.begin(), v);
        const double first = fwd(chain[0]) ? length(chain[0]) - s0 : s0;
        best.legs = {drive(sr.id, first)};
        best.length = first + last;
        chain.push_back(onto);
        for (std::size_t i = 1; i < chain.size(); ++i) {
          best.legs.push_back("turn " + endNode(chain[i - 1]) + " " + road(chain[i]).id);
          const double meters = i + 1 < chain.size() ? length(chain[i]) : last;
          best.legs.push_back(drive(road(chain[i]).id, meters));
          best.length += i + 1 < chain.size() ? meters : 0.0;
        }
      }
    }
    return best;
  }
};

std::vector<std::string> legTexts(const Route& route) {
  std::vector<std::string> out;
  for (const Leg& leg : route.legs) {
    out.push_back(leg.action == LegAction::Drive ? BruteForce::drive(leg.road, leg.meters) : "turn " + leg.at + " " + leg.road);
  }
  return out;
}

TEST(LoopRoads, RoutesMatchABruteForceShortestPathInBothDirections) {
  int queries = 0, on_loops = 0, through_loops = 0;
  for (std::uint32_t seed = 1; seed <= 12; ++seed) {
    const Map map = loopMap(seed);
    RoadGraph graph(map);
    std::vector<const Road*> loops;
    for (const Road& r : map.roads()) {
      if (r.from == r.to) loops.push_back(&r);
    }
    ASSERT_GE(loops.size(), 3U) << "seed " << seed;
    std::mt19937 rng(100 + seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    auto position = [&](bool on_loop) {
      const Road& r = on_loop ? *loops[rng() % loops.size()] : map.roads()[rng() % map.roads().size()];
      return RoadPosition{r.id, unit(rng) < 0.5 ? r.from : r.to, unit(rng) * r.centerline.length()};
    };
    for (int pair = 0; pair < 20; ++pair) {
      const RoadPosition a = position(pair % 4 != 3), b = position(pair % 2 == 0);
      RouteOptions options;
      options.turn_penalty_m_per_90deg = 10 * unit(rng);
      options.u_turn_penalty_m = 60 * unit(rng);
      const BruteForce reference{map, options};
      for (const auto& [from, to] : {std::pair(a, b), std::pair(b, a)}) {
        const BruteForce::Answer want = reference.solve(from, to);
        for (const bool astar : {true, false}) {
          options.use_astar = astar;
          const RouteResult got = graph.route(from, to, options);
          const std::string what = toString(from) + " -> " + toString(to) + (astar ? " (A*)" : " (Dijkstra)");
          ASSERT_EQ(got.route.has_value(), want.cost < kInf) << what << ": " << got.reason;
          ++queries;
          if (!got.route) continue;
          EXPECT_NEAR(got.route->cost, want.cost, 1e-6) << what;
          EXPECT_NEAR(got.route->length_m, want.length, 1e-6) << what;
          EXPECT_NEAR(got.route->line.length(), want.length, 1e-6) << what;
          EXPECT_EQ(legTexts(*got.route), want.legs) << what;
          for (const std::string& r : got.route->roads) through_loops += map.road(r).from == map.road(r).to;
          on_loops += map.road(from.road).from == map.road(from.road).to || map.road(to.road).from == map.road(to.road).to;
        }
      }
    }
  }
  // 12 maps × 20 pairs × 2 directions × 2 searches; most start or end on a loop, many pass one.
  EXPECT_EQ(queries, 960);
  EXPECT_GT(on_loops, 500);
  EXPECT_GT(through_loops, 500);
}

}  // namespace
}  // namespace mapnav
