// The PNG codec (see png.h) on libpng. Not on OpenCV's imgcodecs: that library brings GDAL and some
// 110 other shared libraries, whose loading cost every mapnav process (each test, each command)
// 0.14 s before main, 0.4 s under the sanitizers.
//
// libpng reports an error by longjmp to the setjmp of the function that called it. So each function
// here that calls libpng arms its own setjmp and holds only plain data (no destructors to skip); the
// structs are owned by the RAII classes around them and the pixels live in the caller's Image.
#include "mapnav/image/png.h"

#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <new>
#include <string>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "claimed_size.h"

namespace mapnav {

namespace {

// libpng's message for the exception, kept in the struct's error pointer until libpng longjmps.
using Message = std::array<char, 256>;

[[noreturn]] void pngFail(png_structp png, png_const_charp text) {
  Message& message = *static_cast<Message*>(png_get_error_ptr(png));
  std::snprintf(message.data(), message.size(), "%s", text);
  png_longjmp(png, 1);
}

void pngIgnoreWarning(png_structp, png_const_charp) {}

struct MemoryInput {
  std::span<const std::uint8_t> bytes;
  std::size_t at = 0;
};

void readFromMemory(png_structp png, png_bytep out, png_size_t count) {
  MemoryInput& in = *static_cast<MemoryInput*>(png_get_io_ptr(png));
  if (count > in.bytes.size() - in.at) png_error(png, "the data ends before the image does");
  std::memcpy(out, in.bytes.data() + in.at, count);
  in.at += count;
}

void appendToVector(png_structp png, png_bytep data, png_size_t count) {
  auto& out = *static_cast<std::vector<std::uint8_t>*>(png_get_io_ptr(png));
  try {
    out.insert(out.end(), data, data + count);
  } catch (const std::bad_alloc&) {
    png_error(png, "out of memory");  // an exception must not cross libpng's C frames
  }
}

void noFlush(png_structp) {}

/// libpng's reading of one PNG in memory, as 8-bit grey or RGB: fewer bits are expanded, a palette
/// becomes RGB, alpha (and grey with alpha, as RGB) is dropped, and no gamma is applied: OpenCV's
/// cv::imdecode(IMREAD_UNCHANGED) then RGB, pixel for pixel.
class PngReader {
 public:
  explicit PngReader(std::span<const std::uint8_t> bytes) : input_{bytes} {
    png_ = png_create_read_struct(PNG_LIBPNG_VER_STRING, &message_, pngFail, pngIgnoreWarning);
    if (png_ != nullptr) info_ = png_create_info_struct(png_);
    if (png_ == nullptr || info_ == nullptr) throw std::bad_alloc();
    png_set_read_fn(png_, &input_, readFromMemory);
  }
  ~PngReader() { png_destroy_read_struct(&png_, &info_, nullptr); }
  PngReader(const PngReader&) = delete;
  PngReader& operator=(const PngReader&) = delete;

  struct Header {
    int width = 0, height = 0;
    int bit_depth = 0;  ///< as stored; 16 is not read (readRows)
    int channels = 0;   ///< after the transformations: 1 or 3
  };

  /// Reads the header and sets the transformations; false on a libpng error (message()).
  bool readHeader(Header& header) {
    if (setjmp(png_jmpbuf(png_))) return false;
    png_read_info(png_, info_);
    const png_byte type = png_get_color_type(png_, info_);
    header.bit_depth = png_get_bit_depth(png_, info_);
    if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png_);
    if (type == PNG_COLOR_TYPE_GRAY && header.bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png_);
    if (type == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png_);
    png_set_strip_alpha(png_);
    passes_ = png_set_interlace_handling(png_);
    png_read_update_info(png_, info_);
    header.width = static_cast<int>(png_get_image_width(png_, info_));
    header.height = static_cast<int>(png_get_image_height(png_, info_));
    header.channels = png_get_channels(png_, info_);
    return true;
  }

  /// Reads every row into `image` (sized from readHeader); false on a libpng error.
  bool readRows(Image& image) {
    if (setjmp(png_jmpbuf(png_))) return false;
    for (int pass = 0; pass < passes_; ++pass) {
      for (int y = 0; y < image.height; ++y) png_read_row(png_, image.pixel(0, y), nullptr);
    }
    png_read_end(png_, nullptr);
    return true;
  }

  const char* message() const { return message_.data(); }

 private:
  MemoryInput input_;
  Message message_{};
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
  int passes_ = 1;
};

class PngWriter {
 public:
  PngWriter() {
    png_ = png_create_write_struct(PNG_LIBPNG_VER_STRING, &message_, pngFail, pngIgnoreWarning);
    if (png_ != nullptr) info_ = png_create_info_struct(png_);
    if (png_ == nullptr || info_ == nullptr) throw std::bad_alloc();
  }
  ~PngWriter() { png_destroy_write_struct(&png_, &info_); }
  PngWriter(const PngWriter&) = delete;
  PngWriter& operator=(const PngWriter&) = delete;

  /// Encodes `image` into `out`; false on a libpng error (message()). The settings are OpenCV's
  /// cv::imencode(".png") ones, so the bytes are those it wrote: Fast is its default (only the Sub
  /// filter, zlib level 1, run-length strategy), Balanced its IMWRITE_PNG_COMPRESSION = 3 (every
  /// filter, level 3, default strategy).
  bool write(const Image& image, PngCompression compression, std::vector<std::uint8_t>& out) {
    if (setjmp(png_jmpbuf(png_))) return false;
    png_set_write_fn(png_, &out, appendToVector, noFlush);
    if (compression == PngCompression::Fast) {
      png_set_filter(png_, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
      png_set_compression_level(png_, Z_BEST_SPEED);
      png_set_compression_strategy(png_, Z_RLE);
    } else {
      png_set_compression_level(png_, 3);
      png_set_compression_strategy(png_, Z_DEFAULT_STRATEGY);
    }
    png_set_IHDR(png_, info_, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
                 image.channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png_, info_);
    for (int y = 0; y < image.height; ++y) png_write_row(png_, image.pixel(0, y));
    png_write_end(png_, info_);
    return true;
  }

  const char* message() const { return message_.data(); }

 private:
  Message message_{};
  png_structp png_ = nullptr;
  png_infop info_ = nullptr;
};

}  // namespace

std::vector<std::uint8_t> encodePng(const Image& image, PngCompression compression) {
  if (image.empty() || (image.channels != 1 && image.channels != 3)) {
    throw InvalidInput("encodePng: an image needs 1 or 3 channels and a size, got " + std::to_string(image.width) +
                       "x" + std::to_string(image.height) + "x" + std::to_string(image.channels));
  }
  std::vector<std::uint8_t> bytes;
  PngWriter writer;
  if (!writer.write(image, compression, bytes)) throw Error(std::string("encodePng: ") + writer.message());
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
  // Only a PNG whose header claims a sane size goes to the decoder: a 100-byte file can claim
  // 30000 x 30000 pixels, which would be allocated before the data is found missing. The IHDR chunk
  // comes first: after the 8-byte signature, its length and type (8 bytes), then width and height,
  // 4 bytes each, big-endian.
  static constexpr std::array<std::uint8_t, 8> kSignature{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < 24 || !std::equal(kSignature.begin(), kSignature.end(), bytes.begin())) {
    throw InvalidInput(std::string(source) + ": not a PNG image (no PNG signature)");
  }
  const auto be32 = [&](std::size_t at) {
    return std::uint64_t{bytes[at]} << 24 | std::uint64_t{bytes[at + 1]} << 16 | std::uint64_t{bytes[at + 2]} << 8 |
           std::uint64_t{bytes[at + 3]};
  };
  detail::requireClaimedSize(be32(16), be32(20), "PNG", source);
  PngReader reader(bytes);
  const auto unreadable = [&] {
    return InvalidInput(std::string(source) + ": not a readable 8-bit PNG image (" + reader.message() + ")");
  };
  PngReader::Header header;
  if (!reader.readHeader(header)) throw unreadable();
  if (header.bit_depth == 16) {
    throw InvalidInput(std::string(source) + ": a 16-bit PNG (a depth map?); mapnav reads 8-bit images");
  }
  if (header.channels != 1 && header.channels != 3) {
    throw InvalidInput(std::string(source) + ": unsupported number of channels " + std::to_string(header.channels));
  }
  Image image(header.width, header.height, header.channels);
  if (!reader.readRows(image)) throw unreadable();
  return image;
}

}  // namespace mapnav
