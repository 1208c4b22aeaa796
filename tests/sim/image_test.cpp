#include "mapnav/sim/image.h"

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
    EXPECT_EQ(std::string(e.what()).rfind("frame 7: not a readable 8-bit PNG", 0), 0u) << e.what();
  }
  EXPECT_THROW(decodePng({}, "empty"), InvalidInput);
}

}  // namespace
}  // namespace mapnav
