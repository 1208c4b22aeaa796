#pragma once
// The `world` block of a mission file: WorldOptions by field name, and how the world differs from
// the map (its `map_error` object, MapErrorOptions by field name).
#include <string>

#include "mapnav/core/issue.h"
#include "mapnav/sim/map_error.h"
#include "mapnav/sim/world.h"

namespace mapnav {

/// Reads {"seed": 3, "shadow_density": 0.4, ...}: every WorldOptions field by its name
/// (worldOptionTable()), defaults for those absent. Wrong types, values out of range (each field's
/// rule) and unknown members are issues at their pointers under `pointer` ("/world/shadow_k").
/// A `map_error` member is not WorldOptions' (parseMapErrorOptions reads it) and is skipped here.
WorldOptions parseWorldOptions(const std::string& json, const std::string& pointer, Issues& issues);

/// The block's `map_error` object ({"offset_sigma_m": 0.5, "seed": 4}, mapErrorOptionTable()),
/// defaults for its absent members, MapErrorOptions{} when the block has none; its issues at
/// POINTER/map_error/NAME. A block that is not a JSON object is parseWorldOptions' to report.
MapErrorOptions parseMapErrorOptions(const std::string& json, const std::string& pointer, Issues& issues);

}  // namespace mapnav
