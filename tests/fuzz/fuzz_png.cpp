// Fuzz target: PNG bytes through decodePng, the decoder the replay-log reader uses for frames and
// masks. A decoded image must be consistent (size × channels bytes, 1 or 3 channels).
#include <span>

#include "fuzz_support.h"
#include "mapnav/core/error.h"
#include "mapnav/image/png.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace mapnav;
  try {
    const Image image = decodePng(std::span(data, size), "fuzz.png");
    fuzz::require(image.width > 0 && image.height > 0 && (image.channels == 1 || image.channels == 3) &&
                      image.data.size() == static_cast<std::size_t>(image.width) * image.height * image.channels,
                  "decodePng gave an inconsistent image");
  } catch (const InvalidInput&) {
  }
  return 0;
}
