#include "mapnav/navigator/route.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <unordered_map>

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/astar_search.hpp>
#include <boost/graph/dijkstra_shortest_paths.hpp>
#include <boost/property_map/function_property_map.hpp>

#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/core/options.h"

namespace mapnav {

void RouteOptions::validate() const {
  requireOption(std::isfinite(turn_penalty_m_per_90deg) && turn_penalty_m_per_90deg >= 0, "RouteOptions",
                "turn_penalty_m_per_90deg", turn_penalty_m_per_90deg, "finite and >= 0");
  requireOption(std::isfinite(u_turn_penalty_m) && u_turn_penalty_m >= 0, "RouteOptions", "u_turn_penalty_m",
                u_turn_penalty_m, "finite and >= 0");
}

std::string turnDirection(double angle) {
  if (std::abs(angle) <= degToRad(15)) return "straight";
  return angle > 0 ? "left" : "right";
}

namespace {

// What an edge costs, before the query's options: driving `meters` (x cost factor) of `road`
// after turning by `angle` at intersection `node` (none for the start's edges).
struct Step {
  double meters = 0;
  double angle = 0;
  bool u_turn = false;
  std::size_t road = 0;
  std::size_t node = SIZE_MAX;
};
using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::directedS, boost::no_property, Step>;
using Vertex = Graph::vertex_descriptor;
using Edge = Graph::edge_descriptor;

// A vertex of the search graph is a directed traversal of a road: having driven road `road` in
// direction `forward` (from → to) or backward, the vehicle is at the traversal's end node. Turn
// costs then sit on the edges between traversals.
struct Traversal {
  std::size_t road = 0;
  bool forward = true;
};

struct Found {};  // thrown by the A* visitor when the goal is taken off the queue

// A query's start and goal: their roads (indices) and arc lengths from the roads' `from` ends.
struct RouteEnds {
  std::size_t sr = 0, gr = 0;
  double s_start = 0, s_goal = 0;
};

// The roads and intersections (indices) a query may not use.
struct Blocks {
  std::vector<bool> road, node;
};

// The edges one query adds (S's, and those into G), removed when the query ends, whatever happens,
// so that the next one starts from the graph as it was built.
struct QueryEdges {
  Graph& graph;
  Vertex S, G;
  std::vector<Vertex> into_goal;
  QueryEdges(Graph& g, Vertex s, Vertex goal) : graph(g), S(s), G(goal) {}
  QueryEdges(const QueryEdges&) = delete;
  QueryEdges& operator=(const QueryEdges&) = delete;
  ~QueryEdges() {
    boost::clear_out_edges(S, graph);
    for (Vertex v : into_goal) boost::remove_edge(v, G, graph);
  }
};

// The search's result: per vertex its predecessor (itself when unreached) and its distance.
struct SearchResult {
  std::vector<Vertex> pred;
  std::vector<double> dist;
};

}  // namespace

struct RoadGraph::Impl {
  const Map& map;
  Graph graph;                                        // traversals 0..2R-1, then S = 2R, G = 2R + 1
  std::vector<Traversal> traversals;                  // per traversal vertex
  std::vector<Vec2> end_position;                     // per traversal vertex: where it ends (heuristic)
  std::unordered_map<std::string, std::size_t> road_index;
  std::vector<std::vector<Vertex>> arriving;          // per intersection: traversals ending there
  double min_cost_factor = 1.0;

  explicit Impl(const Map& m) : map(m), graph(2 * m.roads().size() + 2) {
    const auto& roads = map.roads();
    for (std::size_t r = 0; r < roads.size(); ++r) {
      road_index.emplace(roads[r].id, r);
      min_cost_factor = std::min(min_cost_factor, roads[r].cost_factor);
    }
    // Two traversals per road: vertex 2r forward, 2r + 1 backward (a one-way road's backward
    // traversal gets no edges). Turn costs and blocking are query options, applied by the weight
    // map, so the graph is built once.
    arriving.resize(map.intersections().size());
    std::vector<std::vector<Vertex>> leaving(map.intersections().size());
    for (std::size_t r = 0; r < roads.size(); ++r) {
      for (const bool forward : {true, false}) {
        const Vertex v = traversals.size();
        traversals.push_back({r, forward});
        end_position.push_back(map.intersection(forward ? roads[r].to : roads[r].from).position);
        if (!forward && roads[r].oneway) continue;
        arriving[node(endNode(traversals[v]))].push_back(v);
        leaving[node(startNode(traversals[v]))].push_back(v);
      }
    }
    for (std::size_t n = 0; n < arriving.size(); ++n) {
      for (Vertex v : arriving[n]) {
        const Traversal& in = traversals[v];
        for (Vertex w : leaving[n]) {
          const Traversal& out = traversals[w];
          boost::add_edge(v, w, Step{length(out.road), normalizeAngle(headingOut(out) - headingIn(in)),
                                     out.road == in.road && out.forward != in.forward, out.road, n}, graph);
        }
      }
    }
  }

  Vertex start() const { return traversals.size(); }
  Vertex goal() const { return traversals.size() + 1; }
  std::size_t node(const std::string& id) const {
    return static_cast<std::size_t>(map.findIntersection(id) - map.intersections().data());
  }
  const Road& road(std::size_t r) const { return map.roads()[r]; }
  std::string endNode(const Traversal& t) const { return t.forward ? road(t.road).to : road(t.road).from; }
  std::string startNode(const Traversal& t) const { return t.forward ? road(t.road).from : road(t.road).to; }
  double length(std::size_t r) const { return road(r).centerline.length(); }
  // Heading arriving at the end node, and leaving the start node, of a traversal.
  double headingIn(const Traversal& t) const {
    const Polyline2& c = road(t.road).centerline;
    return t.forward ? c.headingAt(c.length()) : normalizeAngle(c.headingAt(0) + kPi);
  }
  double headingOut(const Traversal& t) const {
    const Polyline2& c = road(t.road).centerline;
    return t.forward ? c.headingAt(0) : normalizeAngle(c.headingAt(c.length()) + kPi);
  }
  double turnCost(double angle, bool u_turn, const RouteOptions& o) const {
    return u_turn ? o.u_turn_penalty_m : std::abs(angle) / (kPi / 2) * o.turn_penalty_m_per_90deg;
  }

  // One query's steps (RoadGraph::route).
  Blocks blocks(const std::set<std::string>& blocked) const;
  bool usable(const Traversal& t, const Blocks& b) const {
    return !b.road[t.road] && (t.forward || !road(t.road).oneway);
  }
  void connect(const RouteEnds& e, const Blocks& b, QueryEdges& edges);
  SearchResult search(const RouteEnds& e, const Blocks& b, const RouteOptions& options);
  Route routeAlong(const SearchResult& found, const RouteEnds& e, const Blocks& b, const RoadPosition& from,
                   const RoadPosition& to) const;
};

RoadGraph::RoadGraph(const Map& map) : impl_(std::make_unique<Impl>(map)) {}
RoadGraph::~RoadGraph() = default;
RoadGraph::RoadGraph(RoadGraph&&) noexcept = default;
RoadGraph& RoadGraph::operator=(RoadGraph&&) noexcept = default;
const Map& RoadGraph::map() const { return impl_->map; }
std::size_t RoadGraph::vertexCount() const { return impl_->traversals.size(); }

namespace {

// Where a road position is on its road: arc length from the road's `from` end.
double arcFromStart(const Road& road, const RoadPosition& p) {
  const double len = road.centerline.length();
  if (p.node != road.from && p.node != road.to) {
    throw InvalidInput("road position " + toString(p) + ": " + p.node + " is not an end of " + road.id);
  }
  if (!(p.meters >= 0) || p.meters > len) {
    char text[96];
    std::snprintf(text, sizeof text, ": %g m is beyond the road's %.2f m", p.meters, len);
    throw InvalidInput("road position " + toString(p) + text);
  }
  return p.node == road.from ? p.meters : len - p.meters;
}

// The ids of `blocked`, each checked to name a road or an intersection (NotFound otherwise).
std::set<std::string> blockedIds(const Map& map, const std::vector<std::string>& ids) {
  std::set<std::string> blocked;
  for (const std::string& id : ids) {
    if (map.findRoad(id) == nullptr && map.findIntersection(id) == nullptr) {
      throw NotFound("--block " + id + ": no road or intersection has this id");
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

Blocks RoadGraph::Impl::blocks(const std::set<std::string>& blocked) const {
  Blocks b{std::vector<bool>(map.roads().size(), false), std::vector<bool>(map.intersections().size(), false)};
  for (const std::string& id : blocked) {
    if (const Road* r = map.findRoad(id)) b.road[road_index.at(r->id)] = true;
    if (map.findIntersection(id) != nullptr) b.node[node(id)] = true;
  }
  return b;
}

// S and G split their roads: S's edges drive the rest of the start road, the edges into G turn onto
// the goal road and drive to the goal.
void RoadGraph::Impl::connect(const RouteEnds& e, const Blocks& b, QueryEdges& edges) {
  const Vertex S = start(), G = goal();
  const double start_len = length(e.sr), goal_len = length(e.gr);
  // S → traversals of the start road, driving the rest of it (either way: the vehicle may set off
  // in either direction).
  for (const bool forward : {true, false}) {
    const Vertex v = 2 * e.sr + (forward ? 0 : 1);
    if (!usable(traversals[v], b)) continue;
    boost::add_edge(S, v, Step{forward ? start_len - e.s_start : e.s_start, 0.0, false, e.sr, SIZE_MAX}, graph);
  }
  // Traversals arriving at an end of the goal road → G, turning onto it and driving to the goal.
  for (const bool forward : {true, false}) {
    const Traversal onto{e.gr, forward};  // driving the goal road in this direction reaches G
    if (!usable(onto, b)) continue;
    const std::size_t n = node(startNode(onto));
    for (Vertex v : arriving[n]) {
      const Traversal& in = traversals[v];
      boost::add_edge(v, G,
                      Step{forward ? e.s_goal : goal_len - e.s_goal, normalizeAngle(headingOut(onto) - headingIn(in)),
                           in.road == e.gr && in.forward != forward, e.gr, n},
                      graph);
      edges.into_goal.push_back(v);
    }
  }
  // Start and goal on the same road: straight there, if the road may be driven that way.
  if (e.sr == e.gr && usable(Traversal{e.sr, e.s_goal >= e.s_start}, b)) {
    boost::add_edge(S, G, Step{std::abs(e.s_goal - e.s_start), 0.0, false, e.sr, SIZE_MAX}, graph);
  }
}

// A* (or Dijkstra) from S to G; blocked parts cost "infinity".
SearchResult RoadGraph::Impl::search(const RouteEnds& e, const Blocks& b, const RouteOptions& options) {
  const Vertex S = start(), G = goal();
  constexpr double kBlocked = std::numeric_limits<double>::max();  // Boost's "infinity"
  auto weight = boost::make_function_property_map<Edge, double>([&](const Edge& edge) {
    const Step& step = graph[edge];
    if (b.road[step.road] || (step.node != SIZE_MAX && b.node[step.node])) return kBlocked;
    const double turn = step.node == SIZE_MAX ? 0.0 : turnCost(step.angle, step.u_turn, options);
    return step.meters * road(step.road).cost_factor + turn;
  });
  const std::size_t n = boost::num_vertices(graph);
  SearchResult found{std::vector<Vertex>(n), std::vector<double>(n, std::numeric_limits<double>::infinity())};
  std::vector<Vertex>& pred = found.pred;
  std::vector<double>& dist = found.dist;
  const Vec2 goal_point = road(e.gr).centerline.pointAt(e.s_goal);
  if (options.use_astar) {
    // Euclidean distance to the goal never exceeds the remaining cost when scaled by the
    // smallest cost factor, so A* stays exact.
    auto heuristic = [&](Vertex v) {
      if (v == G) return 0.0;
      const Vec2 p = v == S ? road(e.sr).centerline.pointAt(e.s_start) : end_position[v];
      return (p - goal_point).norm() * min_cost_factor;
    };
    struct Visitor : boost::default_astar_visitor {
      Vertex goal;
      explicit Visitor(Vertex gv) : goal(gv) {}
      void examine_vertex(Vertex v, const Graph&) {
        if (v == goal) throw Found{};
      }
    };
    std::vector<double> rank(n);
    std::vector<boost::default_color_type> color(n);
    const auto index = boost::get(boost::vertex_index, graph);
    try {
      boost::astar_search(graph, S, heuristic,
                          boost::weight_map(weight)
                              .predecessor_map(boost::make_iterator_property_map(pred.begin(), index))
                              .distance_map(boost::make_iterator_property_map(dist.begin(), index))
                              .rank_map(boost::make_iterator_property_map(rank.begin(), index))
                              .color_map(boost::make_iterator_property_map(color.begin(), index))
                              .visitor(Visitor(G)));
    } catch (const Found&) {
    }
  } else {
    boost::dijkstra_shortest_paths(graph, S,
                                   boost::weight_map(weight).predecessor_map(boost::make_iterator_property_map(pred.begin(), boost::get(boost::vertex_index, graph)))
                                       .distance_map(boost::make_iterator_property_map(dist.begin(), boost::get(boost::vertex_index, graph))));
  }
  return found;
}

// The route the search found: vertices S, traversals..., G, turned into legs and the centre line.
Route RoadGraph::Impl::routeAlong(const SearchResult& found, const RouteEnds& e, const Blocks& b,
                                  const RoadPosition& from, const RoadPosition& to) const {
  const Vertex S = start(), G = goal();
  const Road& start_road = road(e.sr);
  const Road& goal_road = road(e.gr);
  std::vector<Vertex> chain;
  for (Vertex v = G; v != S; v = found.pred[v]) chain.push_back(v);
  std::reverse(chain.begin(), chain.end());  // traversals..., G
  Route route;
  route.from = from;
  route.to = to;
  route.cost = found.dist[G];
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
  auto addTurn = [&](const std::string& node, double angle, const std::string& onto) {
    route.intersections.push_back(node);
    route.legs.push_back(Leg{LegAction::Turn, onto, 0.0, node, angle});
  };
  if (chain.size() == 1) {  // S → G on one road
    addPiece(start_road, e.s_start, e.s_goal);
  } else {
    const Traversal first = traversals[chain.front()];
    addPiece(start_road, e.s_start, first.forward ? length(e.sr) : 0.0);
    for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
      const Traversal in = traversals[chain[i]];
      if (chain[i + 1] == G) {
        // The goal road is entered at the end the last traversal arrives at: from its `from` end
        // it is driven forward (a loop road, from == to, is entered forward when it may be).
        const bool forward = endNode(in) == goal_road.from && usable(Traversal{e.gr, true}, b);
        const Traversal onto{e.gr, forward};
        addTurn(endNode(in), normalizeAngle(headingOut(onto) - headingIn(in)), goal_road.id);
        addPiece(goal_road, forward ? 0.0 : length(e.gr), e.s_goal);
      } else {
        const Traversal out = traversals[chain[i + 1]];
        addTurn(endNode(in), normalizeAngle(headingOut(out) - headingIn(in)), road(out.road).id);
        const double len = length(out.road);
        addPiece(road(out.road), out.forward ? 0.0 : len, out.forward ? len : 0.0);
      }
    }
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
  const RouteEnds ends{g.road_index.at(start_road.id), g.road_index.at(goal_road.id), arcFromStart(start_road, from),
                       arcFromStart(goal_road, to)};
  const std::set<std::string> blocked = blockedIds(map, options.blocked);
  RouteResult result;
  if (auto why = noRouteWithoutSearch(map, from, to, blocked)) {
    result.reason = std::move(*why);
    return result;
  }
  const Blocks blocks = g.blocks(blocked);
  QueryEdges edges(g.graph, g.start(), g.goal());
  g.connect(ends, blocks, edges);
  const SearchResult found = g.search(ends, blocks, options);
  // Both searches start every predecessor at the vertex itself (and every distance at DBL_MAX,
  // which is finite), so an unreached goal is one that is still its own predecessor.
  if (found.pred[g.goal()] == g.goal()) {
    result.reason = blocked.empty()
                        ? "no route from " + toString(from) + " to " + toString(to) + " respects the one-way roads"
                        : "every route from " + toString(from) + " to " + toString(to) +
                              " passes a blocked road or intersection";
    return result;
  }
  result.route = g.routeAlong(found, ends, blocks, from, to);
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
