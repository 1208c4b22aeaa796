#pragma once
// A mission's route: its stops after the start (the via points in order, then the goal) and the one
// Route through them that the Navigator follows and the simulator drives (world frame, metres).
#include <string>
#include <vector>

#include "mapnav/mission/mission_file.h"
#include "mapnav/navigator/road_position.h"
#include "mapnav/navigator/route.h"

namespace mapnav {

/// The route from `from` through every stop in order, as one Route: legs concatenated (two drive
/// legs on the same road at a stop are merged; a stop left back the way it was reached is a turn
/// around there), lines joined, intersections in order. `stop_s` gets the arc length along the
/// joined line at which each stop is reached (the last one: the length), m. Throws Unreachable
/// naming `what` and the reason.
Route planThrough(RoadGraph& graph, const RoadPosition& from, const std::vector<RoadPosition>& stops,
                  const std::string& what, std::vector<double>* stop_s = nullptr, const RouteOptions& options = {});

/// The mission's stops after the start: its via points, then the goal.
std::vector<RoadPosition> missionStops(const MissionFile& mission);

}  // namespace mapnav
