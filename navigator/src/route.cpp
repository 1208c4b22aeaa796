#include "mapnav/navigator/route.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "route_network.h"

namespace mapnav {

const OptionTable<RouteOptions>& routeOptionTable() {
  using O = RouteOptions;
  static const OptionTable<O> table =
      OptionTable<O>("RouteOptions")
          .field("turn_penalty_m_per_90deg", &O::turn_penalty_m_per_90deg, atLeast(0),
                 "cost of turning, metres of driving per 90 degrees of turn")
          .field("u_turn_penalty_m", &O::u_turn_penalty_m, atLeast(0),
                 "cost of turning back along the road just driven, at an intersection, m")
          .field("use_astar", &O::use_astar, "bidirectional A* with landmark bounds (ALT); false: Dijkstra");
  return table;
}

void RouteOptions::validate() const { routeOptionTable().validate(*this); }

std::string turnDirection(double angle) {
  if (std::abs(angle) <= degToRad(15)) return "straight";
  if (std::abs(angle) >= degToRad(165)) return "around";
  return angle > 0 ? "left" : "right";
}

namespace {

using route_detail::Index;

// How many landmarks the A* lower bounds use. Farthest-point selection takes the corners of a
// grid first (which alone make its bounds exact without turns), then points along the edges; 8
// cost 2 × 8 Dijkstra runs once and 128 bytes per intersection. 16 did not speed up queries on an
// irregular 100k map (median 19 ms against 15 ms with 8, the machine shared).
constexpr int kLandmarks = 8;

// A query's start and goal: their roads (indices) and arc lengths from the roads' `from` ends.
struct RouteEnds {
  Index sr = 0, gr = 0;
  double s_start = 0, s_goal = 0;
};

// Unsets a query's block marks when the query ends, whatever happens.
struct ClearBlocks {
  route_detail::BlockMarks& marks;
  ~ClearBlocks() { marks.clear(); }
};

}  // namespace

struct RoadGraph::Impl {
  const Map& map;
  route_detail::Network network;
  route_detail::BlockMarks blocks;
  std::optional<route_detail::Landmarks> landmarks;  // computed by the first A* query
  route_detail::BidirectionalSearch search;

  explicit Impl(const Map& m) : map(m) {
    std::vector<double> in(2 * map.roads().size()), out(in.size());
    for (Index v = 0; v < in.size(); ++v) {
      in[v] = headingIn(v);
      out[v] = headingOut(v);
    }
    network = route_detail::Network::build(map, in, out);
    blocks.road.assign(map.roads().size(), 0);
    blocks.node.assign(map.intersections().size(), 0);
  }

  Index node(const std::string& id) const {
    return static_cast<Index>(map.findIntersection(id) - map.intersections().data());
  }
  Index roadIndex(const std::string& id) const { return static_cast<Index>(map.findRoad(id) - map.roads().data()); }
  const Road& road(Index r) const { return map.roads()[r]; }
  // Traversal v drives road v / 2, forward (from → to) when v is even.
  static bool forward(Index v) { return (v & 1U) == 0; }
  const std::string& endNode(Index v) const { return forward(v) ? road(v >> 1).to : road(v >> 1).from; }
  double length(Index r) const { return road(r).centerline.length(); }
  // Heading arriving at the end node, and leaving the start node, of a traversal.
  double headingIn(Index v) const {
    const Polyline2& c = road(v >> 1).centerline;
    return forward(v) ? c.headingAt(c.length()) : normalizeAngle(c.headingAt(0) + kPi);
  }
  double headingOut(Index v) const {
    const Polyline2& c = road(v >> 1).centerline;
    return forward(v) ? c.headingAt(0) : normalizeAngle(c.headingAt(c.length()) + kPi);
  }
  double turnAngle(Index in, Index out) const { return normalizeAngle(headingOut(out) - headingIn(in)); }

  // One query's steps (RoadGraph::route).
  void markBlocks(const std::set<std::string>& blocked);
  route_detail::QueryEnds queryEnds(const RouteEnds& e, const route_detail::TurnCosts& turns) const;
  Route routeAlong(const route_detail::Path& path, const route_detail::QueryEnds& q, const RouteEnds& e,
                   const RoadPosition& from, const RoadPosition& to) const;
};

RoadGraph::RoadGraph(const Map& map) : impl_(std::make_unique<Impl>(map)) {}
RoadGraph::~RoadGraph() = default;
RoadGraph::RoadGraph(RoadGraph&&) noexcept = default;
RoadGraph& RoadGraph::operator=(RoadGraph&&) noexcept = default;
const Map& RoadGraph::map() const { return impl_->map; }
std::size_t RoadGraph::vertexCount() const { return impl_->network.traversals(); }

namespace {

// The ids of `blocked`, each checked to name a road or an intersection (NotFound otherwise).
std::set<std::string> blockedIds(const Map& map, const std::vector<std::string>& ids) {
  std::set<std::string> blocked;
  for (const std::string& id : ids) {
    if (map.findRoad(id) == nullptr && map.findIntersection(id) == nullptr) {
      throw NotFound("blocked \"" + id + "\": no road or intersection has this id");
    }
    blocked.insert(id);
  }
  return blocked;
}

// Why there is no route, when that is known without a search: the start or goal road is blocked,
// or the two are in different parts of the network.
std::optional<std::string> noRouteWithoutSearch(const Map& map, const RoadPosition& from, const RoadPosition& to,
                                                const std::set<std::string>& blocked) {
  for (const RoadPosition* p : {&from, &to}) {
    if (blocked.contains(p->road)) {
      return std::string(p == &from ? "the start" : "the goal") + " road " + p->road + " is blocked";
    }
  }
  const auto& components = map.components();
  auto componentOf = [&](const std::string& node) {
    const std::size_t index = static_cast<std::size_t>(map.findIntersection(node) - map.intersections().data());
    for (std::size_t c = 0; c < components.size(); ++c) {
      if (std::binary_search(components[c].begin(), components[c].end(), index)) return c;
    }
    return components.size();
  };
  if (componentOf(map.road(from.road).from) != componentOf(map.road(to.road).from)) {
    return "no road connects " + from.road + " to " + to.road + ": they are in different parts of the network";
  }
  return std::nullopt;
}

}  // namespace

void RoadGraph::Impl::markBlocks(const std::set<std::string>& blocked) {
  std::vector<Index> roads, nodes;
  for (const std::string& id : blocked) {
    if (map.findRoad(id) != nullptr) roads.push_back(roadIndex(id));
    if (map.findIntersection(id) != nullptr) nodes.push_back(node(id));
  }
  blocks.set(roads, nodes);
}

// The start's edges drive the rest of the start road (either way: the vehicle may set off in
// either direction); the goal's edges turn onto the goal road and drive to the goal.
route_detail::QueryEnds RoadGraph::Impl::queryEnds(const RouteEnds& e, const route_detail::TurnCosts& turns) const {
  route_detail::QueryEnds q;
  const double start_factor = road(e.sr).cost_factor, goal_factor = road(e.gr).cost_factor;
  for (const bool fwd : {true, false}) {
    const Index v = 2 * e.sr + (fwd ? 0 : 1);
    if (!network.usable(v, blocks)) continue;
    const double meters = fwd ? length(e.sr) - e.s_start : e.s_start;
    q.sources.push_back({v, meters * start_factor, meters * start_factor, fwd});
  }
  for (const bool fwd : {true, false}) {
    const Index onto = 2 * e.gr + (fwd ? 0 : 1);  // driving the goal road this way reaches the goal
    if (!network.usable(onto, blocks)) continue;
    const Index n = network.end_node[onto ^ 1U];  // where it is entered
    if (blocks.node[n] != 0) continue;
    const double drive = (fwd ? e.s_goal : length(e.gr) - e.s_goal) * goal_factor;
    for (Index i = network.arriving_begin[n]; i < network.arriving_begin[n + 1]; ++i) {
      const Index v = network.arriving[i];
      if (!network.usable(v, blocks)) continue;
      const double turn = route_detail::turnCost(std::abs(turnAngle(v, onto)), v == (onto ^ 1U), turns);
      q.targets.push_back({v, drive + turn, drive, fwd});
    }
  }
  // Start and goal on the same road: straight there, if the road may be driven that way.
  if (e.sr == e.gr && network.usable(2 * e.sr + (e.s_goal >= e.s_start ? 0 : 1), blocks)) {
    q.direct = std::abs(e.s_goal - e.s_start) * start_factor;
  }
  return q;
}

// The route the search found, turned into legs and the centre line.
Route RoadGraph::Impl::routeAlong(const route_detail::Path& path, const route_detail::QueryEnds& q, const RouteEnds& e,
                                  const RoadPosition& from, const RoadPosition& to) const {
  const Road& start_road = road(e.sr);
  const Road& goal_road = road(e.gr);
  const std::vector<Index>& chain = path.traversals;
  Route route;
  route.from = from;
  route.to = to;
  route.cost = path.cost;
  std::vector<Vec2> line;
  auto addPiece = [&](const Road& road, double s0, double s1) {  // drive along road from arc s0 to s1
    const Polyline2 piece = road.centerline.slice(std::min(s0, s1), std::max(s0, s1));
    std::vector<Vec2> pts = piece.points();
    if (s1 < s0) std::reverse(pts.begin(), pts.end());
    for (const Vec2& p : pts) {
      if (line.empty() || (line.back() - p).norm() > 1e-9) line.push_back(p);
    }
    const double meters = std::abs(s1 - s0);
    route.length_m += meters;
    if (route.roads.empty() || route.roads.back() != road.id) route.roads.push_back(road.id);
    route.legs.push_back(Leg{LegAction::Drive, road.id, meters, "", 0.0});
  };
  auto addTurn = [&](Index in, Index out) {
    route.intersections.push_back(endNode(in));
    route.legs.push_back(Leg{LegAction::Turn, road(out >> 1).id, 0.0, endNode(in), turnAngle(in, out)});
  };
  if (chain.empty()) {  // along one road
    addPiece(start_road, e.s_start, e.s_goal);
  } else {
    addPiece(start_road, e.s_start, forward(chain.front()) ? length(e.sr) : 0.0);
    for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
      const Index out = chain[i + 1];
      addTurn(chain[i], out);
      const double len = length(out >> 1);
      addPiece(road(out >> 1), forward(out) ? 0.0 : len, forward(out) ? len : 0.0);
    }
    const bool onto_forward = q.targets[path.target].forward;
    addTurn(chain.back(), 2 * e.gr + (onto_forward ? 0 : 1));
    addPiece(goal_road, onto_forward ? 0.0 : length(e.gr), e.s_goal);
  }
  route.line = Polyline2(std::move(line));
  return route;
}

RouteResult RoadGraph::route(const RoadPosition& from, const RoadPosition& to, const RouteOptions& options) {
  options.validate();
  Impl& g = *impl_;
  const Map& map = g.map;
  const Road& start_road = map.road(from.road);
  const Road& goal_road = map.road(to.road);
  const RouteEnds ends{g.roadIndex(start_road.id), g.roadIndex(goal_road.id), arcFromStart(start_road, from),
                       arcFromStart(goal_road, to)};
  const std::set<std::string> blocked = blockedIds(map, options.blocked);
  RouteResult result;
  if (auto why = noRouteWithoutSearch(map, from, to, blocked)) {
    result.reason = std::move(*why);
    return result;
  }
  g.markBlocks(blocked);
  const ClearBlocks clear{g.blocks};
  const route_detail::TurnCosts turns{options.turn_penalty_m_per_90deg, options.u_turn_penalty_m};
  const route_detail::QueryEnds q = g.queryEnds(ends, turns);
  route_detail::Path path;
  if (options.use_astar) {
    if (!g.landmarks) g.landmarks = route_detail::chooseLandmarks(g.network, kLandmarks);
    path = g.search.run(g.network, *g.landmarks, q, g.blocks, turns);
  } else {
    path = route_detail::dijkstraPath(g.network, q, g.blocks, turns);
  }
  if (!path.found) {
    result.reason = blocked.empty()
                        ? "no route from " + toString(from) + " to " + toString(to) + " respects the one-way roads"
                        : "every route from " + toString(from) + " to " + toString(to) +
                              " passes a blocked road or intersection";
    return result;
  }
  result.route = g.routeAlong(path, q, ends, from, to);
  return result;
}

std::string toDialogue(const Route& route) {
  std::string text;
  char buffer[200];
  for (std::size_t i = 0; i < route.legs.size(); ++i) {
    const Leg& leg = route.legs[i];
    if (leg.action == LegAction::Drive) {
      std::snprintf(buffer, sizeof buffer, "Drive on %s %.1f m", leg.road.c_str(), leg.meters);
      text += buffer;
      text += i + 1 < route.legs.size() ? " and " : ".\n";
    } else {
      const std::string direction = turnDirection(leg.angle);
      if (direction == "straight") {
        std::snprintf(buffer, sizeof buffer, "go straight through %s onto %s.\n", leg.at.c_str(), leg.road.c_str());
      } else if (direction == "around") {  // the skid-steer vehicle turns on its tracks
        std::snprintf(buffer, sizeof buffer, "turn around in place at %s onto %s.\n", leg.at.c_str(), leg.road.c_str());
      } else {
        std::snprintf(buffer, sizeof buffer, "turn %s %.0f degrees at %s onto %s.\n", direction.c_str(),
                      std::abs(radToDeg(leg.angle)), leg.at.c_str(), leg.road.c_str());
      }
      text += buffer;
    }
  }
  return text;
}

std::string toJson(const Route& route) {
  Json legs = Json::array();
  for (const Leg& leg : route.legs) {
    if (leg.action == LegAction::Drive) {
      legs.push_back({{"action", "drive"}, {"road", leg.road}, {"meters", std::round(leg.meters * 1000) / 1000}});
    } else {
      legs.push_back({{"action", "turn"},
                      {"at", leg.at},
                      {"direction", turnDirection(leg.angle)},
                      {"degrees", std::round(std::abs(radToDeg(leg.angle)) * 10) / 10},
                      {"onto", leg.road}});
    }
  }
  Json j = {{"from", toString(route.from)},
            {"to", toString(route.to)},
            {"length_m", std::round(route.length_m * 1000) / 1000},
            {"cost", std::round(route.cost * 1000) / 1000},
            {"legs", legs}};
  return dumpJson(j);
}

}  // namespace mapnav
