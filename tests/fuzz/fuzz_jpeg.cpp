// Fuzz target: JPEG bytes through decodeJpeg, the decoder of photos (`mapnav calibrate`,
// `mapnav rectify`).
#include "fuzz_image.h"
#include "mapnav/image/jpeg.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mapnav::fuzz::requireConsistentDecoding(data, size, mapnav::decodeJpeg, "decodeJpeg");
  return 0;
}
