// The most common image size (order-independent, ties settled by size) and fitting an image to a
// size at its right and bottom edges (chessboard photos of one camera, two 1 px larger).
#include <algorithm>

#include <gtest/gtest.h>

#include "mapnav/image/image.h"

namespace mapnav {
namespace {

TEST(MostCommonSize, TheSizeMostImagesHaveInAnyOrder) {
  std::vector<ImageSize> sizes{{1281, 721}, {1280, 720}, {1280, 720}, {1281, 721}, {1280, 720}, {640, 480}};
  std::sort(sizes.begin(), sizes.end());
  do {
    EXPECT_EQ(mostCommonSize(sizes), (ImageSize{1280, 720}));
  } while (std::next_permutation(sizes.begin(), sizes.end()));
  // A tie: the size of more pixels, then the wider.
  EXPECT_EQ(mostCommonSize({{640, 480}, {800, 600}}), (ImageSize{800, 600}));
  EXPECT_EQ(mostCommonSize({{600, 800}, {800, 600}}), (ImageSize{800, 600}));
  EXPECT_EQ(mostCommonSize({}), (ImageSize{0, 0}));
}

TEST(FitToSize, CutsOrPadsAtTheRightAndBottomKeepingPixelCoordinates) {
  Image image(3, 2, 1);
  for (std::size_t i = 0; i < image.data.size(); ++i) image.data[i] = static_cast<std::uint8_t>(10 + i);  // 10 11 12 / 13 14 15
  const Image cut = fitToSize(image, {2, 1});
  EXPECT_EQ(cut.data, (std::vector<std::uint8_t>{10, 11}));
  const Image padded = fitToSize(image, {4, 3});
  EXPECT_EQ(padded.data, (std::vector<std::uint8_t>{10, 11, 12, 0, 13, 14, 15, 0, 0, 0, 0, 0}));
  const Image both = fitToSize(image, {2, 3});
  EXPECT_EQ(both.data, (std::vector<std::uint8_t>{10, 11, 13, 14, 0, 0}));
  EXPECT_EQ(fitToSize(image, {3, 2}), image);
}

}  // namespace
}  // namespace mapnav
