#pragma once
// OpenCV headers over mapnav Images (internal to vision/): no copy, so a view lives no longer than
// its image's pixels and sees every change to them.
#include <opencv2/core.hpp>

#include "mapnav/image/image.h"

namespace mapnav::cvview {

/// `image`'s pixels as a cv::Mat of CV_8UC1, CV_8UC3 or CV_8UC4 by its channels (1, 3, 4).
inline cv::Mat view(Image& image) {
  const int type = image.channels == 1 ? CV_8UC1 : image.channels == 3 ? CV_8UC3 : CV_8UC4;
  return cv::Mat(image.height, image.width, type, image.data.data());
}
/// The same over a const image, for OpenCV's inputs (what OpenCV only reads).
inline cv::Mat view(const Image& image) { return view(const_cast<Image&>(image)); }

}  // namespace mapnav::cvview
