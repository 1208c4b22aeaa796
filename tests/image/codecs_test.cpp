// mapnav's codecs (libpng, libjpeg) against OpenCV's imgcodecs, which mapnav used before and which
// stays the reference here only: the same bytes out of encodePng, the same pixels out of the
// decoders. Then the errors of decodeJpeg and readImage (decodePng's are in png_test.cpp).
#include <png.h>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/image/jpeg.h"
#include "mapnav/image/png.h"
#include "mapnav/image/read_image.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

// A seeded image with smooth regions and noise, as camera frames and masks have both.
Image testImage(int width, int height, int channels, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(-6, 6);
  Image image(width, height, channels);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < channels; ++c) {
        const int smooth = (x * (c + 1) * 3 + y * 2) % 256;
        image.pixel(x, y)[c] = static_cast<std::uint8_t>(std::clamp(smooth + noise(rng), 0, 255));
      }
    }
  }
  return image;
}

// OpenCV's matrix of an Image: BGR for colour.
cv::Mat toBgr(const Image& image) {
  const cv::Mat view(image.height, image.width, image.channels == 1 ? CV_8UC1 : CV_8UC3,
                     const_cast<std::uint8_t*>(image.data.data()));
  cv::Mat out;
  if (image.channels == 1) return view.clone();
  cv::cvtColor(view, out, cv::COLOR_RGB2BGR);
  return out;
}

// OpenCV's decoding of `bytes` as mapnav's decoders give it: grey stays grey, colour as RGB.
Image openCvDecode(std::span<const std::uint8_t> bytes, int flags) {
  const cv::Mat decoded = cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8UC1,
                                               const_cast<std::uint8_t*>(bytes.data())),
                                       flags);
  EXPECT_FALSE(decoded.empty());
  cv::Mat rgb;
  if (decoded.channels() == 1) {
    rgb = decoded;
  } else {
    cv::cvtColor(decoded, rgb, decoded.channels() == 4 ? cv::COLOR_BGRA2RGB : cv::COLOR_BGR2RGB);
  }
  Image image(rgb.cols, rgb.rows, rgb.channels());
  for (int y = 0; y < rgb.rows; ++y) std::copy(rgb.ptr(y), rgb.ptr(y) + rgb.cols * rgb.channels(), image.pixel(0, y));
  return image;
}

std::vector<std::uint8_t> openCvEncode(const Image& image, const char* extension, std::vector<int> params = {}) {
  std::vector<std::uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(extension, toBgr(image), bytes, params));
  return bytes;
}

TEST(PngReference, EncodedBytesAreOpenCvsForBothCompressions) {
  for (int channels : {1, 3}) {
    const Image image = testImage(97, 61, channels, 7u + static_cast<unsigned>(channels));
    EXPECT_EQ(encodePng(image, PngCompression::Fast), openCvEncode(image, ".png")) << channels << " channels";
    EXPECT_EQ(encodePng(image, PngCompression::Balanced), openCvEncode(image, ".png", {cv::IMWRITE_PNG_COMPRESSION, 3}))
        << channels << " channels";
  }
}

// A PNG of any colour type and depth, written with libpng directly (OpenCV writes none with a
// palette, grey with alpha, or interlacing). `samples` holds the rows as libpng takes them.
std::vector<std::uint8_t> libpngEncode(int width, int height, int bit_depth, int color_type, bool interlaced,
                                       const std::vector<std::uint8_t>& samples, int row_bytes) {
  std::vector<std::uint8_t> out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    ADD_FAILURE() << "libpng failed to write the test PNG";
    return {};
  }
  png_set_write_fn(
      png, &out,
      [](png_structp p, png_bytep data, png_size_t n) {
        auto* v = static_cast<std::vector<std::uint8_t>*>(png_get_io_ptr(p));
        v->insert(v->end(), data, data + n);
      },
      nullptr);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), bit_depth, color_type,
               interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  std::vector<png_color> palette;
  if (color_type == PNG_COLOR_TYPE_PALETTE) {
    for (int i = 0; i < 256; ++i) palette.push_back({static_cast<png_byte>(i), static_cast<png_byte>(255 - i),
                                                     static_cast<png_byte>(i * 7)});
    png_set_PLTE(png, info, palette.data(), 256);
  }
  png_write_info(png, info);
  std::vector<png_bytep> rows;
  for (int y = 0; y < height; ++y) rows.push_back(const_cast<std::uint8_t*>(samples.data()) + y * row_bytes);
  png_write_image(png, rows.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return out;
}

TEST(PngReference, EveryColourTypeAndDepthDecodesToOpenCvsPixels) {
  const int w = 23, h = 17;
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> byte(0, 255);
  struct Case {
    const char* name;
    int bit_depth, color_type, samples_per_pixel;
    bool interlaced;
    int expected_channels;
  };
  const Case cases[] = {
      {"grey 8", 8, PNG_COLOR_TYPE_GRAY, 1, false, 1},     {"grey 1", 1, PNG_COLOR_TYPE_GRAY, 1, false, 1},
      {"grey 4", 4, PNG_COLOR_TYPE_GRAY, 1, false, 1},
      {"grey+alpha", 8, PNG_COLOR_TYPE_GRAY_ALPHA, 2, false, 3}, {"rgb 8", 8, PNG_COLOR_TYPE_RGB, 3, false, 3},
      {"rgba 8", 8, PNG_COLOR_TYPE_RGBA, 4, false, 3},
      {"palette", 8, PNG_COLOR_TYPE_PALETTE, 1, false, 3}, {"rgb interlaced", 8, PNG_COLOR_TYPE_RGB, 3, true, 3},
  };
  for (const Case& c : cases) {
    const int row_bytes = (w * c.samples_per_pixel * c.bit_depth + 7) / 8;
    std::vector<std::uint8_t> samples(static_cast<std::size_t>(row_bytes) * h);
    for (std::uint8_t& s : samples) s = static_cast<std::uint8_t>(byte(rng));
    const std::vector<std::uint8_t> png = libpngEncode(w, h, c.bit_depth, c.color_type, c.interlaced, samples, row_bytes);
    const Image ours = decodePng(png, c.name);
    EXPECT_EQ(ours.channels, c.expected_channels) << c.name;
    EXPECT_EQ(ours, openCvDecode(png, cv::IMREAD_UNCHANGED)) << c.name;
  }
}

TEST(JpegReference, ColourAndGreyDecodeToOpenCvsPixels) {
  for (int channels : {1, 3}) {
    const Image image = testImage(64, 48, channels, 21u + static_cast<unsigned>(channels));
    const std::vector<std::uint8_t> jpeg = openCvEncode(image, ".jpg", {cv::IMWRITE_JPEG_QUALITY, 90});
    const Image ours = decodeJpeg(jpeg, "frame.jpg");
    EXPECT_EQ(ours.channels, channels);
    EXPECT_EQ(ours, openCvDecode(jpeg, cv::IMREAD_UNCHANGED)) << channels << " channels";
    // Lossy, but close to what was encoded on average (garbage would be ~80 off): quality 90 drops
    // much of the ±6 noise, and the wraps from 255 to 0 ring.
    double error = 0;
    for (std::size_t i = 0; i < image.data.size(); ++i) error += std::abs(ours.data[i] - image.data[i]);
    EXPECT_LT(error / static_cast<double>(image.data.size()), 10.0);
  }
}

TEST(JpegReference, TheRealCalibrationPhotosDecodeToOpenCvsPixels) {
  ASSERT_TRUE(testing::realDataPresent("calibration"));
  for (const char* name : {"calibration1.jpg", "calibration7.jpg"}) {
    const std::string bytes = readFile(testing::realDataPath("calibration") / name);
    const std::span jpeg(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    const Image ours = decodeJpeg(jpeg, name);
    EXPECT_EQ(ours.channels, 3) << name;
    EXPECT_EQ(ours, openCvDecode(jpeg, cv::IMREAD_COLOR)) << name;
  }
}

TEST(Png, SixteenBitImagesAreRefusedByName) {
  const std::vector<std::uint8_t> samples(2 * 3 * 2, 0x80);
  const std::vector<std::uint8_t> png = libpngEncode(3, 2, 16, PNG_COLOR_TYPE_GRAY, false, samples, 6);
  try {
    decodePng(png, "depth.png");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "depth.png: a 16-bit PNG (a depth map?); mapnav reads 8-bit images");
  }
}

TEST(Jpeg, BadBytesAreNamedErrors) {
  const std::vector<std::uint8_t> jpeg = openCvEncode(testImage(40, 30, 3, 5), ".jpg");
  const auto message = [](std::span<const std::uint8_t> bytes) {
    try {
      decodeJpeg(bytes, "photo.jpg");
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string_view text = "GIF89a";
  EXPECT_EQ(message(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size())),
            "photo.jpg: not a JPEG image (no JPEG signature)");
  // Cut in the middle of the pixel data: libjpeg's warning, an error here.
  const std::string cut = message(std::span(jpeg).first(jpeg.size() / 2));
  EXPECT_EQ(cut.rfind("photo.jpg: not a readable JPEG image (", 0), 0u) << cut;
  // The frame header (SOF0: FF C0, length, precision, then height and width, big-endian) claiming
  // 30000 x 30000 pixels.
  std::vector<std::uint8_t> huge = jpeg;
  std::size_t sof = 2;
  while (sof + 1 < huge.size() && !(huge[sof] == 0xFF && huge[sof + 1] == 0xC0)) ++sof;
  ASSERT_LT(sof + 9, huge.size());
  for (std::size_t at : {sof + 5, sof + 7}) {
    huge[at] = 0x75;
    huge[at + 1] = 0x30;
  }
  EXPECT_EQ(message(huge), "photo.jpg: the JPEG claims 30000 x 30000 pixels, more than the 67108864 mapnav reads");
}

TEST(ReadImage, TellsPngFromJpegByTheBytesAndNamesTheFileOtherwise) {
  const auto dir = testing::freshTempDir();
  const Image grey = testImage(16, 12, 1, 3);
  writePng(grey, dir / "grey.jpg");  // a PNG, whatever its name says
  EXPECT_EQ(readImage(dir / "grey.jpg"), grey);
  const std::vector<std::uint8_t> jpeg = openCvEncode(testImage(16, 12, 3, 4), ".jpg");
  writeFileAtomic(dir / "photo.png", std::string_view(reinterpret_cast<const char*>(jpeg.data()), jpeg.size()));
  EXPECT_EQ(readImage(dir / "photo.png"), decodeJpeg(jpeg, "photo"));
  writeFileAtomic(dir / "notes.txt", "not an image");
  try {
    readImage(dir / "notes.txt");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "notes.txt").string() + ": neither a PNG nor a JPEG image (mapnav reads those two)");
  }
  EXPECT_THROW(readImage(dir / "missing.jpg"), IoError);
}

}  // namespace
}  // namespace mapnav
