#pragma once
// mapnav's one PNG codec (libpng, kept inside image/src): camera frames, masks and logs, and the
// pictures render::Canvas draws.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>
#include <vector>

#include "mapnav/image/image.h"

namespace mapnav {

/// How encodePng compresses. Each setting gives the same bytes every time for the same image.
enum class PngCompression {
  Fast,      ///< Sub filter, zlib level 1, run-length strategy: frames and masks, written often
  Balanced,  ///< every filter, zlib level 3, default strategy: render::Canvas's pictures, smaller
};

/// Decodes PNG bytes into 8-bit grey or RGB: fewer bits are expanded, a palette becomes RGB, alpha
/// is dropped (grey with alpha becomes RGB), no gamma is applied. Throws InvalidInput starting with
/// `source` (the file name, for messages) when they are not a decodable PNG, are 16-bit, or when
/// the header claims more than kMaxImagePixels pixels (refused before any decoding).
Image decodePng(std::span<const std::uint8_t> bytes, std::string_view source);
/// decodePng on a file. Throws IoError when the file cannot be read, InvalidInput naming the file
/// when it is not a decodable PNG.
Image readPng(const std::filesystem::path& path);
/// Writes a PNG atomically (deterministic bytes for the same image). Throws IoError.
void writePng(const Image& image, const std::filesystem::path& path);
/// PNG bytes in memory (1 or 3 channels). Throws InvalidInput for an empty image or another number
/// of channels, Error when the encoder fails.
std::vector<std::uint8_t> encodePng(const Image& image, PngCompression compression = PngCompression::Fast);

}  // namespace mapnav
