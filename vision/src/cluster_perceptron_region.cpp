// The "cluster-perceptron" pipeline's road region and per-pixel road confidence, from the perceptron's
// per-pixel output (beyond the paper, whose answer is the centre line alone). See cluster_perceptron.h.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "cluster_perceptron_internal.h"
#include "cv_view.h"
#include "mapnav/core/error.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav {

std::optional<PerceptronRegion> perceptronRegion(const Image& certainty, const Image& ground, const Image& seed) {
  const int w = certainty.width, h = certainty.height;
  if (certainty.channels != 1 || ground.channels != 1 || seed.channels != 1 || ground.width != w ||
      ground.height != h || seed.width != w || seed.height != h)
    throw InvalidInput("perceptronRegion: the certainty, ground and seed masks must be 1-channel images of one size");
  // Road: the perceptron's decision (certainty > 127), where the camera sees the ground.
  cv::Mat road(h, w, CV_8UC1);
  for (std::size_t i = 0; i < certainty.data.size(); ++i)
    road.data[i] = certainty.data[i] > 127 && ground.data[i] != 0 ? 255 : 0;
  cv::Mat labels;
  const int n = cv::connectedComponents(road, labels, 8, CV_32S);
  if (n < 2) return std::nullopt;
  // The component the seed overlaps most.
  std::vector<long> overlap(static_cast<std::size_t>(n), 0);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
      if (seed.pixel(u, v)[0] != 0) ++overlap[static_cast<std::size_t>(labels.at<int>(v, u))];
  overlap[0] = 0;  // not road
  const auto best = static_cast<int>(std::max_element(overlap.begin(), overlap.end()) - overlap.begin());
  if (overlap[static_cast<std::size_t>(best)] == 0) return std::nullopt;
  PerceptronRegion out;
  out.mask = Image(w, h, 1);
  cv::Mat m = cvview::view(out.mask);
  m.setTo(255, labels == best);
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(m.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  if (contours.empty()) return std::nullopt;
  const auto largest = std::max_element(contours.begin(), contours.end(), [](const auto& a, const auto& b) {
    return cv::contourArea(a) < cv::contourArea(b);
  });
  std::vector<cv::Point> poly;
  cv::approxPolyDP(*largest, poly, 1.0, true);
  if (poly.size() < 3) return std::nullopt;
  for (const cv::Point& p : poly) out.outline.emplace_back(p.x, p.y);
  return out;
}

Image smoothCertainty(const Image& certainty, int radius) {
  if (radius <= 0) return certainty;
  Image out = certainty;
  cv::blur(cvview::view(certainty), cvview::view(out), cv::Size(2 * radius + 1, 2 * radius + 1), cv::Point(-1, -1),
           cv::BORDER_REPLICATE);
  return out;
}

Image perceptronConfidence(const Image& certainty, const Image& ground, const Image& region) {
  Image out(certainty.width, certainty.height, 1);
  for (std::size_t i = 0; i < out.data.size(); ++i) {
    if (ground.data[i] == 0) continue;
    const int c = certainty.data[i];  // 0..240, 16 apart
    out.data[i] = static_cast<std::uint8_t>(region.data[i] != 0 && c > 127 ? 129 + (126 * (c - 128) + 56) / 112
                                                                           : (64 * c + 120) / 240);
  }
  return out;
}

}  // namespace mapnav
