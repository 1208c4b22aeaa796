#pragma once
// The body of the image decoders' fuzz targets (fuzz_png, fuzz_jpeg): the bytes either decode to a
// consistent image (size × channels bytes, 1 or 3 channels) or throw InvalidInput.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "fuzz_support.h"
#include "mapnav/core/error.h"
#include "mapnav/image/image.h"

namespace mapnav::fuzz {

template <class Decode>
void requireConsistentDecoding(const std::uint8_t* data, std::size_t size, Decode decode, const char* decoder) {
  try {
    const Image image = decode(std::span(data, size), "fuzz input");
    require(image.width > 0 && image.height > 0 && (image.channels == 1 || image.channels == 3) &&
                image.data.size() == static_cast<std::size_t>(image.width) * image.height * image.channels,
            (std::string(decoder) + " gave an inconsistent image").c_str());
  } catch (const InvalidInput&) {
  }
}

}  // namespace mapnav::fuzz
