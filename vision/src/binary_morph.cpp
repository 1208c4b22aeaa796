#include "binary_morph.h"

#include <algorithm>
#include <optional>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace mapnav::detail {

namespace {

// Half-widths of the kernel's rows (index: row), or nothing when the fast path does not apply.
std::optional<std::vector<int>> rowHalfWidths(const cv::Mat& kernel) {
  if (kernel.type() != CV_8UC1 || kernel.rows % 2 == 0 || kernel.cols % 2 == 0) return std::nullopt;
  const int cy = kernel.rows / 2, cx = kernel.cols / 2;
  std::vector<int> half(static_cast<std::size_t>(kernel.rows), -1);
  for (int y = 0; y < kernel.rows; ++y) {
    int first = -1, last = -1, count = 0;
    for (int x = 0; x < kernel.cols; ++x) {
      if (kernel.at<std::uint8_t>(y, x) == 0) continue;
      if (first < 0) first = x;
      last = x;
      ++count;
    }
    if (count == 0 || count != last - first + 1 || first != 2 * cx - last) return std::nullopt;  // gap / asymmetric
    half[static_cast<std::size_t>(y)] = cx - first;
  }
  for (int d = 1; d <= cy; ++d) {  // symmetric in rows, never wider away from the centre row
    const int up = half[static_cast<std::size_t>(cy - d)], down = half[static_cast<std::size_t>(cy + d)];
    if (up != down || up > half[static_cast<std::size_t>(cy - d + 1)]) return std::nullopt;
  }
  return half;
}

// dst = 255 where every kernel pixel over the image is set in `src` (non-zero; with `invert`, zero),
// else 0. Pixels outside the image are ignored, which for such kernels equals OpenCV's replicated
// border. The kernel is the union of its rows: each row of the output is the AND of the rows around
// it, each eroded horizontally by its kernel row's half-width (byte loops, vectorised; built for AVX2
// too where the processor has it).
__attribute__((target_clones("avx2", "default"))) void erodeRows(const cv::Mat& src, cv::Mat& dst, const std::vector<int>& half, bool invert) {
  const int w = src.cols, h = src.rows, r = static_cast<int>(half.size()) / 2;
  std::vector<int> levels(half);
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  const int widest = levels.back();
  // Horizontal erosions, one image per distinct half-width.
  std::vector<cv::Mat> eroded(levels.size());
  for (cv::Mat& m : eroded) m.create(h, w, CV_8UC1);
  // The row padded by `widest` on both sides (outside = set), then ANDs of runs of 2, 4, 8, ...
  // pixels: a run of any length is the AND of two overlapping power-of-two runs.
  const int padded = w + 2 * widest;
  int steps = 0;
  while ((2 << steps) <= 2 * widest + 1) ++steps;
  std::vector<std::vector<std::uint8_t>> runs(static_cast<std::size_t>(steps) + 1,
                                              std::vector<std::uint8_t>(static_cast<std::size_t>(padded), 255));
  const std::uint8_t on = invert ? 0 : 255, off = invert ? 255 : 0;
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* s = src.ptr<std::uint8_t>(y);
    std::uint8_t* __restrict base = runs[0].data() + widest;
    for (int x = 0; x < w; ++x) base[x] = s[x] != 0 ? on : off;
    for (int k = 1; k <= steps; ++k) {
      const std::uint8_t* __restrict a = runs[static_cast<std::size_t>(k - 1)].data();
      std::uint8_t* __restrict b = runs[static_cast<std::size_t>(k)].data();
      const int half_run = 1 << (k - 1);
      for (int i = 0; i + 2 * half_run <= padded; ++i) b[i] = a[i] & a[i + half_run];
    }
    for (std::size_t l = 0; l < levels.size(); ++l) {
      const int t = levels[l];
      std::uint8_t* __restrict o = eroded[l].ptr<std::uint8_t>(y);
      int k = 0;
      while ((2 << k) <= 2 * t + 1) ++k;
      const std::uint8_t* __restrict lo = runs[static_cast<std::size_t>(k)].data() + widest - t;
      const std::uint8_t* __restrict hi = runs[static_cast<std::size_t>(k)].data() + widest + t - (1 << k) + 1;
      for (int x = 0; x < w; ++x) o[x] = lo[x] & hi[x];
    }
  }
  std::vector<const cv::Mat*> of_row(half.size());
  for (std::size_t k = 0; k < half.size(); ++k)
    of_row[k] = &eroded[static_cast<std::size_t>(std::lower_bound(levels.begin(), levels.end(), half[k]) - levels.begin())];
  // `src` is no longer read: the output goes straight into dst (its own pixels when it already has the
  // size, e.g. a view of an Image, or src itself).
  dst.create(h, w, CV_8UC1);
  for (int y = 0; y < h; ++y) {
    std::uint8_t* __restrict o = dst.ptr<std::uint8_t>(y);
    std::fill(o, o + w, std::uint8_t{255});
    for (int dy = -r; dy <= r; ++dy) {
      if (y + dy < 0 || y + dy >= h) continue;
      const std::uint8_t* __restrict e = of_row[static_cast<std::size_t>(dy + r)]->ptr<std::uint8_t>(y + dy);
      for (int x = 0; x < w; ++x) o[x] &= e[x];
    }
    if (invert)
      for (int x = 0; x < w; ++x) o[x] = static_cast<std::uint8_t>(~o[x]);
  }
}

// A mask that is all set or all clear stays as it is (outside pixels being ignored).
bool uniform(const cv::Mat& src, cv::Mat& dst) {
  const int set = cv::countNonZero(src);
  if (set != 0 && static_cast<std::size_t>(set) != src.total()) return false;
  dst.create(src.size(), CV_8UC1);
  dst.setTo(cv::Scalar(set == 0 ? 0 : 255));
  return true;
}

}  // namespace

void erodeBinary(const cv::Mat& src, cv::Mat& dst, const cv::Mat& kernel) {
  const auto half = rowHalfWidths(kernel);
  if (!half || src.type() != CV_8UC1 || src.empty()) {
    cv::erode(src, dst, kernel, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
    return;
  }
  if (!uniform(src, dst)) erodeRows(src, dst, *half, false);
}

void dilateBinary(const cv::Mat& src, cv::Mat& dst, const cv::Mat& kernel) {
  const auto half = rowHalfWidths(kernel);
  if (!half || src.type() != CV_8UC1 || src.empty()) {
    cv::dilate(src, dst, kernel);
    return;
  }
  if (!uniform(src, dst)) erodeRows(src, dst, *half, true);  // dilate(M) = ~erode(~M), symmetric kernel
}

void closeOpenBinary(cv::Mat& mask, const cv::Mat& kernel) {
  dilateBinary(mask, mask, kernel);
  erodeBinary(mask, mask, kernel);
  erodeBinary(mask, mask, kernel);
  dilateBinary(mask, mask, kernel);
}

}  // namespace mapnav::detail
