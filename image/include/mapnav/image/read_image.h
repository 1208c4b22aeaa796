#pragma once
// Reading an image file whatever its format (PNG or JPEG), for commands that take photos.
#include <filesystem>

#include "mapnav/image/image.h"

namespace mapnav {

/// A PNG (decodePng) or JPEG (decodeJpeg) file, told apart by its first bytes, not its name: grey
/// as 1 channel, colour as RGB. Throws IoError when the file cannot be read, InvalidInput naming the
/// file when it is neither or cannot be decoded.
Image readImage(const std::filesystem::path& path);

}  // namespace mapnav
