// Fuzz target: GeoJSON import (importGeoJson) and, when it gives a map, validation (validateMap)
// with every issue's pointer translated back into the GeoJSON file, as `mapnav import` does.
#include "fuzz_support.h"
#include "mapnav/core/error.h"
#include "mapnav/map/geojson.h"
#include "mapnav/map/validation.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace mapnav;
  Issues issues;
  try {
    const auto imported = importGeoJson(fuzz::asText(data, size), issues);
    if (!imported) {
      fuzz::require(hasErrors(issues), "importGeoJson returned nothing without an error");
      return 0;
    }
    for (const Issue& issue : validateMap(imported->map)) (void)imported->toFeaturePointer(issue.where);
  } catch (const Error&) {
  }
  return 0;
}
