#pragma once
// A plain 8-bit image, so that camera frames and masks cross module boundaries without OpenCV in
// any public header. Pixel (x, y): column x from the left, row y from the top.
#include <compare>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mapnav {

/// The largest image the decoders (decodePng, decodeJpeg) accept, in pixels (2^26: 8192 x 8192).
inline constexpr std::uint64_t kMaxImagePixels = std::uint64_t{1} << 26;

struct Image {
  int width = 0;
  int height = 0;
  int channels = 3;                 ///< 3: RGB, 1: grey (masks)
  std::vector<std::uint8_t> data;   ///< row-major, channels interleaved, no padding

  Image() = default;
  Image(int w, int h, int c) : width(w), height(h), channels(c), data(static_cast<std::size_t>(w) * h * c, 0) {}
  bool empty() const { return data.empty(); }
  std::uint8_t* pixel(int x, int y) { return data.data() + (static_cast<std::size_t>(y) * width + x) * channels; }
  const std::uint8_t* pixel(int x, int y) const {
    return data.data() + (static_cast<std::size_t>(y) * width + x) * channels;
  }
  bool operator==(const Image&) const = default;
};

/// An RGB copy of a grey image (each level copied to R, G and B); an RGB image as it is. The
/// vision pipelines take RGB; logs and real sequences may hold grey frames.
Image toRgb(Image image);
/// An RGB photo as a grey camera gives it to the pipelines: its luminance 0.299 R + 0.587 G +
/// 0.114 B, rounded, in every channel (`mapnav eval segmentation --grey`, `mapnav log
/// import-kitti-raw --grey`). Throws InvalidInput for an image that does not have 3 channels.
Image greyed(const Image& image);
/// Whether every pixel of an RGB frame has R = G = B (a grey camera's frame given as RGB, as toRgb
/// makes it).
bool isGreyFrame(const std::uint8_t* rgb, int width, int height);

/// An image size, width × height in pixels.
struct ImageSize {
  int width = 0, height = 0;
  auto operator<=>(const ImageSize&) const = default;
};
/// The size most of `sizes` have, whatever their order: among sizes of equal count the one of most
/// pixels, then the widest. {0, 0} when `sizes` is empty.
ImageSize mostCommonSize(const std::vector<ImageSize>& sizes);
/// `image` cut or padded (black) at its right and bottom edges to `size`, so that every pixel keeps
/// its coordinates (and a camera's principal point stays where it was).
Image fitToSize(const Image& image, ImageSize size);

}  // namespace mapnav
