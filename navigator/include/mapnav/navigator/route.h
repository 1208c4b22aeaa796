#pragma once
// Routes across intersections (Wallace 1985, Figure 1): "Navigate to R3, 2 meters from I3" —
// "Drive on it 2.5 meters and turn to right 90 degrees". Boost.Graph stays behind RoadGraph's
// private pointer (as Lanelet2's routing graph), so this header pulls in nothing heavy.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/polyline2.h"
#include "mapnav/map/map.h"
#include "mapnav/navigator/road_position.h"

namespace mapnav {

struct RouteOptions {
  /// Cost of turning, in metres of driving per 90 degrees of turn (linear in the turn angle), so
  /// that of two routes of equal length the one with fewer and gentler turns wins.
  double turn_penalty_m_per_90deg = 5.0;
  /// Cost of turning back along the road just driven, at an intersection, in metres.
  double u_turn_penalty_m = 50.0;
  /// Roads and intersections that may not be used (ids).
  std::vector<std::string> blocked;
  /// Bidirectional A* with landmark lower bounds (ALT), which on a grid visits little more than the
  /// route's roads (on irregular maps with uneven cost factors, a band around the route); false runs
  /// Dijkstra over the whole graph (the reference: routes of the same cost, far slower on large
  /// maps). The first A* query of a RoadGraph computes the landmark distances (17 Dijkstra runs
  /// over the intersections: 5-13 s at a million on a shared 2-core machine).
  bool use_astar = true;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// The options' names, rules and descriptions (`blocked`, a list of ids, is not in it: it has no
/// rule); validate() checks them.
const OptionTable<RouteOptions>& routeOptionTable();

enum class LegAction { Drive, Turn };

struct Leg {
  LegAction action = LegAction::Drive;
  std::string road;     ///< Drive: the road; Turn: the road turned onto
  double meters = 0;    ///< Drive: distance along the road
  std::string at;       ///< Turn: the intersection (a turn around at a via point: its road position)
  double angle = 0;     ///< Turn: radians, left positive, (-pi, pi]
};

/// "left", "right", "straight" (within 15 degrees) or "around" (165 degrees or more: back the way it
/// came, as at an out-and-back via point), as the dialogue says it.
std::string turnDirection(double angle);

struct Route {
  RoadPosition from, to;
  double length_m = 0;  ///< distance driven
  double cost = 0;      ///< length × cost factors + turn penalties
  std::vector<Leg> legs;
  std::vector<std::string> roads;          ///< driven, in order
  std::vector<std::string> intersections;  ///< passed, in order
  Polyline2 line;                          ///< the centre line driven, start to goal
};

/// A route, or why there is none.
struct RouteResult {
  std::optional<Route> route;
  std::string reason;  ///< when there is no route: why (different components, blocked, one-way)
};

class RoadGraph {
 public:
  /// The graph of `map`, which must outlive it.
  explicit RoadGraph(const Map& map);
  ~RoadGraph();
  RoadGraph(RoadGraph&&) noexcept;
  RoadGraph& operator=(RoadGraph&&) noexcept;

  /// The cheapest route. Throws NotFound for unknown ids (in the positions or `blocked`) and
  /// InvalidInput for a position off its road. Not thread-safe: a query reuses the graph's search
  /// buffers and marks its blocked roads in the graph until it returns; the first A* query also
  /// computes the landmark distances, once (blocked roads do not change them: blocking only makes
  /// routes dearer, so the landmark bounds stay below every blocked query's costs).
  RouteResult route(const RoadPosition& from, const RoadPosition& to, const RouteOptions& options = {});

  const Map& map() const;
  std::size_t vertexCount() const;  ///< directed road traversals (for benchmarks)

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The dialogue: "Drive on R1 3.0 m and turn right 90 degrees onto R2. Drive on R2 40.0 m ..."
std::string toDialogue(const Route& route);
/// {"length_m":..,"legs":[{"action":"drive","road":"R1","meters":2.5},{"action":"turn","at":"I1",
/// "direction":"right","degrees":90,"onto":"R2"},...]}
std::string toJson(const Route& route);

}  // namespace mapnav
