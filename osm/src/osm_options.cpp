// OsmImportOptions: the table of its value fields and their rules, and the checks of the others
// (highways, bbox, widths).
#include <algorithm>
#include <cmath>
#include <string>

#include "mapnav/core/error.h"
#include "mapnav/map/geojson.h"
#include "mapnav/osm/osm_import.h"

namespace mapnav {

namespace {

/// default_width_m's and every `widths` entry's.
const OptionRule kWidthRule = above(0);

bool isStandardSurface(const std::string& name) {
  const auto surfaces = standardSurfaces();
  return std::any_of(surfaces.begin(), surfaces.end(), [&](const auto& s) { return s.first == name; });
}

}  // namespace

const OptionTable<OsmImportOptions>& osmImportOptionTable() {
  using O = OsmImportOptions;
  static const OptionTable<O> table =
      OptionTable<O>("OsmImportOptions")
          .field("default_width_m", &O::default_width_m, kWidthRule, "paved width of the highways `widths` does not list, m")
          .field("shoulder", &O::shoulder, "the shoulder surface on both sides: one of the standard surfaces")
          .field("steps_cost_factor", &O::steps_cost_factor, atLeast(1), "route cost factor of steps")
          .field("repair", &O::repair, "repair the data instead of only reporting it")
          .field("merge_distance_m", &O::merge_distance_m, atLeast(0), "repair: nodes of kept ways closer than this become one, m")
          .field("min_piece_m", &O::min_piece_m, atLeast(0), "a shorter piece is tiny (with repair, a tiny stub is dropped), m")
          .field("max_landmark_distance_m", &O::max_landmark_distance_m, atLeast(0),
                 "a landmark farther than this from every imported road's paved area is dropped, m")
          .field("keep_far_landmarks", &O::keep_far_landmarks, "keep the landmarks farther than max_landmark_distance_m too")
          .field("name", &O::name, "the map's name (\"\": \"imported from <file name>\")")
          .field("position_sigma_m", &O::position_sigma_m, inRange(0, kMaxPositionSigmaM),
                 "how well the ways are placed in the world, 1-sigma per axis, m (the map's position_sigma_m)")
          .check("shoulder", [](const O& o) { return isStandardSurface(o.shoulder); }, "a standard surface");
  return table;
}

void OsmImportOptions::validate() const {
  if (highways.empty()) throw InvalidInput("OsmImportOptions.highways: empty; keep at least one highway value");
  if (bbox) {
    const auto& b = *bbox;
    const bool ok = std::all_of(b.begin(), b.end(), [](double v) { return std::isfinite(v); }) && b[0] >= -180 &&
                    b[2] <= 180 && b[1] >= -90 && b[3] <= 90 && b[0] < b[2] && b[1] < b[3];
    if (!ok) throw InvalidInput("OsmImportOptions.bbox: expected west < east in [-180, 180] and south < north in [-90, 90]");
  }
  // A width by highway value has default_width_m's rule; a map of them is no field of a table.
  for (const auto& [highway, width] : widths) {
    const OptionFieldSpec entry{.name = "widths[" + highway + "]", .rule = kWidthRule};
    if (std::string broken = detail::brokenOptionValue(entry, "OsmImportOptions", width); !broken.empty())
      throw InvalidInput(broken);
  }
  osmImportOptionTable().validate(*this);
}

}  // namespace mapnav
