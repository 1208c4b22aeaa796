// readImage (see read_image.h): the file's first bytes choose the decoder.
#include "mapnav/image/read_image.h"

#include <cstdint>
#include <span>
#include <string>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/image/jpeg.h"
#include "mapnav/image/png.h"

namespace mapnav {

Image readImage(const std::filesystem::path& path) {
  const std::string file = readFile(path);  // IoError naming the file
  const std::span bytes(reinterpret_cast<const std::uint8_t*>(file.data()), file.size());
  if (file.starts_with("\x89PNG")) return decodePng(bytes, path.string());
  if (file.starts_with("\xFF\xD8\xFF")) return decodeJpeg(bytes, path.string());
  throw InvalidInput(path.string() + ": neither a PNG nor a JPEG image (mapnav reads those two)");
}

}  // namespace mapnav
