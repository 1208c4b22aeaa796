// Scoring in a bird's-eye grid on a hand-made camera; every expected value is worked out by hand in
// the comments.
#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <string>

#include "mapnav/core/error.h"
#include "mapnav/vision/bev_eval.h"
#include "mapnav/vision/segmentation_eval.h"

namespace mapnav {
namespace {

// A level pin-hole 1 m above the ground, 7 × 4 pixels, f = 2 px, principal point (3, 1): a ground
// point x m right of the camera and z m ahead projects to u = 3 + 2x / z, v = 1 + 2 / z. The image
// covers u in [−0.5, 6.5], v in [−0.5, 3.5]; the horizon is row 1.
std::unique_ptr<Camera> levelCamera(double forward_offset_m = 0.0) {
  CameraIntrinsics in;
  in.width = 7;
  in.height = 4;
  in.fx = in.fy = 2.0;
  in.cx = 3.0;
  in.cy = 1.0;
  CameraMount mount;
  mount.offset = Vec2(forward_offset_m, 0.0);
  mount.height_m = 1.0;
  mount.tilt_rad = 0.0;
  return createCamera(LensModel::Pinhole, in, mount);
}

// x −4..4, z 0..8, 2 m cells: 4 columns with centres x = −3, −1, 1, 3 (left to right) and 4 rows with
// centres z = 7, 5, 3, 1 (far first).
//   z = 7: v = 1.286 → row 1; u = 3 ∓ 0.857, 3 ∓ 0.286 → 2.143, 2.714, 3.286, 3.857 → 2, 3, 3, 4
//   z = 5: v = 1.4   → row 1; u = 1.8, 2.6, 3.4, 4.2                                  → 2, 3, 3, 4
//   z = 3: v = 1.667 → row 2; u = 1, 2.333, 3.667, 5                                  → 1, 2, 4, 5
//   z = 1: v = 3     → row 3; u = −3 (outside), 1, 5, 9 (outside)
// Pixel index v · 7 + u.
const BevGrid kGrid{-4.0, 4.0, 0.0, 8.0, 2.0};
const std::vector<std::int32_t> kPixelOfCell = {9, 10, 10, 11, 9, 10, 10, 11, 15, 16, 18, 19, -1, 22, 26, -1};

TEST(BevEval, GridCellsLookUpTheNearestPixel) {
  EXPECT_EQ(kGrid.columns(), 4);
  EXPECT_EQ(kGrid.rows(), 4);
  const BevSampling s = bevSampling(*levelCamera(), kGrid);
  EXPECT_EQ(s.columns, 4);
  EXPECT_EQ(s.rows, 4);
  EXPECT_EQ(s.pixel_of_cell, kPixelOfCell);
  EXPECT_EQ(s.samples, (PixelSamples{9, 10, 10, 11, 9, 10, 10, 11, 15, 16, 18, 19, 22, 26}));
  // The grid is measured from the ground below the camera, not from the vehicle's reference point.
  EXPECT_EQ(bevSampling(*levelCamera(0.7), kGrid).pixel_of_cell, kPixelOfCell);
}

// KITTI's grid: 20 m / 0.05 = 400 columns, 40 m / 0.05 = 800 rows.
TEST(BevEval, KittiDefaultsAndBadGrids) {
  const BevGrid kitti;
  EXPECT_EQ(kitti.columns(), 400);
  EXPECT_EQ(kitti.rows(), 800);
  EXPECT_NO_THROW(kitti.validate());
  const auto fails = [](BevGrid g, const std::string& field) {
    try {
      g.validate();
      ADD_FAILURE() << "no error for " << field;
    } catch (const InvalidInput& e) {
      EXPECT_EQ(std::string(e.what()).rfind("BevGrid::" + field + " = ", 0), 0u) << e.what();
    }
  };
  fails({-10, 10, 6, 46, 0.0}, "cell_m");
  fails({10, -10, 6, 46, 0.05}, "x_max_m");
  fails({-10, 10, 46, 46, 0.05}, "z_max_m");
  fails({-10, 10, 6, 46, 0.001}, "cell_m");  // 20000 × 40000 cells
  fails({-10, 10, 6, 46, 50.0}, "cell_m");   // round(20 / 50) = 0 columns
  fails({-10, std::numeric_limits<double>::infinity(), 6, 46, 0.05}, "x_max_m");
}

// KITTI's grid on the camera `mapnav log import-kitti` makes of kitti_vo_seq1 (calib.txt P0: f 707.0912,
// principal point (601.8873, 183.1104), 1226 × 370, 1.65 m up, level). Counted independently (Python,
// u = cx + f x / z, v = cy + f h / z over the 320000 cell centres, in [−0.5, 1225.5] × [−0.5, 369.5]):
// 308301 cells in the image; the nearest rows (z < 6.26 m) fall below its bottom edge.
TEST(BevEval, KittiGridOnTheKittiCamera) {
  CameraIntrinsics in;
  in.width = 1226;
  in.height = 370;
  in.fx = in.fy = 707.0912;
  in.cx = 601.8873;
  in.cy = 183.1104;
  CameraMount mount;
  mount.height_m = 1.65;
  mount.tilt_rad = 0.0;
  const BevSampling s = bevSampling(*createCamera(LensModel::Pinhole, in, mount), BevGrid{});
  EXPECT_EQ(s.samples.size(), 308301u);
  // Row 799 (z = 6.025 m) projects to v = 183.11 + 707.09 · 1.65 / 6.025 = 376.8: below the image.
  EXPECT_EQ(s.pixel_of_cell[799 * 400 + 200], -1);
  // Row 0 (z = 45.975 m), column 200 (x = 0.025 m): u = 602.27 → 602, v = 208.49 → 208.
  EXPECT_EQ(s.pixel_of_cell[200], 208 * 1226 + 602);
}

// label (0 non-road, 1 road, 2 ignored)   predicted (1 road)
//   row 1: u 2, 3 road; u 4 non-road        u 2, 3, 4 road
//   row 2: u 1 non-road; 2, 4 road; 5 ign.  u 2, 5 road
//   row 3: u 1 road; u 5 non-road           u 5 road
// every other pixel non-road, not predicted.
Image grey(int w, int h) { return Image(w, h, 1); }
void set(Image& im, int index, std::uint8_t value) { im.data[static_cast<std::size_t>(index)] = value; }

Image handLabel() {
  Image l = grey(7, 4);
  for (const int i : {9, 10, 16, 18, 22}) set(l, i, 1);
  set(l, 19, 2);
  return l;
}

const LabelClasses kClasses{{1}, {2}};

// Per cell (far row first): 9 TP, 10 TP, 10 TP, 11 FP | the same | 15 TN, 16 TP, 18 FN, 19 ignored |
// outside, 22 FN, 26 FP, outside → TP 7, FP 3, FN 2, TN 1: IoU 7/12. Per pixel the same images give
// TP 3 (9, 10, 16), FP 2 (11, 26), FN 2 (18, 22), TN 20 (28 less those 7 and the ignored 19): IoU 3/7.
TEST(BevEval, CountsOneSamplePerCell) {
  Image predicted = grey(7, 4);
  for (const int i : {9, 10, 11, 16, 19, 26}) set(predicted, i, 255);
  const BevSampling s = bevSampling(*levelCamera(), kGrid);
  const PixelCounts bev = countPixels(predicted, handLabel(), kClasses, &s.samples);
  EXPECT_EQ(bev.tp, 7u);
  EXPECT_EQ(bev.fp, 3u);
  EXPECT_EQ(bev.fn, 2u);
  EXPECT_EQ(bev.tn, 1u);
  EXPECT_DOUBLE_EQ(*bev.iou(), 7.0 / 12.0);
  const PixelCounts image = countPixels(predicted, handLabel(), kClasses);
  EXPECT_EQ(image.tp, 3u);
  EXPECT_EQ(image.fp, 2u);
  EXPECT_EQ(image.fn, 2u);
  EXPECT_EQ(image.tn, 20u);
  // A sample outside the image is an error, not a read past its end.
  const PixelSamples bad = {3, 28};
  EXPECT_THROW(countPixels(predicted, handLabel(), kClasses, &bad), InvalidInput);
}

// Scores at the sampled pixels: 9 → 200, 10 → 150, 11 → 100, 15 → 50, 16 → 250, 18 → 20, 22 → 120,
// 26 → 180 (19 ignored). Counting each pixel once per cell: road 250 ×1, 200 ×2, 150 ×4, 120 ×1,
// 20 ×1 (9 in all); non-road 180 ×1, 100 ×2, 50 ×1 (4).
//   t in (200, 250]: TP 1 FP 0  P 1     R 1/9
//   t in (180, 200]: TP 3 FP 0  P 1     R 1/3
//   t in (150, 180]: TP 3 FP 1  P 3/4   R 1/3
//   t in (120, 150]: TP 7 FP 1  P 7/8   R 7/9   F 14/17
//   t in (100, 120]: TP 8 FP 1  P 8/9   R 8/9   F 8/9   ← MaxF
//   t in (50, 100]:  TP 8 FP 3  P 8/11  R 8/9   F 4/5
//   t in (20, 50]:   TP 8 FP 4  P 2/3   R 8/9
//   t in [1, 20]:    TP 9 FP 4  P 9/13  R 1     F 9/11
// AP: recall 0 to 0.3 → precision 1 (4 levels); 0.4 to 0.8 → 8/9 (5); 0.9 and 1 → 9/13 (2).
TEST(BevEval, MaxFAndApOverCells) {
  Image score = grey(7, 4);
  const std::pair<int, std::uint8_t> scores[] = {{9, 200},  {10, 150}, {11, 100}, {15, 50},
                                                 {16, 250}, {18, 20},  {22, 120}, {26, 180}};
  for (const auto& [i, v] : scores) set(score, i, v);
  const BevSampling s = bevSampling(*levelCamera(), kGrid);
  ScoreHistogram h;
  h.add(score, handLabel(), kClasses, &s.samples);
  const PixelCounts at110 = h.at(110);
  EXPECT_EQ(at110.tp, 8u);
  EXPECT_EQ(at110.fp, 1u);
  EXPECT_EQ(at110.fn, 1u);
  EXPECT_NEAR(*h.maxF(), 8.0 / 9.0, 1e-12);
  EXPECT_NEAR(*h.averagePrecision(), (4.0 + 5.0 * 8.0 / 9.0 + 2.0 * 9.0 / 13.0) / 11.0, 1e-12);
  // The summary takes them from the same histogram.
  const SegmentationScores sum = summarize({at110}, &h);
  EXPECT_NEAR(*sum.maxf, 8.0 / 9.0, 1e-12);
}

// Resampled for an overlay: each cell its pixel's value, far row at the top, cells outside 0.
TEST(BevEval, ResampledImageIsTheGridSeenFromAbove) {
  Image im = grey(7, 4);
  for (int i = 0; i < 28; ++i) set(im, i, static_cast<std::uint8_t>(100 + i));
  const BevSampling s = bevSampling(*levelCamera(), kGrid);
  const Image bev = resampleToBev(im, s);
  ASSERT_EQ(bev.width, 4);
  ASSERT_EQ(bev.height, 4);
  EXPECT_EQ(bev.data, (std::vector<std::uint8_t>{109, 110, 110, 111, 109, 110, 110, 111, 115, 116, 118, 119, 0, 122,
                                                  126, 0}));
  EXPECT_THROW(resampleToBev(grey(3, 3), s), InvalidInput);
}

}  // namespace
}  // namespace mapnav
