// Images at another size (vision/resize.h): photos averaged over the pixels they shrink from,
// labels by their nearest pixel, and the frame scale the pipelines' pixel options follow.
#include "mapnav/vision/resize.h"

#include <gtest/gtest.h>

#include <cmath>

#include "mapnav/core/error.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {
namespace {

// A 4 x 2 photo halved to 2 x 1: each pixel the mean of its 2 x 2 block, by hand.
TEST(Resize, AShrunkPhotoAveragesEachBlock) {
  Image photo(4, 2, 3);
  const int levels[2][4] = {{0, 40, 100, 100}, {80, 120, 200, 0}};
  for (int v = 0; v < 2; ++v)
    for (int u = 0; u < 4; ++u)
      for (int c = 0; c < 3; ++c) photo.pixel(u, v)[c] = static_cast<std::uint8_t>(levels[v][u] + c);
  const Image half = resized(photo, {2, 1}, ResizeKind::Photo);
  ASSERT_EQ(half.width, 2);
  ASSERT_EQ(half.height, 1);
  ASSERT_EQ(half.channels, 3);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(half.pixel(0, 0)[c], 60 + c);   // (0 + 40 + 80 + 120) / 4
    EXPECT_EQ(half.pixel(1, 0)[c], 100 + c);  // (100 + 100 + 200 + 0) / 4
  }
}

// Labels doubled keep their class indices, each pixel copied to a 2 x 2 block; halved, one of the
// block's own values (never a mean that is no class).
TEST(Resize, LabelsKeepTheirClassIndices) {
  Image labels(2, 1, 1);
  labels.pixel(0, 0)[0] = 3;
  labels.pixel(1, 0)[0] = 11;
  const Image twice = resized(labels, {4, 2}, ResizeKind::Labels);
  for (int v = 0; v < 2; ++v)
    for (int u = 0; u < 4; ++u) EXPECT_EQ(twice.pixel(u, v)[0], u < 2 ? 3 : 11) << u << "," << v;
  const Image back = resized(twice, {2, 1}, ResizeKind::Labels);
  EXPECT_EQ(back, labels);
  EXPECT_THROW(resized(labels, {0, 5}, ResizeKind::Labels), InvalidInput);
  EXPECT_THROW(resized(Image(), {4, 4}, ResizeKind::Photo), InvalidInput);
}

// The pipelines' lengths in pixels follow sqrt(area / (480 x 360)) below that size and stay above.
TEST(Resize, ThePixelScaleIsTheSquareRootOfTheAreaRatioBelowTheReference) {
  EXPECT_DOUBLE_EQ(pixelScale(480, 360), 1.0);
  EXPECT_DOUBLE_EQ(pixelScale(240, 180), 0.5);
  EXPECT_DOUBLE_EQ(pixelScale(320, 240), std::sqrt(320.0 * 240 / (480.0 * 360)));
  EXPECT_DOUBLE_EQ(pixelScale(1280, 720), 1.0);
  EXPECT_DOUBLE_EQ(pixelScale(1242, 375), 1.0);
  EXPECT_DOUBLE_EQ(pixelScale(0, 0), 1.0);
}

}  // namespace
}  // namespace mapnav
