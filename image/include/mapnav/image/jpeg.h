#pragma once
// JPEG decoding (libjpeg, kept inside image/src): photos, such as a chessboard's for calibration.
// mapnav writes no JPEG: its frames, masks and pictures are PNG, which is lossless.
#include <cstdint>
#include <span>
#include <string_view>

#include "mapnav/image/image.h"

namespace mapnav {

/// Decodes JPEG bytes: grey as 1 channel, colour (YCbCr or RGB) as 3-channel RGB, libjpeg's default
/// (accurate integer) inverse DCT and smooth chroma upsampling, so the pixels are those
/// cv::imdecode gives. The EXIF orientation is not applied. Throws InvalidInput starting with
/// `source` when the bytes are not a decodable JPEG, are CMYK, or claim more than kMaxImagePixels
/// pixels (refused before the pixels are decoded).
Image decodeJpeg(std::span<const std::uint8_t> bytes, std::string_view source);

}  // namespace mapnav
