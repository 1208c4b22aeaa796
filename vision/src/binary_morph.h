#pragma once
// Binary erosion and dilation by a structuring element that is symmetric and convex row by row
// (OpenCV's MORPH_RECT and MORPH_ELLIPSE): the same answer as cv::erode / cv::dilate with
// BORDER_REPLICATE or the default border, computed as the AND of horizontally eroded rows (byte loops
// the compiler vectorises) instead of OpenCV's pass per kernel pixel (~140 for a 13 × 13 disk).
// Private to vision/ (OpenCV types).
#include <opencv2/core.hpp>

namespace mapnav::detail {

/// `src`: CV_8UC1, non-zero = set (the masks here hold 0 / 255). `dst` gets 0 / 255 (into its own pixels
/// when it already has src's size and type) and may be `src`. Any other kernel (not
/// symmetric, a row with a gap, widths growing away from the centre row) falls back to cv::erode.
void erodeBinary(const cv::Mat& src, cv::Mat& dst, const cv::Mat& kernel);
/// The dilation, under the same conditions (falls back to cv::dilate).
void dilateBinary(const cv::Mat& src, cv::Mat& dst, const cv::Mat& kernel);
/// Closing then opening (cv::morphologyEx MORPH_CLOSE then MORPH_OPEN, one iteration each).
void closeOpenBinary(cv::Mat& mask, const cv::Mat& kernel);

}  // namespace mapnav::detail
