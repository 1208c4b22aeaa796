#pragma once
// The `world` block of a mission file: WorldOptions by field name.
#include <string>

#include "mapnav/core/issue.h"
#include "mapnav/sim/world.h"

namespace mapnav {

/// Reads {"seed": 3, "shadow_density": 0.4, ...}: every WorldOptions field by its name
/// (worldOptionTable()), defaults for those absent. Wrong types, values out of range (each field's
/// rule) and unknown members are issues at their pointers under `pointer` ("/world/shadow_k").
WorldOptions parseWorldOptions(const std::string& json, const std::string& pointer, Issues& issues);

}  // namespace mapnav
