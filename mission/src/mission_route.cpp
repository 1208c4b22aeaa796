// A mission's route through its stops (mission_route.h).
#include "mapnav/mission/mission_route.h"

#include <cmath>
#include <utility>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/geometry/polyline2.h"
#include "mapnav/geometry/types.h"

namespace mapnav {

Route planThrough(RoadGraph& graph, const RoadPosition& from, const std::vector<RoadPosition>& stops,
                  const std::string& what, std::vector<double>* stop_s, const RouteOptions& options) {
  Route joined;
  joined.from = from;
  joined.to = stops.empty() ? from : stops.back();
  std::vector<Vec2> line;
  if (stop_s != nullptr) stop_s->clear();
  RoadPosition here = from;
  for (const RoadPosition& stop : stops) {
    const RouteResult leg = graph.route(here, stop, options);
    if (!leg.route) throw Unreachable(what + ": no route: " + leg.reason);
    const Route& r = *leg.route;
    // Back the way it came from a via point (out and back on its road): a turn around there, not
    // one drive leg through it.
    bool turns_around = false;
    if (line.size() >= 2 && r.line.size() >= 2 && r.line.length() > 1e-9) {
      const Vec2 in = line.back() - line[line.size() - 2];
      turns_around = std::abs(normalizeAngle(r.line.headingAt(0) - std::atan2(in.y(), in.x()))) > kPi / 2;
    }
    if (turns_around) joined.legs.push_back(Leg{LegAction::Turn, here.road, 0.0, toString(here), kPi});
    for (const Vec2& p : r.line.points()) {
      if (line.empty() || (line.back() - p).norm() > 1e-9) line.push_back(p);
    }
    for (const Leg& l : r.legs) {
      if (l.action == LegAction::Drive && !joined.legs.empty() && joined.legs.back().action == LegAction::Drive &&
          joined.legs.back().road == l.road) {
        joined.legs.back().meters += l.meters;  // through a via point on the same road
      } else {
        joined.legs.push_back(l);
      }
    }
    for (const std::string& road : r.roads) {
      if (joined.roads.empty() || joined.roads.back() != road) joined.roads.push_back(road);
    }
    joined.intersections.insert(joined.intersections.end(), r.intersections.begin(), r.intersections.end());
    joined.length_m += r.length_m;
    joined.cost += r.cost;
    if (stop_s != nullptr) stop_s->push_back(joined.length_m);
    here = stop;
  }
  joined.line = Polyline2(std::move(line));
  return joined;
}

std::vector<RoadPosition> missionStops(const MissionFile& mission) {
  std::vector<RoadPosition> stops = mission.via;
  stops.push_back(mission.goal);
  return stops;
}

}  // namespace mapnav
