// Bidirectional A* with landmark lower bounds (ALT; Goldberg & Harrelson 2005, "Computing the
// shortest path: A* search meets graph theory"), with the average potentials of Ikeda et al. (1994):
// the forward search uses p(v) = (pi_t(v) - pi_s(v)) / 2 and the backward one -p(v), where pi_t
// bounds the cost from v to the goal and pi_s the cost from the start to v from below. Both bounds
// are consistent (edges cost at least their drive, which is what the landmark distances add up), so
// the two searches run Dijkstra on the same non-negative reduced costs and may stop as soon as the
// smallest keys of their queues add up to the best route met (Goldberg & Harrelson, Section 5).
//
// On a grid, many vertices have the same key (every staircase between two corners is as long, and
// the landmark bounds are exact there without turns), so the order among equal keys decides how
// much of such a plateau is swept before the two searches meet. Keys are therefore put in buckets
// of width `quantum_` (a 1e-11 part of the route's lower bound, above the rounding of the sums) and
// within a bucket the vertex farthest from its search's end goes first, which runs straight along
// a plateau to the other search. The order of scanning does not decide correctness (a vertex whose
// distance improves is queued again), only the stopping rule does, and it uses the buckets' lower
// ends: the route returned costs at most 3 quanta more than the cheapest (a 3e-11 part, far below
// any difference between two routes that are not tied).
#include <algorithm>
#include <cmath>

#include "route_network.h"

namespace mapnav::route_detail {

namespace {
constexpr int kForward = 0, kBackward = 1;
// Priority order of the queues (a max-heap on it): lower bucket first, then the larger distance,
// then the smaller vertex.
bool lowerPriority(const QueueEntry& a, const QueueEntry& b) {
  if (a.bucket != b.bucket) return a.bucket > b.bucket;
  if (a.dist != b.dist) return a.dist < b.dist;
  return a.v > b.v;
}
}  // namespace

// Entries of vertex v are this query's when stamp_[v] == query_; otherwise they are stale and the
// first touch resets them (with v's potential, computed once per query).
void BidirectionalSearch::touch(Index v, const Network& network, const Landmarks& landmarks) {
  if (stamp_[v] == query_) return;
  stamp_[v] = query_;
  dist_[kForward][v] = dist_[kBackward][v] = kInfinity;
  pred_[kForward][v] = pred_[kBackward][v] = kNone;
  const Index x = network.end_node[v];
  double to_goal = kInfinity, from_start = kInfinity;
  for (const auto& [node, cost] : entries_) to_goal = std::min(to_goal, landmarks.bound(x, node) + cost);
  for (const auto& [node, cost] : exits_) from_start = std::min(from_start, cost + landmarks.bound(node, x));
  // A vertex that cannot reach the goal, or be reached from the start, is on no route.
  potential_[v] = std::isfinite(to_goal) && std::isfinite(from_start) ? 0.5 * (to_goal - from_start)
                                                                      : std::numeric_limits<double>::quiet_NaN();
}

// A better distance `d` for v on `side` (via `pred`): queued, and a route met if the other side has
// reached v too.
void BidirectionalSearch::label(int side, Index v, double d, Index pred, double& best, Index& meet) {
  if (std::isnan(potential_[v]) || !(d < dist_[side][v])) return;
  dist_[side][v] = d;
  pred_[side][v] = pred;
  const double key = d + (side == kForward ? potential_[v] : -potential_[v]);
  heap_[side].push_back(QueueEntry{std::floor(key / quantum_), d, v});
  std::push_heap(heap_[side].begin(), heap_[side].end(), lowerPriority);
  const double through = d + dist_[1 - side][v];
  if (through < best) {
    best = through;
    meet = v;
  }
}

Path BidirectionalSearch::run(const Network& network, const Landmarks& landmarks, const QueryEnds& ends,
                              const BlockMarks& blocks, const TurnCosts& turns) {
  const std::size_t n = network.traversals();
  if (stamp_.size() != n) {
    stamp_.assign(n, 0);
    potential_.assign(n, 0.0);
    for (int s : {kForward, kBackward}) {
      dist_[s].assign(n, kInfinity);
      pred_[s].assign(n, kNone);
    }
    query_ = 0;
  }
  if (++query_ == 0) {  // the stamps wrapped around: forget them all
    std::fill(stamp_.begin(), stamp_.end(), 0);
    query_ = 1;
  }
  scanned_ = 0;
  exits_.clear();
  entries_.clear();
  for (const EndEdge& s : ends.sources) exits_.emplace_back(network.end_node[s.v], s.cost);
  for (const EndEdge& t : ends.targets) entries_.emplace_back(network.end_node[t.v], t.bound);
  for (auto& h : heap_) h.clear();
  // The quantum: from the smallest keys the two searches start with, which add up to a lower bound
  // of the route's cost.
  double start_key[2] = {kInfinity, kInfinity};
  for (int side : {kForward, kBackward}) {
    for (const EndEdge& e : side == kForward ? ends.sources : ends.targets) {
      touch(e.v, network, landmarks);
      const double key = e.cost + (side == kForward ? potential_[e.v] : -potential_[e.v]);
      if (key < start_key[side]) start_key[side] = key;
    }
  }
  const double scale = start_key[0] + start_key[1];
  quantum_ = 1e-11 * (std::isfinite(scale) && scale > 1 ? scale : 1.0);
  double best = ends.direct;
  Index meet = kNone;
  for (int side : {kForward, kBackward}) {
    for (const EndEdge& e : side == kForward ? ends.sources : ends.targets) label(side, e.v, e.cost, kNone, best, meet);
  }
  const TurnGraph& g = network.graph;
  while (!heap_[kForward].empty() && !heap_[kBackward].empty()) {
    const double top_f = heap_[kForward].front().bucket, top_b = heap_[kBackward].front().bucket;
    // Every key in a queue is at least its top bucket's lower end; 3 quanta more let the search
    // stop on a tie that the rounding of the sums put a hair apart.
    if (static_cast<double>(top_f + top_b + 3) * quantum_ >= best) break;
    const int side = top_f <= top_b ? kForward : kBackward;
    auto& heap = heap_[side];
    std::pop_heap(heap.begin(), heap.end(), lowerPriority);
    const QueueEntry top = heap.back();
    heap.pop_back();
    const Index v = top.v;
    const double d = dist_[side][v];
    if (top.dist > d) continue;  // an old entry: v was queued again with a shorter distance
    ++scanned_;
    if (side == kForward) {
      if (blocks.node[network.end_node[v]] != 0) continue;  // no turn at a blocked intersection
      for (const auto& e : boost::make_iterator_range(boost::out_edges(v, g))) {
        const Index w = boost::target(e, g);
        if (!network.usable(w, blocks)) continue;
        touch(w, network, landmarks);
        label(kForward, w, d + network.stepCost(v, w, g[e].abs_angle, turns), v, best, meet);
      }
    } else {
      for (const auto& e : boost::make_iterator_range(boost::in_edges(v, g))) {
        const Index u = boost::source(e, g);
        if (!network.usable(u, blocks) || blocks.node[network.end_node[u]] != 0) continue;
        touch(u, network, landmarks);
        label(kBackward, u, d + network.stepCost(u, v, g[e].abs_angle, turns), v, best, meet);
      }
    }
  }
  return reconstruct(network, ends, turns, meet, ends.direct);
}

// The route through `meet`: the forward predecessors back to a start edge, then the backward ones
// on to a goal edge (the cheapest goal edge of the last traversal, as the search seeded it).
Path BidirectionalSearch::reconstruct(const Network& network, const QueryEnds& ends, const TurnCosts& turns, Index meet,
                                      double direct) const {
  Path path;
  if (meet == kNone) {
    path.found = std::isfinite(direct);
    path.cost = direct;
    return path;
  }
  for (Index v = meet; v != kNone; v = pred_[kForward][v]) path.traversals.push_back(v);
  std::reverse(path.traversals.begin(), path.traversals.end());
  for (Index v = pred_[kBackward][meet]; v != kNone; v = pred_[kBackward][v]) path.traversals.push_back(v);
  const Index last = path.traversals.back();
  double cheapest = kInfinity;
  for (std::size_t t = 0; t < ends.targets.size(); ++t) {
    if (ends.targets[t].v == last && ends.targets[t].cost < cheapest) {
      cheapest = ends.targets[t].cost;
      path.target = t;
    }
  }
  path.found = true;
  path.cost = pathCost(network, ends, turns, path.traversals, path.target);
  return path;
}

}  // namespace mapnav::route_detail
