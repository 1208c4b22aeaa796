// Images at another size, with OpenCV's resampling (resize.h).
#include "mapnav/vision/resize.h"

#include <cstdint>

#include <opencv2/imgproc.hpp>

#include "cv_view.h"
#include "mapnav/core/error.h"
#include "mapnav/core/strprintf.h"

namespace mapnav {

Image resized(const Image& image, ImageSize size, ResizeKind kind) {
  if (image.empty() || (image.channels != 1 && image.channels != 3)) {
    throw InvalidInput("resized: the image must be non-empty with 1 or 3 channels");
  }
  if (size.width < 1 || size.height < 1 ||
      static_cast<std::uint64_t>(size.width) * static_cast<std::uint64_t>(size.height) > kMaxImagePixels) {
    throw InvalidInput(strprintf("resized: %dx%d is not an image size (1 px to %llu px)", size.width, size.height,
                                 static_cast<unsigned long long>(kMaxImagePixels)));
  }
  Image out(size.width, size.height, image.channels);
  const bool shrinking = size.width * size.height < image.width * image.height;
  const int interpolation = kind == ResizeKind::Labels ? cv::INTER_NEAREST : shrinking ? cv::INTER_AREA : cv::INTER_LINEAR;
  cv::Mat target = cvview::view(out);
  cv::resize(cvview::view(image), target, target.size(), 0, 0, interpolation);
  return out;
}

}  // namespace mapnav
