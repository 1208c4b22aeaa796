#include "mapnav/navigator/progress.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace mapnav {

std::optional<RoadProjection> projectToRoad(const Map& map, const Pose2& pose, double max_distance_m) {
  std::optional<RoadProjection> best;
  // roadsNear measures from the paved edge; ask wide enough to catch every centre line in range.
  for (const Road* road : map.roadsNear(pose.translation(), max_distance_m)) {
    const Polyline2::Projection p = road->centerline.project(pose.translation());
    if (p.distance > max_distance_m) continue;
    if (best && (p.distance > best->distance || (p.distance == best->distance && road->id > best->position.road))) continue;
    RoadProjection r;
    r.position = RoadPosition{road->id, road->from, p.arc_length, p.lateral};
    r.heading_error = normalizeAngle(pose.heading() - road->centerline.headingAt(p.arc_length));
    r.distance = p.distance;
    best = r;
  }
  return best;
}

const OptionTable<ProgressOptions>& progressOptionTable() {
  using O = ProgressOptions;
  static const OptionTable<O> table =
      OptionTable<O>("ProgressOptions")
          .field("off_route_tolerance_m", &O::off_route_tolerance_m, above(0),
                 "farther than this from the route's centre line is off the route, m")
          .field("search_ahead_m", &O::search_ahead_m, above(0),
                 "the next position is looked for up to this far ahead of the last, m")
          .field("turnaround_reach_m", &O::turnaround_reach_m, atLeast(0),
                 "within this of a turnaround it is reached and progress moves onto the way back, m");
  return table;
}

void ProgressOptions::validate() const { progressOptionTable().validate(*this); }

std::vector<double> turnaroundArcs(const Route& route) {
  // The line's vertices where it folds back, with their arc lengths: the legs' metres say which,
  // the vertex where (a slice of the line ending a hair past it would end going back).
  const std::vector<Vec2>& p = route.line.points();
  std::vector<double> folds;
  double c = 0;
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    c += (p[i] - p[i - 1]).norm();
    if ((p[i] - p[i - 1]).dot(p[i + 1] - p[i]) < 0) folds.push_back(c);
  }
  std::vector<double> arcs;
  double s = 0;
  for (const Leg& leg : route.legs) {
    if (leg.action == LegAction::Drive) s += leg.meters;
    if (leg.action != LegAction::Turn || turnDirection(leg.angle) != "around") continue;
    double at = s, nearest = 1.0;  // the fold within 1 m of it
    for (const double f : folds) {
      if (std::abs(f - s) < nearest) {
        nearest = std::abs(f - s);
        at = f;
      }
    }
    arcs.push_back(at);
  }
  return arcs;
}

RouteProgress::RouteProgress(Route route, const ProgressOptions& options)
    : route_(std::move(route)), options_(options), turnarounds_(turnaroundArcs(route_)) {
  options_.validate();
}

ProgressStatus RouteProgress::update(const Pose2& pose) {
  const Polyline2& line = route_.line;
  const double length = line.length();
  // The stretch between the last turnaround passed and the next: the line comes back over itself
  // there, and the way back is no place for the way out (nor the other way round).
  const auto next = std::upper_bound(turnarounds_.begin(), turnarounds_.end(), along_);
  double begin = next == turnarounds_.begin() ? 0.0 : *std::prev(next);
  double end = next == turnarounds_.end() ? length : std::min(length, *next);
  // The first pose is looked for along the whole stretch; later ones from a little behind the last
  // position to the search window ahead.
  const double s0 = started_ ? std::max(begin, along_ - 1.0) : begin;
  const double s1 = started_ ? std::min(end, along_ + options_.search_ahead_m) : end;
  started_ = true;
  const Polyline2::Projection p = line.slice(s0, s1).project(pose.translation());
  along_ = std::max(along_, s0 + p.arc_length);
  if (end < length && along_ >= end - options_.turnaround_reach_m) {  // reached: onto the way back
    along_ = begin = end;
    const auto after = std::upper_bound(turnarounds_.begin(), turnarounds_.end(), along_);
    end = after == turnarounds_.end() ? length : std::min(length, *after);
  }
  ProgressStatus status;
  status.stretch_begin_m = begin;
  status.stretch_end_m = end;
  status.along_m = along_;
  status.to_go_m = length - along_;
  status.off_route_m = p.distance;
  status.off_route = p.distance > options_.off_route_tolerance_m;
  status.finished = status.to_go_m <= 0.5;
  // The drive leg under way: legs in order, each drive leg covering its metres of the line.
  double start = 0;
  for (std::size_t i = 0; i < route_.legs.size(); ++i) {
    if (route_.legs[i].action != LegAction::Drive) continue;
    status.leg = i;
    start += route_.legs[i].meters;
    if (along_ < start) break;
  }
  return status;
}

bool needsReplan(const ProgressStatus& status, const Route& route, const std::vector<std::string>& blocked) {
  if (status.off_route) return true;
  // Roads and intersections still ahead: the legs from the current one on.
  for (std::size_t i = status.leg; i < route.legs.size(); ++i) {
    const Leg& leg = route.legs[i];
    for (const std::string& id : blocked) {
      if (leg.road == id || (leg.action == LegAction::Turn && leg.at == id)) return true;
    }
  }
  return false;
}

RouteResult replan(RoadGraph& graph, const Pose2& pose, const RoadPosition& goal, const RouteOptions& options) {
  const auto here = projectToRoad(graph.map(), pose);
  if (!here) {
    RouteResult none;
    none.reason = "the vehicle is more than 5 m from every road";
    return none;
  }
  RoadPosition from = here->position;
  from.lateral = 0;
  return graph.route(from, goal, options);
}

}  // namespace mapnav
