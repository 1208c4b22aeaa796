// JPEG decoding (see jpeg.h) on libjpeg(-turbo). Like libpng (see png.cpp), libjpeg reports an
// error through a callback that must not return, so it longjmps to the setjmp of the member
// function that called libjpeg; those functions hold only plain data.
#include "mapnav/image/jpeg.h"

// clang-format off
#include <cstdio>  // jpeglib.h needs FILE and size_t first
#include <jpeglib.h>
// clang-format on

#include <array>
#include <csetjmp>
#include <new>
#include <string>

#include "claimed_size.h"
#include "mapnav/core/error.h"

namespace mapnav {

namespace {

struct ErrorHandler {
  jpeg_error_mgr base;  // first, so that libjpeg's pointer to it is one to the handler
  std::jmp_buf jump;
  std::array<char, JMSG_LENGTH_MAX> message;
};

[[noreturn]] void jpegFail(j_common_ptr info) {
  auto* handler = reinterpret_cast<ErrorHandler*>(info->err);
  (*info->err->format_message)(info, handler->message.data());
  std::longjmp(handler->jump, 1);
}

// libjpeg's warnings of corrupt data (level -1: a truncated file, a bad marker) would leave grey
// blocks in the image and go on; here they fail the decoding like its errors. Trace messages
// (levels 0 and up) are dropped.
void failOnCorruptData(j_common_ptr info, int level) {
  if (level < 0) jpegFail(info);
}

class JpegReader {
 public:
  explicit JpegReader(std::span<const std::uint8_t> bytes) {
    info_.err = jpeg_std_error(&handler_.base);
    handler_.base.error_exit = jpegFail;
    handler_.base.emit_message = failOnCorruptData;
    handler_.message[0] = '\0';
    if (setjmp(handler_.jump)) throw std::bad_alloc();  // jpeg_create_decompress fails only on memory
    jpeg_create_decompress(&info_);
    created_ = true;
    jpeg_mem_src(&info_, bytes.data(), static_cast<unsigned long>(bytes.size()));
  }
  ~JpegReader() {
    if (created_) jpeg_destroy_decompress(&info_);
  }
  JpegReader(const JpegReader&) = delete;
  JpegReader& operator=(const JpegReader&) = delete;

  /// Reads the header: the size and the number of channels the pixels will have (1 grey, 3 RGB,
  /// 4 for CMYK, which readRows does not take); false on a libjpeg error (message()).
  bool readHeader(int& width, int& height, int& channels) {
    if (setjmp(handler_.jump)) return false;
    jpeg_read_header(&info_, TRUE);
    width = static_cast<int>(info_.image_width);
    height = static_cast<int>(info_.image_height);
    channels = info_.num_components == 1 ? 1 : info_.num_components == 3 ? 3 : 4;
    info_.out_color_space = channels == 1 ? JCS_GRAYSCALE : JCS_RGB;
    return true;
  }

  /// Decodes every row into `image` (sized from readHeader); false on a libjpeg error.
  bool readRows(Image& image) {
    if (setjmp(handler_.jump)) return false;
    jpeg_start_decompress(&info_);
    while (info_.output_scanline < info_.output_height) {
      JSAMPROW row = image.pixel(0, static_cast<int>(info_.output_scanline));
      jpeg_read_scanlines(&info_, &row, 1);
    }
    jpeg_finish_decompress(&info_);
    return true;
  }

  const char* message() const { return handler_.message.data(); }

 private:
  ErrorHandler handler_{};
  jpeg_decompress_struct info_{};
  bool created_ = false;
};

}  // namespace

Image decodeJpeg(std::span<const std::uint8_t> bytes, std::string_view source) {
  if (bytes.size() < 3 || bytes[0] != 0xFF || bytes[1] != 0xD8 || bytes[2] != 0xFF) {
    throw InvalidInput(std::string(source) + ": not a JPEG image (no JPEG signature)");
  }
  JpegReader reader(bytes);
  const auto unreadable = [&] {
    return InvalidInput(std::string(source) + ": not a readable JPEG image (" + reader.message() + ")");
  };
  int width = 0, height = 0, channels = 0;
  if (!reader.readHeader(width, height, channels)) throw unreadable();
  detail::requireClaimedSize(static_cast<std::uint64_t>(width), static_cast<std::uint64_t>(height), "JPEG", source);
  if (channels == 4) throw InvalidInput(std::string(source) + ": a CMYK JPEG, which mapnav does not read");
  Image image(width, height, channels);
  if (!reader.readRows(image)) throw unreadable();
  return image;
}

}  // namespace mapnav
