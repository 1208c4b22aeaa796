#pragma once
// Validation that reports every problem of a map as an Issue with a JSON Pointer into the map
// file (docs/map-format.md lists every check).
#include "mapnav/core/issue.h"
#include "mapnav/core/option_table.h"
#include "mapnav/map/map.h"

namespace mapnav {

struct ValidationOptions {
  /// How far (m) a road's end may be from its intersection's position when it is not inside the
  /// intersection's shape. Also the radius around a shared intersection inside which two roads
  /// may touch.
  double end_tolerance_m = 0.5;
  /// Consecutive centre-line points closer than this (m) are a repeated point.
  double repeated_point_tolerance_m = 1e-3;
  /// Roads shorter than this (m) get a `roads.very_short` warning.
  double min_road_length_m = 1.0;
  /// Coordinates beyond ±this (m) are refused (`geometry.invalid_coordinate`).
  double max_coordinate_m = 1e7;
  /// Widths above this (m) are refused (`roads.invalid_width`).
  double max_width_m = 100.0;
  /// A landmark farther than this (m) from the paved area of the road it stands beside gets a
  /// `landmarks.far_from_road` warning: a camera looking along that road would hardly see it.
  double max_landmark_distance_m = 10.0;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// ValidationOptions' fields by name, with their rules.
const OptionTable<ValidationOptions>& validationOptionTable();

/// Every problem of `map`, errors and warnings, in a stable order (by check pass, then by position
/// in the file).
Issues validateMap(const MapData& map, const ValidationOptions& options = {});

}  // namespace mapnav
