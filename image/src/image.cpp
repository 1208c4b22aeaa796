// Image conversions that need no codec: grey to RGB, RGB to a grey camera's, and the test for a grey
// frame given as RGB.
#include "mapnav/image/image.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "mapnav/core/error.h"

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

Image greyed(const Image& image) {
  if (image.channels != 3) throw InvalidInput("greyed: expected a 3-channel photo, got " + std::to_string(image.channels) + " channels");
  Image out = image;
  for (std::size_t i = 0; i < out.data.size(); i += 3) {
    const double y = 0.299 * image.data[i] + 0.587 * image.data[i + 1] + 0.114 * image.data[i + 2];
    out.data[i] = out.data[i + 1] = out.data[i + 2] = static_cast<std::uint8_t>(std::lround(y));
  }
  return out;
}

ImageSize mostCommonSize(const std::vector<ImageSize>& sizes) {
  std::map<ImageSize, int> count;
  for (const ImageSize& s : sizes) ++count[s];
  ImageSize best;
  int best_count = 0;
  auto pixels = [](const ImageSize& s) { return static_cast<long long>(s.width) * s.height; };
  for (const auto& [size, n] : count) {  // in size order, so ties are settled the same way every time
    if (n > best_count || (n == best_count && (pixels(size) > pixels(best) ||
                                               (pixels(size) == pixels(best) && size.width > best.width)))) {
      best = size;
      best_count = n;
    }
  }
  return best;
}

Image fitToSize(const Image& image, ImageSize size) {
  Image out(size.width, size.height, image.channels);
  const int w = std::min(size.width, image.width), h = std::min(size.height, image.height);
  for (int y = 0; y < h; ++y) std::copy_n(image.pixel(0, y), static_cast<std::size_t>(w) * image.channels, out.pixel(0, y));
  return out;
}

}  // namespace mapnav
