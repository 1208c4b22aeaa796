#pragma once
// Small maps built in code, shared by the map tests.
#include "mapnav/map/map.h"

namespace mapnav::testing {

/// A cross intersection I1 at the origin with four 20 m roads, 2 m wide, to dead ends:
/// R1 → E (20, 0), R2 → N (0, 20), R3 → W (−20, 0), R4 → S (0, −20). Concrete on grass.
MapData crossOfFourRoads();

}  // namespace mapnav::testing
