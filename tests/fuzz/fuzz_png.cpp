// Fuzz target: PNG bytes through decodePng, the decoder the replay-log reader uses for frames and
// masks.
#include "fuzz_image.h"
#include "mapnav/image/png.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mapnav::fuzz::requireConsistentDecoding(data, size, mapnav::decodePng, "decodePng");
  return 0;
}
