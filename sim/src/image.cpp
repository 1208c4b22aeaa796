#include "mapnav/sim/image.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstring>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"

namespace mapnav {

namespace {

cv::Mat toMat(const Image& image) {
  const cv::Mat view(image.height, image.width, image.channels == 1 ? CV_8UC1 : CV_8UC3,
                     const_cast<std::uint8_t*>(image.data.data()));
  cv::Mat bgr;
  if (image.channels == 3) {
    cv::cvtColor(view, bgr, cv::COLOR_RGB2BGR);
  } else {
    bgr = view.clone();
  }
  return bgr;
}

}  // namespace

std::vector<std::uint8_t> encodePng(const Image& image) {
  if (image.empty() || (image.channels != 1 && image.channels != 3)) {
    throw InvalidInput("encodePng: an image needs 1 or 3 channels and a size, got " + std::to_string(image.width) +
                       "x" + std::to_string(image.height) + "x" + std::to_string(image.channels));
  }
  std::vector<std::uint8_t> bytes;
  cv::imencode(".png", toMat(image), bytes);
  return bytes;
}

void writePng(const Image& image, const std::filesystem::path& path) {
  const std::vector<std::uint8_t> bytes = encodePng(image);
  writeFileAtomic(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

Image readPng(const std::filesystem::path& path) {
  const std::string bytes = readFile(path);
  return decodePng(std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), path.string());
}

Image decodePng(std::span<const std::uint8_t> bytes, std::string_view source) {
  cv::Mat decoded;
  try {
    decoded = cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<std::uint8_t*>(bytes.data())),
                           cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
    decoded = cv::Mat();
  }
  if (decoded.empty() || decoded.depth() != CV_8U) {
    throw InvalidInput(std::string(source) + ": not a readable 8-bit PNG image (corrupt or another format)");
  }
  cv::Mat rgb;
  int channels = 3;
  switch (decoded.channels()) {
    case 1:
      rgb = decoded;
      channels = 1;
      break;
    case 3: cv::cvtColor(decoded, rgb, cv::COLOR_BGR2RGB); break;
    case 4: cv::cvtColor(decoded, rgb, cv::COLOR_BGRA2RGB); break;
    default: throw InvalidInput(std::string(source) + ": unsupported number of channels " + std::to_string(decoded.channels()));
  }
  Image image(rgb.cols, rgb.rows, channels);
  for (int y = 0; y < rgb.rows; ++y) {
    std::memcpy(image.pixel(0, y), rgb.ptr(y), static_cast<std::size_t>(rgb.cols) * channels);
  }
  return image;
}

}  // namespace mapnav
