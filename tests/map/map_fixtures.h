#pragma once
// Small maps built in code, shared by the map tests.
#include "mapnav/map/map.h"

namespace mapnav::testing {

/// A cross intersection I1 at the origin with four 20 m roads, 2 m wide, to dead ends:
/// R1 → E (20, 0), R2 → N (0, 20), R3 → W (−20, 0), R4 → S (0, −20). Concrete on grass.
MapData crossOfFourRoads();

/// crossOfFourRoads() with one landmark of each kind beside its roads: pole P1 at
/// (10, 2) on R1 (radius 0.1, 5 m), tree T1 at (−3, 12) (0.25, 8 m; species and osm_node kept),
/// bench B1 at (−12, −2.5) (0.8, 0.8; a kept `height` tag "0.45 m"), bollard Bo1 at (2, −6)
/// (0.08, 0.9) and manhole M1 at (15, 0) in R1's paving (0.3, flat); origin 42.05 N, 87.67 W.
MapData crossWithOneLandmarkOfEachKind();

}  // namespace mapnav::testing
