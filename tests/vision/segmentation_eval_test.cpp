// Segmentation scores on hand-made masks; every expected value is worked out by hand in the comments.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "mapnav/core/error.h"
#include "mapnav/testing/support.h"
#include "mapnav/vision/region.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision/segmentation_eval.h"

namespace mapnav {
namespace {

Image grey(int w, int h, std::vector<std::uint8_t> values) {
  Image im(w, h, 1);
  im.data = std::move(values);
  return im;
}

const LabelClasses kCamVid{{3, 4}, {11}};

// label    3  3  4 11      predicted  1 0 1 1
//          0  1  3  5                 1 0 0 0
// → TP (3,1) (4,1) = 2; FN (3,0) (3,0 bottom) = 2; FP (0,1) = 1; TN (1,0) (5,0) = 2; 11 ignored.
const Image kLabel = grey(4, 2, {3, 3, 4, 11, 0, 1, 3, 5});
const Image kPredicted = grey(4, 2, {255, 0, 255, 255, 255, 0, 0, 0});

TEST(SegmentationEval, CountsLeaveIgnoredPixelsOut) {
  const PixelCounts c = countPixels(kPredicted, kLabel, kCamVid);
  EXPECT_EQ(c.tp, 2u);
  EXPECT_EQ(c.fp, 1u);
  EXPECT_EQ(c.fn, 2u);
  EXPECT_EQ(c.tn, 2u);
  EXPECT_DOUBLE_EQ(*c.iou(), 2.0 / 5.0);
  EXPECT_DOUBLE_EQ(*c.precision(), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(*c.recall(), 2.0 / 4.0);
  // With road = 3 only, the 4 becomes a false positive: TP 1, FP 2, FN 2 → IoU 1/5.
  EXPECT_DOUBLE_EQ(*countPixels(kPredicted, kLabel, LabelClasses{{3}, {11}}).iou(), 1.0 / 5.0);
  // Nothing labelled and nothing predicted: IoU and recall undefined, not 0 or 1.
  const PixelCounts none = countPixels(grey(2, 1, {0, 0}), grey(2, 1, {1, 11}), kCamVid);
  EXPECT_FALSE(none.iou());
  EXPECT_FALSE(none.precision());
  EXPECT_FALSE(none.recall());
}

TEST(SegmentationEval, RejectsMismatchedInputs) {
  EXPECT_THROW(countPixels(grey(3, 2, std::vector<std::uint8_t>(6, 0)), kLabel, kCamVid), InvalidInput);
  EXPECT_THROW(countPixels(kPredicted, kLabel, LabelClasses{{}, {}}), InvalidInput);
  EXPECT_THROW(countPixels(kPredicted, kLabel, LabelClasses{{3}, {3}}), InvalidInput);
  EXPECT_THROW(countPixels(kPredicted, kLabel, LabelClasses{{300}, {}}), InvalidInput);
}

TEST(SegmentationEval, MaxFAndApFromScores) {
  // label  road road non road non ignored;  scores 200 100 150 50 10 255.
  // threshold in (150, 200]: TP 1 FP 0 FN 2: P 1,   R 1/3, F 1/2
  //           (100, 150]:    TP 1 FP 1 FN 2: P 1/2, R 1/3, F 2/5
  //            (50, 100]:    TP 2 FP 1 FN 1: P 2/3, R 2/3, F 2/3
  //            (10,  50]:    TP 3 FP 1 FN 0: P 3/4, R 1,   F 6/7   ← MaxF
  //             (0,  10]:    TP 3 FP 2 FN 0: P 3/5, R 1,   F 3/4
  // AP: recall levels 0, .1, .2, .3 reach precision 1; .4 ... 1 reach 3/4 → (4 + 7 · 3/4) / 11.
  ScoreHistogram h;
  h.add(grey(6, 1, {200, 100, 150, 50, 10, 255}), grey(6, 1, {3, 4, 0, 3, 7, 11}), kCamVid);
  const PixelCounts at60 = h.at(60);
  EXPECT_EQ(at60.tp, 2u);
  EXPECT_EQ(at60.fp, 1u);
  EXPECT_EQ(at60.fn, 1u);
  EXPECT_EQ(at60.tn, 1u);
  EXPECT_DOUBLE_EQ(*h.maxF(), 6.0 / 7.0);
  EXPECT_DOUBLE_EQ(*h.averagePrecision(), (4 + 7 * 0.75) / 11);
}

TEST(SegmentationEval, MaxFOfABinaryMaskIsItsF1) {
  // kPredicted as a 0/255 score: every threshold gives its P 2/3, R 1/2 → F1 = 2PR/(P+R) = 4/7.
  // AP: recall 1/2 reaches levels 0 ... .5 (6 of 11) at precision 2/3 → 6 · (2/3) / 11.
  ScoreHistogram h;
  h.add(kPredicted, kLabel, kCamVid);
  EXPECT_DOUBLE_EQ(*h.maxF(), 4.0 / 7.0);
  EXPECT_NEAR(*h.averagePrecision(), 6 * (2.0 / 3.0) / 11, 1e-12);
  EXPECT_FALSE(ScoreHistogram{}.maxF());
}

TEST(SegmentationEval, SummaryAccumulatesOverTheSet) {
  // a: TP 2 FP 1 FN 2 (IoU .4); b: TP 8 FP 0 FN 2 (IoU .8); c: no road, none predicted (undefined).
  // Set: TP 10 FP 1 FN 4 → IoU 10/15; precision 10/11; recall 10/14; median of {.4, .8} = .6.
  const std::vector<PixelCounts> per_image = {{2, 1, 2, 0}, {8, 0, 2, 5}, {0, 0, 0, 5}};
  const SegmentationScores s = summarize(per_image);
  EXPECT_EQ(s.images, 3);
  EXPECT_DOUBLE_EQ(*s.iou, 10.0 / 15.0);
  EXPECT_DOUBLE_EQ(*s.iou_median, 0.6);
  EXPECT_DOUBLE_EQ(*s.iou_worst, 0.4);
  EXPECT_DOUBLE_EQ(*s.precision, 10.0 / 11.0);
  EXPECT_DOUBLE_EQ(*s.recall, 10.0 / 14.0);
  EXPECT_FALSE(s.maxf);
  EXPECT_FALSE(s.ap);
}

TEST(SegmentationEval, OverlayColoursTpFpFnAndDarkensIgnored) {
  Image photo(4, 2, 3);
  std::fill(photo.data.begin(), photo.data.end(), 100);
  const Image o = drawSegmentationOverlay(photo, kPredicted, kLabel, kCamVid);
  auto rgb = [&](int x, int y) { return std::vector<int>(o.pixel(x, y), o.pixel(x, y) + 3); };
  EXPECT_EQ(rgb(0, 0), (std::vector<int>{50, 160, 50}));    // TP: (100 + (0, 220, 0)) / 2
  EXPECT_EQ(rgb(1, 0), (std::vector<int>{50, 90, 177}));    // FN: (100 + (0, 80, 255)) / 2
  EXPECT_EQ(rgb(0, 1), (std::vector<int>{177, 50, 50}));    // FP: (100 + (255, 0, 0)) / 2
  EXPECT_EQ(rgb(1, 1), (std::vector<int>{100, 100, 100}));  // TN untouched
  EXPECT_EQ(rgb(3, 0), (std::vector<int>{33, 33, 33}));     // ignored: a third
}

TEST(SegmentationEval, BottomTrapezoidInFractionsOfTheImage) {
  const Polygon2 t = bottomTrapezoid(480, 360);
  ASSERT_EQ(t.size(), 4u);
  EXPECT_DOUBLE_EQ(t[0].x(), 120);  // 480 / 2 - 0.5 · 480 / 2
  EXPECT_DOUBLE_EQ(t[0].y(), 352.8);  // 0.98 · 360
  EXPECT_DOUBLE_EQ(t[1].x(), 360);
  EXPECT_DOUBLE_EQ(t[2].x(), 288);  // 240 + 0.2 · 480 / 2
  EXPECT_DOUBLE_EQ(t[2].y(), 252);  // 0.7 · 360
  EXPECT_DOUBLE_EQ(t[3].x(), 192);
  EXPECT_THROW(bottomTrapezoid(480, 360, TrapezoidOptions{0.5, 0.6, 0.7, 0.98}), InvalidInput);
}

TEST(SegmentationEval, LargestRegionOutline) {
  // A 3 × 3 square at (1..3, 1..3) and a lone pixel at (6, 0): the square's corners, which fill back
  // to exactly its 9 pixels.
  Image mask(8, 5, 1);
  for (int y = 1; y <= 3; ++y)
    for (int x = 1; x <= 3; ++x) mask.pixel(x, y)[0] = 255;
  const Image square = mask;
  mask.pixel(6, 0)[0] = 255;
  const Polygon2 outline = largestRegionOutline(mask);
  ASSERT_EQ(outline.size(), 4u);
  for (const Vec2& p : outline) {
    EXPECT_TRUE(p.x() == 1 || p.x() == 3) << p.transpose();
    EXPECT_TRUE(p.y() == 1 || p.y() == 3) << p.transpose();
  }
  EXPECT_EQ(rasterizePolygon(outline, 8, 5), square);
  EXPECT_TRUE(largestRegionOutline(Image(4, 4, 1)).empty());
}


// The horizon of a camera tilted down by t is the row cy - fy tan t; the rows below it are ground.
TEST(SegmentationEval, GroundMaskIsTheRowsBelowTheHorizon) {
  for (const double tilt_deg : {0.0, 5.0, -2.0}) {
    const Image mask = groundMask(*testing::terregatorPinhole(tilt_deg));  // 512 x 480, fy 904, cy 239.5
    ASSERT_EQ(mask.width, 512);
    ASSERT_EQ(mask.height, 480);
    const double horizon = 239.5 - 904.0 * std::tan(tilt_deg * std::numbers::pi / 180.0);  // 239.5, 160.4, 271.1
    for (int v = 0; v < 480; ++v) {
      const std::uint8_t expected = v > horizon ? 255 : 0;
      for (int u = 0; u < 512; ++u) ASSERT_EQ(mask.pixel(u, v)[0], expected) << "tilt " << tilt_deg << " row " << v;
    }
  }
}

}  // namespace
}  // namespace mapnav
