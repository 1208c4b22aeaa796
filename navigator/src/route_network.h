#pragma once
// The search graph behind RoadGraph (internal: it pulls in Boost.Graph). A vertex is a directed
// traversal of a road: vertex 2r drives road r from → to, 2r + 1 to → from (the backward traversal
// of a one-way road has no edges). Driving traversal v ends at its end node; an edge v → w turns
// there onto w and drives all of w. Turn costs and blocked roads are query options, applied when an
// edge is looked at, so the graph is built once. The query's start and goal are not vertices: the
// start gives the searches their first labels (the rest of the start road, either way) and the goal
// their last edges (turning onto the goal road and driving to the goal), so the graph is never
// modified and can be Boost's compressed sparse row graph.
#include <cstdint>
#include <limits>
#include <vector>

#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/range/iterator_range.hpp>

#include "mapnav/map/map.h"

namespace mapnav::route_detail {

using Index = std::uint32_t;
constexpr Index kNone = std::numeric_limits<Index>::max();
constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct Turn {
  double abs_angle = 0;  ///< |heading change| at the turn, radians
};
using TurnGraph = boost::compressed_sparse_row_graph<boost::bidirectionalS, boost::no_property, Turn,
                                                     boost::no_property, Index, Index>;

/// The query's turn costs (RouteOptions), in metres.
struct TurnCosts {
  double per_90deg = 0;
  double u_turn = 0;
};

/// The cost of turning by `abs_angle` radians, or of a U-turn.
double turnCost(double abs_angle, bool u_turn, const TurnCosts& turns);

/// A first or last edge of a query: the start's edge onto traversal `v` (cost: the rest of the
/// start road), or traversal `v`'s edge to the goal (cost: the turn onto the goal road and the drive
/// along it, `forward` or not, to the goal).
struct EndEdge {
  Index v = 0;
  double cost = 0;
  double bound = 0;       ///< a lower bound of `cost` free of turns (the drive alone)
  bool forward = true;    ///< the goal road's direction (goal edges)
};

/// One query's ends: the start's and the goal's edges, and the straight drive when start and goal
/// are on one road (infinite when there is none).
struct QueryEnds {
  std::vector<EndEdge> sources, targets;
  double direct = kInfinity;
};

/// What a search found: the traversals driven, start to goal (empty: the direct drive along one
/// road), the goal edge taken and the cost, summed from the start in the order driven.
struct Path {
  bool found = false;
  std::vector<Index> traversals;
  std::size_t target = 0;  ///< index into QueryEnds::targets (when traversals is not empty)
  double cost = kInfinity;
};

/// The roads and intersections one query may not use, as marks set for the query and cleared after
/// it (so a query costs nothing per road of the map).
struct BlockMarks {
  std::vector<std::uint8_t> road, node;
  std::vector<Index> set_roads, set_nodes;
  void set(const std::vector<Index>& roads, const std::vector<Index>& nodes);
  void clear();
};

/// Landmark distances for the A* lower bounds (ALT: Goldberg & Harrelson 2005), on the graph of
/// intersections with one edge per drivable traversal costing length × cost factor: no turn
/// penalties and nothing blocked, so every bound stays below the cost of any query.
struct Landmarks {
  int count = 0;
  std::vector<Index> nodes;       ///< the landmark intersections, in the order chosen
  std::vector<double> from, to;   ///< [node · count + i]: d(landmark i, node), d(node, landmark i)
  /// A lower bound of the cheapest drive from intersection a to b (+inf when b cannot be reached).
  double bound(Index a, Index b) const;
};

struct Network {
  TurnGraph graph;
  std::vector<double> drive_cost;     ///< per traversal: length × cost factor
  std::vector<Index> end_node;        ///< per traversal: the intersection it ends at
  std::vector<std::uint8_t> drivable; ///< per traversal: 0 for the backward of a one-way road
  std::vector<Index> arriving_begin;  ///< per intersection, into `arriving` (one past the last: size)
  std::vector<Index> arriving;        ///< traversals ending at each intersection, by intersection
  std::size_t intersections = 0;

  /// Edges between the drivable traversals of `map`, given per traversal the heading arriving at
  /// its end and leaving its start (the turn from v onto w is normalizeAngle(out[w] - in[v])).
  static Network build(const Map& map, const std::vector<double>& heading_in, const std::vector<double>& heading_out);

  std::size_t traversals() const { return drive_cost.size(); }
  /// The cost of edge v → w: the turn (a U-turn when w drives back v's road) and the drive of w.
  double stepCost(Index v, Index w, double abs_angle, const TurnCosts& turns) const {
    return drive_cost[w] + turnCost(abs_angle, w == (v ^ 1U), turns);
  }
  bool usable(Index v, const BlockMarks& blocks) const { return drivable[v] != 0 && blocks.road[v >> 1] == 0; }
  std::size_t bytes() const;  ///< memory held, for the benchmark
};

/// Landmarks chosen by farthest-point selection (each next one the intersection farthest, there and
/// back, from those chosen), at most `count`.
Landmarks chooseLandmarks(const Network& network, int count);

/// The reference: Boost's Dijkstra over the whole graph.
Path dijkstraPath(const Network& network, const QueryEnds& ends, const BlockMarks& blocks, const TurnCosts& turns);

/// An entry of a search queue: vertex `v` at distance `dist`, its key's bucket (an integer, as a
/// double so that no key overflows it).
struct QueueEntry {
  double bucket = 0;
  double dist = 0;
  Index v = 0;
};

/// The fast query: bidirectional A* with landmark lower bounds. Its buffers are kept between
/// queries and reset only where a query wrote, so a query costs what it visits.
class BidirectionalSearch {
 public:
  Path run(const Network& network, const Landmarks& landmarks, const QueryEnds& ends, const BlockMarks& blocks,
           const TurnCosts& turns);
  std::size_t scanned() const { return scanned_; }  ///< vertices taken off the queues by the last run

 private:
  std::vector<std::uint32_t> stamp_;  // per traversal: the query that last wrote its entries
  std::vector<double> potential_;     // forward potential (the backward one is its negative); NaN: useless
  std::vector<double> dist_[2];
  std::vector<Index> pred_[2];
  std::vector<QueueEntry> heap_[2];
  double quantum_ = 1;  // bucket width of the queues' keys
  std::uint32_t query_ = 0;
  std::size_t scanned_ = 0;
  // This query's landmark terms: the source's exits and the goal's entries (node, drive cost).
  std::vector<std::pair<Index, double>> exits_, entries_;

  void touch(Index v, const Network& network, const Landmarks& landmarks);
  void label(int side, Index v, double d, Index pred, double& best, Index& meet);
  Path reconstruct(const Network& network, const QueryEnds& ends, const TurnCosts& turns, Index meet, double direct) const;
};

/// The cost of `path` summed from the start in the order driven (both searches report this, so the
/// same route has the same cost to the last bit).
double pathCost(const Network& network, const QueryEnds& ends, const TurnCosts& turns, const std::vector<Index>& traversals,
                std::size_t target);

}  // namespace mapnav::route_detail
