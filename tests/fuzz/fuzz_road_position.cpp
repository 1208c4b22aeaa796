// Fuzz target: road-position strings (`R1@I1+3/-0.4`, parseRoadPosition). One that parses must
// print (toString) to text that parses back to the same position, and place on a map (toPose)
// or be refused with a mapnav::Error.
#include "fuzz_support.h"
#include "mapnav/core/error.h"
#include "mapnav/map/map_io.h"
#include "mapnav/navigator/road_position.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace mapnav;
  static const Map map = loadMap(fuzz::dataPath("map.json"));
  const std::string_view text = fuzz::asText(data, size);
  RoadPosition position;
  try {
    position = parseRoadPosition(text);
  } catch (const InvalidInput&) {
    return 0;
  }
  const std::string printed = toString(position);
  RoadPosition reread;
  try {
    reread = parseRoadPosition(printed);
  } catch (const InvalidInput& e) {
    fuzz::require(false, "toString gives a road position that does not parse", printed + ": " + e.what());
  }
  fuzz::require(reread == position, "toString does not read back to the same road position", printed);
  try {
    (void)toPose(map, position);
  } catch (const Error&) {
  }
  return 0;
}
