// Fuzz target: a mapnav-map/1 document through both passes of the loader (parseMap, then buildMap,
// which validates), as loadMap does for a file. A map that parses must survive mapToJson → parseMap
// unchanged (the writer's exact round trip).
#include "fuzz_support.h"
#include "mapnav/core/error.h"
#include "mapnav/map/map_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace mapnav;
  Issues issues;
  auto parsed = parseMap(fuzz::asText(data, size), issues);
  if (!parsed) {
    fuzz::require(hasErrors(issues), "parseMap returned nothing without an error");
    return 0;
  }
  const std::string written = mapToJson(*parsed);
  Issues again;
  const auto reread = parseMap(written, again);
  fuzz::require(reread.has_value() && *reread == *parsed, "mapToJson does not read back to the same map", written);
  try {
    auto map = buildMap(std::move(*parsed), "fuzz.json", issues);
    fuzz::require(map.has_value() != hasErrors(issues), "buildMap's result disagrees with its issues");
  } catch (const Error&) {
  }
  return 0;
}
