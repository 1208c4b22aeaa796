#include "route_network.h"

#include <algorithm>
#include <cmath>

#include <boost/graph/dijkstra_shortest_paths.hpp>
#include <boost/property_map/function_property_map.hpp>

#include "mapnav/geometry/types.h"

namespace mapnav::route_detail {

void BlockMarks::set(const std::vector<Index>& roads, const std::vector<Index>& nodes) {
  clear();
  for (Index r : roads) road[r] = 1;
  for (Index n : nodes) node[n] = 1;
  set_roads = roads;
  set_nodes = nodes;
}

void BlockMarks::clear() {
  for (Index r : set_roads) road[r] = 0;
  for (Index n : set_nodes) node[n] = 0;
  set_roads.clear();
  set_nodes.clear();
}

double turnCost(double abs_angle, bool u_turn, const TurnCosts& turns) {
  return u_turn ? turns.u_turn : abs_angle / (kPi / 2) * turns.per_90deg;
}

std::size_t Network::bytes() const {
  const std::size_t v = traversals(), e = boost::num_edges(graph);
  // Compressed sparse rows both ways: row starts, targets (sources) and, backward, edge indices.
  const std::size_t csr = 2 * (v + 1) * sizeof(Index) + e * (2 * sizeof(Index) + sizeof(Index) + sizeof(Turn));
  return csr + v * (sizeof(double) + sizeof(Index) + 1) + (arriving_begin.size() + arriving.size()) * sizeof(Index);
}

Network Network::build(const Map& map, const std::vector<double>& heading_in, const std::vector<double>& heading_out) {
  const auto& roads = map.roads();
  const auto& nodes = map.intersections();
  Network n;
  n.intersections = nodes.size();
  const std::size_t count = 2 * roads.size();
  n.drive_cost.resize(count);
  n.end_node.resize(count);
  n.drivable.resize(count);
  std::vector<Index> start_node(count);
  auto nodeIndex = [&](const std::string& id) { return static_cast<Index>(map.findIntersection(id) - nodes.data()); };
  std::vector<Index> arriving_count(nodes.size() + 1, 0), leaving_begin(nodes.size() + 1, 0);
  for (std::size_t r = 0; r < roads.size(); ++r) {
    const Index from = nodeIndex(roads[r].from), to = nodeIndex(roads[r].to);
    const double cost = roads[r].centerline.length() * roads[r].cost_factor;
    for (const bool forward : {true, false}) {
      const Index v = static_cast<Index>(2 * r + (forward ? 0 : 1));
      n.drive_cost[v] = cost;
      n.end_node[v] = forward ? to : from;
      start_node[v] = forward ? from : to;
      n.drivable[v] = forward || !roads[r].oneway;
      if (!n.drivable[v]) continue;
      ++arriving_count[n.end_node[v] + 1];
      ++leaving_begin[start_node[v] + 1];
    }
  }
  for (std::size_t i = 1; i <= nodes.size(); ++i) {
    arriving_count[i] += arriving_count[i - 1];
    leaving_begin[i] += leaving_begin[i - 1];
  }
  n.arriving_begin = arriving_count;
  n.arriving.resize(arriving_count.back());
  std::vector<Index> leaving(leaving_begin.back());
  std::vector<Index> fill_a(arriving_count.begin(), arriving_count.end() - 1), fill_l(leaving_begin.begin(), leaving_begin.end() - 1);
  for (Index v = 0; v < count; ++v) {
    if (!n.drivable[v]) continue;
    n.arriving[fill_a[n.end_node[v]]++] = v;
    leaving[fill_l[start_node[v]]++] = v;
  }
  std::size_t edge_count = 0;
  for (std::size_t x = 0; x < nodes.size(); ++x) {
    edge_count += static_cast<std::size_t>(arriving_count[x + 1] - arriving_count[x]) * (leaving_begin[x + 1] - leaving_begin[x]);
  }
  std::vector<std::pair<Index, Index>> edges;
  std::vector<Turn> turns;
  edges.reserve(edge_count);
  turns.reserve(edge_count);
  for (Index v = 0; v < count; ++v) {  // by source, so the graph keeps this order of out-edges
    if (!n.drivable[v]) continue;
    const Index x = n.end_node[v];
    for (Index i = leaving_begin[x]; i < leaving_begin[x + 1]; ++i) {
      edges.emplace_back(v, leaving[i]);
      turns.push_back(Turn{std::abs(normalizeAngle(heading_out[leaving[i]] - heading_in[v]))});
    }
  }
  n.graph = TurnGraph(boost::edges_are_unsorted_multi_pass, edges.begin(), edges.end(), turns.begin(), count);
  return n;
}

double Landmarks::bound(Index a, Index b) const {
  double best = 0;
  const double* fa = &from[static_cast<std::size_t>(a) * count];
  const double* fb = &from[static_cast<std::size_t>(b) * count];
  const double* ta = &to[static_cast<std::size_t>(a) * count];
  const double* tb = &to[static_cast<std::size_t>(b) * count];
  for (int i = 0; i < count; ++i) {
    // Triangle inequality: d(L, b) <= d(L, a) + d(a, b) and d(a, L) <= d(a, b) + d(b, L). An
    // infinite difference means b cannot be reached from a; infinity minus infinity (NaN) says
    // nothing and is skipped by the comparisons.
    const double x = fb[i] - fa[i], y = ta[i] - tb[i];
    if (x > best) best = x;
    if (y > best) best = y;
  }
  return best;
}

namespace {

// The graph of intersections: an edge per drivable traversal, start node → end node, costing its drive.
using NodeGraph = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, double,
                                                     boost::no_property, Index, Index>;

NodeGraph nodeGraph(const Network& n, bool reversed) {
  std::vector<std::pair<Index, Index>> edges;
  std::vector<double> costs;
  for (Index v = 0; v < n.traversals(); ++v) {
    if (!n.drivable[v]) continue;
    const Index start = n.end_node[v ^ 1U];  // the other traversal of the road ends where v starts
    edges.emplace_back(reversed ? n.end_node[v] : start, reversed ? start : n.end_node[v]);
    costs.push_back(n.drive_cost[v]);
  }
  return NodeGraph(boost::edges_are_unsorted_multi_pass, edges.begin(), edges.end(), costs.begin(),
                   static_cast<Index>(n.intersections));
}

// Distances from `source` in `g` (+inf where it cannot reach).
std::vector<double> distancesFrom(const NodeGraph& g, Index source) {
  std::vector<double> dist(boost::num_vertices(g));
  const auto index = boost::get(boost::vertex_index, g);
  boost::dijkstra_shortest_paths(g, source,
                                 boost::weight_map(boost::get(boost::edge_bundle, g))
                                     .distance_map(boost::make_iterator_property_map(dist.begin(), index))
                                     .distance_inf(kInfinity));
  return dist;
}

// The intersection with the largest `score` (the first of equals); +inf counts as largest, so
// that a part of the network no landmark reaches gets one.
Index farthest(const std::vector<double>& score) {
  Index best = 0;
  for (Index x = 1; x < score.size(); ++x) {
    if (score[x] > score[best]) best = x;
  }
  return best;
}

}  // namespace

Landmarks chooseLandmarks(const Network& network, int count) {
  Landmarks l;
  const std::size_t n = network.intersections;
  if (n == 0 || count <= 0) return l;
  const NodeGraph forward = nodeGraph(network, false), backward = nodeGraph(network, true);
  // The first landmark: the intersection farthest from intersection 0; each next one the
  // intersection whose round trip to the nearest landmark chosen so far is longest.
  std::vector<double> nearest = distancesFrom(forward, 0);
  for (double& d : nearest) d = std::isfinite(d) ? d : 0.0;  // unreachable from 0: no candidate yet
  std::vector<std::vector<double>> from, to;
  Index next = farthest(nearest);
  std::fill(nearest.begin(), nearest.end(), kInfinity);
  for (int i = 0; i < count; ++i) {
    if (i > 0 && !(nearest[next] > 0)) break;  // every intersection is a landmark already
    l.nodes.push_back(next);
    from.push_back(distancesFrom(forward, next));
    to.push_back(distancesFrom(backward, next));
    for (std::size_t x = 0; x < n; ++x) nearest[x] = std::min(nearest[x], from.back()[x] + to.back()[x]);
    next = farthest(nearest);
  }
  l.count = static_cast<int>(l.nodes.size());
  l.from.resize(n * l.count);
  l.to.resize(n * l.count);
  for (std::size_t x = 0; x < n; ++x) {
    for (int i = 0; i < l.count; ++i) {
      l.from[x * l.count + i] = from[i][x];
      l.to[x * l.count + i] = to[i][x];
    }
  }
  return l;
}

double pathCost(const Network& network, const QueryEnds& ends, const TurnCosts& turns, const std::vector<Index>& traversals,
                std::size_t target) {
  if (traversals.empty()) return ends.direct;
  double cost = kInfinity;
  for (const EndEdge& s : ends.sources) {
    if (s.v == traversals.front()) cost = std::min(cost, s.cost);
  }
  for (std::size_t i = 0; i + 1 < traversals.size(); ++i) {
    const Index v = traversals[i], w = traversals[i + 1];
    double step = kInfinity;
    for (const auto& e : boost::make_iterator_range(boost::out_edges(v, network.graph))) {
      if (boost::target(e, network.graph) == w) step = std::min(step, network.stepCost(v, w, network.graph[e].abs_angle, turns));
    }
    cost += step;
  }
  return cost + ends.targets[target].cost;
}

Path dijkstraPath(const Network& network, const QueryEnds& ends, const BlockMarks& blocks, const TurnCosts& turns) {
  using Edge = TurnGraph::edge_descriptor;
  const TurnGraph& g = network.graph;
  constexpr double kBlocked = std::numeric_limits<double>::max();  // Boost's "infinity"
  auto weight = boost::make_function_property_map<Edge, double>([&](const Edge& e) {
    const Index v = boost::source(e, g), w = boost::target(e, g);
    if (!network.usable(w, blocks) || blocks.node[network.end_node[v]] != 0) return kBlocked;
    return network.stepCost(v, w, g[e].abs_angle, turns);
  });
  const std::size_t n = network.traversals();
  std::vector<Index> pred(n);
  std::vector<double> dist(n, kBlocked);
  for (Index v = 0; v < n; ++v) pred[v] = v;
  std::vector<Index> sources;
  for (const EndEdge& s : ends.sources) {
    if (s.cost < dist[s.v]) dist[s.v] = s.cost;
    sources.push_back(s.v);
  }
  const auto index = boost::get(boost::vertex_index, g);
  boost::dijkstra_shortest_paths_no_init(g, sources.begin(), sources.end(), boost::make_iterator_property_map(pred.begin(), index),
                                         boost::make_iterator_property_map(dist.begin(), index), weight, index,
                                         std::less<double>(), boost::closed_plus<double>(kBlocked), 0.0,
                                         boost::default_dijkstra_visitor());
  Path path;
  path.cost = ends.direct;
  path.found = std::isfinite(ends.direct);
  std::size_t best = ends.targets.size();
  for (std::size_t t = 0; t < ends.targets.size(); ++t) {
    const double d = dist[ends.targets[t].v];
    if (d < kBlocked && d + ends.targets[t].cost < path.cost) {
      path.cost = d + ends.targets[t].cost;
      best = t;
    }
  }
  if (best == ends.targets.size()) return path;
  path.found = true;
  path.target = best;
  for (Index v = ends.targets[best].v;; v = pred[v]) {
    path.traversals.push_back(v);
    if (pred[v] == v) break;
  }
  std::reverse(path.traversals.begin(), path.traversals.end());
  path.cost = pathCost(network, ends, turns, path.traversals, best);
  return path;
}

}  // namespace mapnav::route_detail
