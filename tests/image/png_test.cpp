#include "mapnav/image/png.h"

#include <gtest/gtest.h>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

TEST(Png, RgbAndGreyImagesRoundTripExactly) {
  const auto dir = testing::freshTempDir();
  Image rgb(5, 3, 3);
  for (std::size_t i = 0; i < rgb.data.size(); ++i) rgb.data[i] = static_cast<std::uint8_t>(i * 17);
  writePng(rgb, dir / "rgb.png");
  EXPECT_EQ(readPng(dir / "rgb.png"), rgb);
  Image grey(4, 4, 1);
  grey.pixel(2, 1)[0] = 255;
  writePng(grey, dir / "grey.png");
  EXPECT_EQ(readPng(dir / "grey.png"), grey);
  EXPECT_EQ(rgb.pixel(1, 0)[0], 3 * 17);  // pixel (1, 0) starts at byte 3
}

TEST(Png, CorruptOrMissingFilesAreNamedErrors) {
  const auto dir = testing::freshTempDir();
  writeFileAtomic(dir / "bad.png", std::string_view("\x89PNG\r\n\x1a\n truncated"));
  try {
    readPng(dir / "bad.png");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("bad.png"), std::string::npos);
  }
  EXPECT_THROW(readPng(dir / "missing.png"), IoError);
}

TEST(Png, BytesInMemoryDecodeAsTheFileWouldAndErrorsNameTheGivenSource) {
  Image rgb(3, 2, 3);
  for (std::size_t i = 0; i < rgb.data.size(); ++i) rgb.data[i] = static_cast<std::uint8_t>(200 - i * 9);
  EXPECT_EQ(decodePng(encodePng(rgb), "memory"), rgb);
  const std::string_view text = "not a PNG";
  try {
    decodePng(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), "frame 7");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "frame 7: not a PNG image (no PNG signature)");
  }
  EXPECT_THROW(decodePng({}, "empty"), InvalidInput);
  // A PNG signature with a chunk that is not an image.
  std::vector<std::uint8_t> broken = encodePng(rgb);
  broken.resize(40);
  EXPECT_THROW(decodePng(broken, "cut"), InvalidInput);
}

// Found with fuzz_png: a few bytes claiming a huge image made the decoder allocate it
// (gigabytes) before finding the pixel data missing; and imdecode tried every codec, not only PNG.
TEST(Png, AHeaderClaimingMoreThanTheLimitIsRefusedBeforeDecoding) {
  std::vector<std::uint8_t> png = encodePng(Image(2, 2, 1));
  for (std::size_t at : {16u, 20u}) {  // IHDR width and height: 30000 = 0x7530, big-endian
    png[at] = 0;
    png[at + 1] = 0;
    png[at + 2] = 0x75;
    png[at + 3] = 0x30;
  }
  try {
    decodePng(png, "huge.png");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "huge.png: the PNG claims 30000 x 30000 pixels, more than the 67108864 mapnav reads");
  }
  const std::string_view bmp = std::string_view("BM\x3a\0\0\0\0\0\0\0\x36\0\0\0\x28\0\0\0\x01\0\0\0\x01\0\0\0\x01\0\x18\0", 30);
  EXPECT_THROW(decodePng(std::span(reinterpret_cast<const std::uint8_t*>(bmp.data()), bmp.size()), "b.bmp"), InvalidInput);
}

}  // namespace
}  // namespace mapnav
