#pragma once
// Where the vehicle is on its route, and when the Navigator should plan again.
#include <optional>
#include <string>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/map/map.h"
#include "mapnav/navigator/road_position.h"
#include "mapnav/navigator/route.h"

namespace mapnav {

/// A pose seen from the nearest road.
struct RoadProjection {
  RoadPosition position;      ///< on the road, measured from its `from` end (lateral: left positive)
  double heading_error = 0;   ///< pose heading − the road's heading (from → to) there, (-pi, pi]
  double distance = 0;        ///< from the centre line, m
};

/// The nearest road's centre line within `max_distance_m` of the pose, or nothing (off the map).
/// Ties go to the road with the smaller id.
std::optional<RoadProjection> projectToRoad(const Map& map, const Pose2& pose, double max_distance_m = 5.0);

struct ProgressOptions {
  /// Farther than this (m) from the route's centre line is off the route.
  double off_route_tolerance_m = 2.0;
  /// How far ahead (m) of the last position the next one is looked for, so that a route passing
  /// near itself does not make progress jump.
  double search_ahead_m = 15.0;
  /// Within this of a turnaround (turnaroundArcs), m, it is reached: progress moves onto the way
  /// back. More than the 0.1 m within which a follower stops at its plan's end (kArrivalToleranceM),
  /// so that a vehicle stopped there passes it.
  double turnaround_reach_m = 0.25;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// The options' names, rules and descriptions; validate() checks them.
const OptionTable<ProgressOptions>& progressOptionTable();

struct ProgressStatus {
  std::size_t leg = 0;      ///< index into Route::legs of the drive leg under way
  double along_m = 0;       ///< driven along the route
  double to_go_m = 0;       ///< left to the goal
  double off_route_m = 0;   ///< distance from the route's centre line
  bool off_route = false;
  bool finished = false;    ///< within 0.5 m of the goal
  /// The stretch of the route under way, between turnarounds (turnaroundArcs): from the last one
  /// passed (0: the start) to the next (the route's length: none ahead), along the route, m.
  double stretch_begin_m = 0;
  double stretch_end_m = 0;
};

/// Where the route turns around, as arc lengths along Route::line: the end of each drive leg that a
/// turn "around" (turnDirection: an out-and-back via point, a U-turn) follows. There the line comes
/// back over itself, so that progress must not look past it before reaching it.
std::vector<double> turnaroundArcs(const Route& route);

class RouteProgress {
 public:
  explicit RouteProgress(Route route, const ProgressOptions& options = {});
  /// The first pose is found anywhere along the route up to its first turnaround; after that
  /// progress only moves forward, looked for from the last position onwards, never past the next
  /// turnaround before it is reached (within turnaround_reach_m), nor back before the last one: a
  /// route that drives a road out and back follows the two passes in order.
  ProgressStatus update(const Pose2& pose);
  const Route& route() const { return route_; }

 private:
  Route route_;
  ProgressOptions options_;
  std::vector<double> turnarounds_;
  double along_ = 0;
  bool started_ = false;
};

/// Plan again when off the route, or when a road or intersection still ahead has become blocked.
bool needsReplan(const ProgressStatus& status, const Route& route, const std::vector<std::string>& blocked);

/// A new route to `goal` from where the pose is (its nearest road, within 5 m). A pose off every
/// road gives no route and says so.
RouteResult replan(RoadGraph& graph, const Pose2& pose, const RoadPosition& goal, const RouteOptions& options = {});

}  // namespace mapnav
