// Image conversions that need no codec: grey to RGB, and the test for a grey frame given as RGB.
#include "mapnav/image/image.h"

namespace mapnav {

bool isGreyFrame(const std::uint8_t* rgb, int width, int height) {
  const std::size_t n = static_cast<std::size_t>(width) * height;
  for (std::size_t i = 0; i < n; ++i, rgb += 3)
    if (rgb[0] != rgb[1] || rgb[0] != rgb[2]) return false;
  return true;
}

Image toRgb(Image image) {
  if (image.channels == 3) return image;
  Image rgb(image.width, image.height, 3);
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t v = image.data[i * image.channels];
    rgb.data[3 * i] = rgb.data[3 * i + 1] = rgb.data[3 * i + 2] = v;
  }
  return rgb;
}

}  // namespace mapnav
