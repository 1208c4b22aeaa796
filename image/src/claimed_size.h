#pragma once
// The decoders' one size check, made on the size a file's header claims, before any pixel is
// allocated (a 100-byte file can claim 30000 x 30000 pixels).
#include <cstdint>
#include <string>
#include <string_view>

#include "mapnav/core/error.h"
#include "mapnav/image/image.h"

namespace mapnav::detail {

/// Throws InvalidInput starting with `source` when width x height exceeds kMaxImagePixels.
inline void requireClaimedSize(std::uint64_t width, std::uint64_t height, std::string_view format,
                               std::string_view source) {
  if (width * height <= kMaxImagePixels) return;
  throw InvalidInput(std::string(source) + ": the " + std::string(format) + " claims " + std::to_string(width) +
                     " x " + std::to_string(height) + " pixels, more than the " + std::to_string(kMaxImagePixels) +
                     " mapnav reads");
}

}  // namespace mapnav::detail
