// Fuzz target: a mapnav-camera/1 document (parseCamera). A camera that parses must be usable:
// project and back-project without crashing, and write (cameraToJson) text that reads back.
#include "fuzz_support.h"
#include "mapnav/core/error.h"
#include "mapnav/geometry/camera_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace mapnav;
  Issues issues;
  std::string name;
  const auto camera = parseCamera(fuzz::asText(data, size), issues, &name);
  if (!camera) {
    fuzz::require(hasErrors(issues), "parseCamera returned nothing without an error");
    return 0;
  }
  (void)camera->projectGround(Vec2(5.0, 0.5));
  (void)camera->backproject(Vec2(0.5 * camera->width(), 0.5 * camera->height()));
  try {
    const std::string written = cameraToJson(*camera, name);
    Issues again;
    fuzz::require(parseCamera(written, again) != nullptr, "cameraToJson does not read back", written);
  } catch (const Error&) {
  }
  return 0;
}
