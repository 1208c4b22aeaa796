// Bidirectional A* with landmark lower bounds (ALT; Goldberg & Harrelson 2005, "Computing the
// shortest path: A* search meets graph theory"), with the average potentials of Ikeda et al. (1994):
// the forward search uses p(v) = (pi_t(v) - pi_s(v)) / 2 and the backward one -p(v), where pi_t
// bounds the cost from v to the goal and pi_s the cost from the start to v from below. Both bounds
// are consistent (edges cost at least their drive, which is what the landmark distances add up), so
// the two searches run Dijkstra on the same non-negative reduced costs and may stop as soon as the
// smallest keys of their queues add up to the best route met (Goldberg & Harrelson, Section 5).
#include <algorithm>
#include <cmath>

#include "route_network.h"

namespace mapnav::route_detail {

namespace {
constexpr int kForward = 0, kBackward = 1;
using HeapEntry = std::pair<double, Index>;
constexpr auto kHeapOrder = std::greater<HeapEntry>();  // a min-heap on (key, vertex)
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
  heap_[side].emplace_back(d + (side == kForward ? potential_[v] : -potential_[v]), v);
  std::push_heap(heap_[side].begin(), heap_[side].end(), kHeapOrder);
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
  double best = ends.direct;
  Index meet = kNone;
  for (int side : {kForward, kBackward}) {
    for (const EndEdge& e : side == kForward ? ends.sources : ends.targets) {
      touch(e.v, network, landmarks);
      label(side, e.v, e.cost, kNone, best, meet);
    }
  }
  const TurnGraph& g = network.graph;
  while (!heap_[kForward].empty() && !heap_[kBackward].empty()) {
    const double top_f = heap_[kForward].front().first, top_b = heap_[kBackward].front().first;
    if (top_f + top_b >= best) break;
    const int side = top_f <= top_b ? kForward : kBackward;
    auto& heap = heap_[side];
    std::pop_heap(heap.begin(), heap.end(), kHeapOrder);
    const auto [key, v] = heap.back();
    heap.pop_back();
    const double d = dist_[side][v];
    if (key > d + (side == kForward ? potential_[v] : -potential_[v])) continue;  // an old entry
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
