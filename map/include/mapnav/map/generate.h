#pragma once
// Generated maps for tests and benchmarks.
#include "mapnav/core/option_table.h"
#include "mapnav/map/map.h"

namespace mapnav {

struct GridMapOptions {
  int columns = 10;         ///< intersections per row, ≥ 2
  int rows = 10;            ///< intersections per column, ≥ 2
  double spacing_m = 40.0;  ///< between neighbouring intersections
  double width_m = 2.0;     ///< of every road

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// GridMapOptions' fields by name, with their rules.
const OptionTable<GridMapOptions>& gridMapOptionTable();

/// A campus-like grid: intersection `I<c>_<r>` at (c·spacing, r·spacing), crosses inside, T on the
/// sides, L at the corners; roads `H<c>_<r>` (east) and `V<c>_<r>` (north), concrete on grass.
/// It has columns·(rows−1) + rows·(columns−1) roads: 224 × 224 gives 99 904.
MapData makeGridMap(const GridMapOptions& options);

}  // namespace mapnav
