#pragma once
// Road positions, the dialogue's way of saying where the robot is: `R1@I1+3` is on road R1, 3 m
// along it from intersection I1, facing away from I1; `R1@I1+3/-0.4` is 0.4 m right of the centre.
#include <string>
#include <string_view>

#include "mapnav/geometry/pose2.h"
#include "mapnav/map/map.h"

namespace mapnav {

struct RoadPosition {
  std::string road;     ///< road id
  std::string node;     ///< one of the road's intersections
  double meters = 0;    ///< along the centre line from `node`, ≥ 0
  double lateral = 0;   ///< left of the centre line, m (right negative)

  bool operator==(const RoadPosition&) const = default;
};

/// Parses `ROAD@NODE+METERS[/LATERAL]`. Throws InvalidInput saying what is wrong.
RoadPosition parseRoadPosition(std::string_view text);
std::string toString(const RoadPosition& position);

/// Where a road position is along its road: the arc length of the centre line from the road's
/// `from` end (on a loop road, whose ends are both `node`, the metres count from `from`: the
/// position faces along the centre line). Throws InvalidInput when `node` is not an end of the road
/// or `meters` is not within [0, the road's length], the numbers printed so that they never
/// contradict the comparison.
double arcFromStart(const Road& road, const RoadPosition& position);

/// The world pose at a road position: on the centre line (plus the lateral offset), heading along
/// the road away from `node`. Throws NotFound for an unknown road, InvalidInput when `node` is not
/// an end of the road or `meters` is beyond its length.
Pose2 toPose(const Map& map, const RoadPosition& position);

/// `position` with its metres clamped to the road's length on `map`: a position written for another
/// map of the same roads (a simulated world that differs from its map, sim/map_error.h, whose roads
/// are a little longer or shorter) is the same distance from the same intersection on this map's
/// road. Throws NotFound for an unknown road.
RoadPosition clampedTo(const Map& map, RoadPosition position);

}  // namespace mapnav
