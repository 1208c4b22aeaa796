// Fuzz target: a mapnav-mission/1 document (parseMission), as if it were tests/fuzz/data/mission.json,
// so that "map.json" and "camera.json" name files that exist.
#include "fuzz_support.h"
#include "mapnav/mission/mission_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace mapnav;
  static const std::filesystem::path path = fuzz::dataPath("mission.json");
  Issues issues;
  const auto mission = parseMission(fuzz::asText(data, size), path, issues);
  fuzz::require(mission.has_value() != hasErrors(issues), "parseMission's result disagrees with its issues");
  return 0;
}
