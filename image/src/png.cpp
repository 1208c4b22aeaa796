// The PNG codec (see png.h): OpenCV's imgcodecs, whose types stay in this file.
#include "mapnav/image/png.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cstring>
#include <string>

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

std::vector<std::uint8_t> encodePng(const Image& image, PngCompression compression) {
  if (image.empty() || (image.channels != 1 && image.channels != 3)) {
    throw InvalidInput("encodePng: an image needs 1 or 3 channels and a size, got " + std::to_string(image.width) +
                       "x" + std::to_string(image.height) + "x" + std::to_string(image.channels));
  }
  // No parameters is OpenCV's fast setting; naming a level also switches to zlib's default strategy.
  std::vector<int> params;
  if (compression == PngCompression::Balanced) params = {cv::IMWRITE_PNG_COMPRESSION, 3};
  std::vector<std::uint8_t> bytes;
  bool encoded = false;
  try {
    encoded = cv::imencode(".png", toMat(image), bytes, params);
  } catch (const cv::Exception& e) {
    throw Error(std::string("encodePng: ") + e.what());
  }
  if (!encoded) throw Error("encodePng: PNG encoding failed");
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
  // Only PNG goes to the decoder (cv::imdecode would try every codec OpenCV has), and only one whose
  // header claims a sane size: a 100-byte file can claim 30000 x 30000 pixels, which the decoder
  // allocates before it finds the data missing. The IHDR chunk comes first: after the 8-byte
  // signature, its length and type (8 bytes), then width and height, 4 bytes each, big-endian.
  static constexpr std::array<std::uint8_t, 8> kSignature{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < 24 || !std::equal(kSignature.begin(), kSignature.end(), bytes.begin())) {
    throw InvalidInput(std::string(source) + ": not a PNG image (no PNG signature)");
  }
  const auto be32 = [&](std::size_t at) {
    return std::uint64_t{bytes[at]} << 24 | std::uint64_t{bytes[at + 1]} << 16 | std::uint64_t{bytes[at + 2]} << 8 |
           std::uint64_t{bytes[at + 3]};
  };
  if (be32(16) * be32(20) > kMaxPngPixels) {
    throw InvalidInput(std::string(source) + ": the PNG claims " + std::to_string(be32(16)) + " x " +
                       std::to_string(be32(20)) + " pixels, more than the " + std::to_string(kMaxPngPixels) +
                       " mapnav reads");
  }
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
