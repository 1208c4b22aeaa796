#pragma once
// mapnav's one PNG codec (OpenCV's, kept inside image/src): camera frames, masks and logs, and the
// pictures render::Canvas draws.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>
#include <vector>

#include "mapnav/image/image.h"

namespace mapnav {

/// The largest image decodePng accepts, in pixels (2^26: 8192 x 8192).
inline constexpr std::uint64_t kMaxPngPixels = std::uint64_t{1} << 26;

/// How encodePng compresses. Each setting gives the same bytes every time for the same image.
enum class PngCompression {
  Fast,      ///< zlib level 1, run-length strategy (OpenCV's default): frames and masks, written often
  Balanced,  ///< zlib level 3, default strategy: render::Canvas's pictures, smaller
};

/// Decodes PNG bytes (8-bit grey or RGB; RGBA loses its alpha). Throws InvalidInput starting with
/// `source` (the file name, for messages) when they are not a decodable PNG, or when its header
/// claims more than kMaxPngPixels pixels (refused before any decoding).
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
