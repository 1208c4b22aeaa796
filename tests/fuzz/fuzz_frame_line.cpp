// Fuzz target: one frames.jsonl line of a replay log (parseLogFrame, as ReplayLog::open reads each
// line), against the log folder tests/fuzz/data/log (8 x 6 frames, some of them broken on purpose)
// with image verification on, so that named images are also decoded and checked.
#include "fuzz_support.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/logs/replay_log.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace mapnav;
  static const auto camera = loadCamera(fuzz::dataPath("camera.json"));
  static const std::filesystem::path dir = fuzz::dataPath("log");
  ReadOptions options;
  options.verify_images = true;
  Issues issues;
  // The first byte picks whether there is a previous frame (at t = 1 s), so time order is fuzzed too.
  const std::optional<double> last_t = size > 0 && data[0] == ' ' ? std::optional(1.0) : std::nullopt;
  const auto frame = parseLogFrame(fuzz::asText(data, size), dir, options, last_t, *camera, issues);
  fuzz::require(frame.has_value() != hasErrors(issues), "parseLogFrame's result disagrees with its issues");
  return 0;
}
