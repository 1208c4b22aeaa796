#pragma once
// The `world` block of a mission file: WorldOptions by field name, how the world differs from the
// map (its `map_error` object, MapErrorOptions by field name) and the vehicle's GNSS receiver (its
// `gnss` object, GnssReceiverOptions by field name).
#include <optional>
#include <string>

#include "mapnav/core/issue.h"
#include "mapnav/logs/gnss.h"
#include "mapnav/sim/map_error.h"
#include "mapnav/sim/world.h"

namespace mapnav {

/// Reads {"seed": 3, "shadow_density": 0.4, ...}: every WorldOptions field by its name
/// (worldOptionTable()), defaults for those absent. Wrong types, values out of range (each field's
/// rule) and unknown members are issues at their pointers under `pointer` ("/world/shadow_k").
/// Its `map_error` and `gnss` members are not WorldOptions' (the functions below read them) and are
/// skipped here.
WorldOptions parseWorldOptions(const std::string& json, const std::string& pointer, Issues& issues);

/// The block's `map_error` object ({"offset_sigma_m": 0.5, "seed": 4}, mapErrorOptionTable()),
/// defaults for its absent members, MapErrorOptions{} when the block has none; its issues at
/// POINTER/map_error/NAME. A block that is not a JSON object is parseWorldOptions' to report.
MapErrorOptions parseMapErrorOptions(const std::string& json, const std::string& pointer, Issues& issues);

/// The block's `gnss` object ({"sigma_m": 1, "bias_sigma_m": 1.5, "seed": 4}, gnssReceiverOptionTable()):
/// a receiver on the vehicle, a fix with every frame; defaults for its absent members; nullopt when
/// the block has none (no receiver). Its issues at POINTER/gnss/NAME.
std::optional<GnssReceiverOptions> parseGnssOptions(const std::string& json, const std::string& pointer, Issues& issues);

}  // namespace mapnav
