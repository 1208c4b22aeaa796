#include "mapnav/vision/calibrate.h"
#include "mapnav/testing/support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/image/read_image.h"
#include "mapnav/vision/rectify.h"

#include <Eigen/Eigenvalues>

namespace mapnav {
namespace {


Segment2 imageOf(const Camera& camera, const Vec2& a, const Vec2& b) {
  const auto pa = camera.projectGround(a);
  const auto pb = camera.projectGround(b);
  EXPECT_TRUE(pa && pb);
  return {*pa, *pb};
}

// --- tilt from the vanishing line -------------------------------------------------------------------

class TiltFromParallelLines : public ::testing::TestWithParam<double> {};

TEST_P(TiltFromParallelLines, RecoversTheTiltWithinAFifthOfADegree) {
  const double tilt = GetParam();
  const auto camera = testing::terregatorPinhole(tilt);
  // The "hood ornament": two poles 2.5 m apart, from 3 to 20 m ahead.
  const Segment2 a = imageOf(*camera, {3, 1.25}, {20, 1.25});
  const Segment2 b = imageOf(*camera, {3, -1.25}, {20, -1.25});
  const double est = radToDeg(tiltFromParallelLines(camera->intrinsics(), a, b));
  std::printf("tilt %.2f deg: recovered %.6f deg (error %.2e deg)\n", tilt, est, est - tilt);
  EXPECT_NEAR(est, tilt, 0.2);
  EXPECT_NEAR(est, tilt, 1e-6);

  // ±0.3 px of noise on the end points.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.3, 0.3);
  double worst = 0;
  for (int trial = 0; trial < 20; ++trial) {
    auto jitter = [&](Segment2 s) {
      s.a += Vec2(noise(rng), noise(rng));
      s.b += Vec2(noise(rng), noise(rng));
      return s;
    };
    const double noisy = radToDeg(tiltFromParallelLines(camera->intrinsics(), jitter(a), jitter(b)));
    worst = std::max(worst, std::abs(noisy - tilt));
  }
  std::printf("tilt %.2f deg with +-0.3 px end point noise: worst error %.4f deg over 20 trials\n", tilt, worst);
  EXPECT_LE(worst, 0.2);
}

INSTANTIATE_TEST_SUITE_P(Tilts, TiltFromParallelLines, ::testing::Values(18.5, 25.0));

TEST(TiltFromParallelLinesAnyDirection, LinesAtAnAngleToTheVehicleGiveTheSameTilt) {
  const auto camera = testing::terregatorPinhole(18.5);
  // Two parallel lines heading 20 degrees left of forward.
  const Vec2 d = unitVector(degToRad(20.0));
  const Vec2 n = leftNormal(d);
  const Segment2 a = imageOf(*camera, Vec2(4, 0) + n, Vec2(4, 0) + n + 12 * d);
  const Segment2 b = imageOf(*camera, Vec2(4, 0) - n, Vec2(4, 0) - n + 12 * d);
  EXPECT_NEAR(radToDeg(tiltFromParallelLines(camera->intrinsics(), a, b)), 18.5, 1e-6);
}

TEST(TiltFromParallelLinesAnyDirection, RemovesLensDistortionFirst) {
  CameraIntrinsics in = testing::terregatorPinhole(22.0)->intrinsics();
  in.distortion = {-0.2, 0.05, 0.0, 0.0, 0.0};
  CameraMount mount;
  mount.tilt_rad = degToRad(22.0);
  const auto camera = createCamera(LensModel::Pinhole, in, mount);
  const Segment2 a = imageOf(*camera, {4, 1.0}, {14, 1.0});
  const Segment2 b = imageOf(*camera, {4, -1.0}, {14, -1.0});
  EXPECT_NEAR(radToDeg(tiltFromParallelLines(in, a, b)), 22.0, 0.01);
}

TEST(TiltFromParallelLinesAnyDirection, ParallelImageLinesAreRejected) {
  CameraIntrinsics in;
  EXPECT_THROW((void)tiltFromParallelLines(in, {{0, 0}, {0, 10}}, {{5, 0}, {5, 10}}), InvalidInput);
  EXPECT_THROW((void)tiltFromParallelLines(in, {{0, 0}, {0, 0}}, {{5, 0}, {5, 10}}), InvalidInput);
}

// --- scale factors from metre sticks --------------------------------------------------------------

TEST(ScaleFromSticks, AxisAlignedSticksHandComputed) {
  // A 1 m stick along x spans 50 rows; a 1 m stick along y spans 40 columns.
  const ScaleFactors s = scaleFromSticks({{100, 200}, {100, 150}}, 1.0, {{80, 300}, {120, 300}}, 1.0);
  EXPECT_NEAR(s.x_m_per_px, 0.02, 1e-12);
  EXPECT_NEAR(s.y_m_per_px, 0.025, 1e-12);
}

TEST(ScaleFromSticks, SlightlyOffAxisSticksHandComputed) {
  // True scales 0.02 m/px (x, rows) and 0.025 m/px (y, columns). The x stick: 48 rows and 10
  // columns: sqrt((48·0.02)² + (10·0.025)²) = sqrt(0.9216 + 0.0625) = sqrt(0.9841) m. The y stick:
  // 4 rows and 36 columns: sqrt(0.0064 + 0.81) = sqrt(0.8164) m.
  const ScaleFactors s =
      scaleFromSticks({{10, 10}, {20, 58}}, std::sqrt(0.9841), {{50, 50}, {86, 54}}, std::sqrt(0.8164));
  EXPECT_NEAR(s.x_m_per_px, 0.02, 1e-12);
  EXPECT_NEAR(s.y_m_per_px, 0.025, 1e-12);
}

TEST(ScaleFromSticks, MeasuredInARectifiedImage) {
  // Metre sticks at known ground positions, located in the rectified image by the rectifier's own
  // grid: the scale is the grid's metres_per_pixel.
  const auto camera = testing::terregatorPinhole(22.0);
  RectifyOptions options;
  options.metres_per_pixel = 0.025;
  const Rectifier rect(*camera, options);
  const Segment2 x_stick{rect.pixelAt({5.0, 0.3}), rect.pixelAt({6.0, 0.3})};
  const Segment2 y_stick{rect.pixelAt({7.0, -0.5}), rect.pixelAt({7.0, 0.5})};
  const ScaleFactors s = scaleFromSticks(x_stick, 1.0, y_stick, 1.0);
  EXPECT_NEAR(s.x_m_per_px, 0.025, 1e-9);
  EXPECT_NEAR(s.y_m_per_px, 0.025, 1e-9);
}

TEST(ScaleFromSticks, RejectsParallelSticksAndBadLengths) {
  EXPECT_THROW((void)scaleFromSticks({{0, 0}, {0, 50}}, 1.0, {{5, 0}, {5, 50}}, 1.0), InvalidInput);
  EXPECT_THROW((void)scaleFromSticks({{0, 0}, {0, 50}}, 0.0, {{0, 0}, {40, 0}}, 1.0), InvalidInput);
}

// --- chessboard ---------------------------------------------------------------------------------------

struct BoardCamera {
  double f = 700.0, cx = 325.0, cy = 236.0;
  int width = 640, height = 480;
};

// A 9 × 6 inner-corner board (10 × 7 squares of `sq` m) with a one-square white margin on a grey
// background, seen by an ideal pin-hole: every pixel's ray meets the board plane; 3 × 3
// supersampling.
Image renderBoard(const BoardCamera& cam, const Mat3& r, const Vec3& t, double sq) {
  Image img(cam.width, cam.height, 3);
  const Mat3 rt = r.transpose();
  const Vec3 t_board = rt * t;
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      double sum = 0;
      for (int sv = 0; sv < 3; ++sv) {
        for (int su = 0; su < 3; ++su) {
          const double uu = u + (su - 1) / 3.0, vv = v + (sv - 1) / 3.0;
          const Vec3 d((uu - cam.cx) / cam.f, (vv - cam.cy) / cam.f, 1.0);
          const Vec3 d_board = rt * d;
          double value = 90;  // background
          if (std::abs(d_board.z()) > 1e-12) {
            const double s = t_board.z() / d_board.z();
            if (s > 0) {
              const Vec3 q = s * d_board - t_board;  // board frame
              const double bx = q.x() / sq, by = q.y() / sq;
              if (bx >= -2 && bx < 10 && by >= -2 && by < 7) {
                value = 245;  // margin
                if (bx >= -1 && bx < 9 && by >= -1 && by < 6) {
                  const long ix = static_cast<long>(std::floor(bx)), iy = static_cast<long>(std::floor(by));
                  value = ((ix + iy) % 2 == 0) ? 20 : 235;
                }
              }
            }
          }
          sum += value;
        }
      }
      const auto g = static_cast<std::uint8_t>(std::lround(sum / 9.0));
      std::uint8_t* p = img.pixel(u, v);
      p[0] = p[1] = p[2] = g;
    }
  }
  return img;
}

Mat3 rotation(double rx_deg, double ry_deg, double rz_deg) {
  return (Eigen::AngleAxisd(degToRad(rz_deg), Vec3::UnitZ()) * Eigen::AngleAxisd(degToRad(ry_deg), Vec3::UnitY()) *
          Eigen::AngleAxisd(degToRad(rx_deg), Vec3::UnitX()))
      .toRotationMatrix();
}

std::vector<Image> boardImages(const BoardCamera& cam, double sq) {
  struct P {
    double rx, ry, rz, dx, dy, z;
  };
  const std::vector<P> poses = {
      {0, 0, 0, 0, 0, 0.55},       {25, 0, 5, 0.02, 0.0, 0.6},   {-25, 0, -5, -0.02, 0.01, 0.6},
      {0, 30, 0, 0.0, -0.02, 0.6}, {0, -30, 10, 0.03, 0.0, 0.6}, {20, 20, 0, -0.05, -0.04, 0.65},
      {-20, 25, -10, 0.05, 0.04, 0.65}, {15, -25, 15, 0.0, 0.05, 0.55}, {-15, -20, -15, 0.06, -0.05, 0.7},
      {30, 10, 30, 0.0, 0.0, 0.7}, {10, -10, -30, -0.06, 0.06, 0.6}, {-30, 15, 0, 0.0, 0.0, 0.75},
  };
  std::vector<Image> images;
  const Vec3 centre(4.0 * sq, 2.5 * sq, 0.0);  // board centre in its own frame
  for (const P& p : poses) {
    const Mat3 r = rotation(p.rx, p.ry, p.rz);
    // Board centre at (dx, dy, z) in the camera frame.
    const Vec3 t = Vec3(p.dx, p.dy, p.z) - r * centre;
    images.push_back(renderBoard(cam, r, t, sq));
  }
  return images;
}

TEST(Chessboard, RecoversTheFocalLengthWithinOnePercentOnRenderedBoards) {
  const BoardCamera cam;
  const double sq = 0.025;
  const std::vector<Image> images = boardImages(cam, sq);
  const ChessboardResult res = calibrateChessboard(images, 9, 6, sq);
  std::printf("chessboard: %d/%zu images used, fx %.3f fy %.3f (true 700: %+.3f%% %+.3f%%), cx %.2f cy %.2f (true %.1f "
              "%.1f), RMS %.4f px, k = [%.4f %.4f %.5f %.5f %.4f]\n",
              res.images_used, images.size(), res.intrinsics.fx, res.intrinsics.fy,
              100 * (res.intrinsics.fx / cam.f - 1), 100 * (res.intrinsics.fy / cam.f - 1), res.intrinsics.cx,
              res.intrinsics.cy, cam.cx, cam.cy, res.rms_reprojection_px, res.intrinsics.distortion[0],
              res.intrinsics.distortion[1], res.intrinsics.distortion[2], res.intrinsics.distortion[3],
              res.intrinsics.distortion[4]);
  for (const std::string& r : res.rejected) std::printf("  rejected %s\n", r.c_str());
  EXPECT_GE(res.images_used, 10);
  EXPECT_EQ(res.intrinsics.width, 640);
  EXPECT_EQ(res.intrinsics.height, 480);
  EXPECT_NEAR(res.intrinsics.fx, cam.f, 0.01 * cam.f);
  EXPECT_NEAR(res.intrinsics.fy, cam.f, 0.01 * cam.f);
  EXPECT_NEAR(res.intrinsics.cx, cam.cx, 3.0);
  EXPECT_NEAR(res.intrinsics.cy, cam.cy, 3.0);
  EXPECT_LT(res.rms_reprojection_px, 0.5);
  ASSERT_EQ(res.intrinsics.distortion.size(), 5u);
}

TEST(Chessboard, FindsAndDrawsCornersAndRejectsBoardlessImages) {
  const BoardCamera cam;
  const Image board = renderBoard(cam, rotation(10, 10, 0), Vec3(-0.1, -0.06, 0.6), 0.025);
  const auto corners = findChessboard(board, 9, 6);
  ASSERT_TRUE(corners);
  EXPECT_EQ(corners->size(), 54u);
  const Image drawn = drawChessboardCorners(board, 9, 6, *corners, true);
  EXPECT_EQ(drawn.width, board.width);
  EXPECT_NE(drawn, board);
  Image grey(640, 480, 3);
  std::fill(grey.data.begin(), grey.data.end(), std::uint8_t{128});
  EXPECT_FALSE(findChessboard(grey, 9, 6));
  std::vector<Image> images = boardImages(cam, 0.025);
  images.insert(images.begin() + 1, grey);
  const ChessboardResult res = calibrateChessboard(images, 9, 6, 0.025);
  ASSERT_EQ(res.rejected.size(), 1u);
  EXPECT_EQ(res.rejected[0], "image 1: no 9x6 chessboard found");
  EXPECT_THROW((void)calibrateChessboard({grey, grey, grey}, 9, 6, 0.025), InvalidInput);
  EXPECT_THROW((void)calibrateChessboard(images, 9, 6, 0.0), InvalidInput);
}

TEST(Chessboard, RealPhotosCalibrateWithSubPixelError) {
  ASSERT_TRUE(testing::realDataPresent("calibration"));
  const std::filesystem::path dir = testing::realDataPath("calibration");
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() == ".jpg") names.push_back(e.path().string());
  }
  std::sort(names.begin(), names.end());
  std::vector<Image> images;
  std::vector<std::string> used_names;
  for (const std::string& n : names) {
    Image img = readImage(n);
    if (img.width != 1280 || img.height != 720) continue;  // two photos are 1281 × 721
    images.push_back(std::move(img));
    used_names.push_back(n);
  }
  ASSERT_GE(images.size(), 3u) << "too few 1280x720 photos in " << dir;
  const ChessboardResult res = calibrateChessboard(images, 9, 6, 0.025, used_names);
  std::printf("real photos: %d/%zu used, fx %.2f fy %.2f cx %.2f cy %.2f, RMS %.4f px\n", res.images_used,
              images.size(), res.intrinsics.fx, res.intrinsics.fy, res.intrinsics.cx, res.intrinsics.cy,
              res.rms_reprojection_px);
  for (const std::string& r : res.rejected) std::printf("  rejected %s\n", r.c_str());
  EXPECT_GE(res.images_used, 3);
  EXPECT_LT(res.rms_reprojection_px, 1.0);
  // The three photos where the board is partly out of frame are skipped, with the reason.
  for (const char* partial : {"calibration1.jpg", "calibration4.jpg", "calibration5.jpg"}) {
    EXPECT_EQ(std::count_if(res.rejected.begin(), res.rejected.end(),
                            [&](const std::string& r) {
                              return r.find(partial) != std::string::npos && r.find("no 9x6 chessboard found") != std::string::npos;
                            }),
              1)
        << partial;
  }
  EXPECT_EQ(res.rejected.size(), 3u);

  // Undistorted with the calibration, the board's rows of corners are straight lines: the RMS
  // distance of the corners from their row's least-squares line, over every photo where the board
  // is found both as taken and undistorted (it may leave the frame when undistorted).
  const auto camera = createCamera(LensModel::Pinhole, res.intrinsics, CameraMount{});
  auto rowBend = [](const std::vector<Vec2>& corners, double& sum_sq, int& count) {
    for (int row = 0; row < 6; ++row) {
      Vec2 mean = Vec2::Zero();
      for (int c = 0; c < 9; ++c) mean += corners[row * 9 + c] / 9.0;
      Mat2 scatter = Mat2::Zero();
      for (int c = 0; c < 9; ++c) scatter += (corners[row * 9 + c] - mean) * (corners[row * 9 + c] - mean).transpose();
      const Eigen::SelfAdjointEigenSolver<Mat2> eig(scatter);
      const Vec2 normal = eig.eigenvectors().col(0);  // smallest eigenvalue: across the line
      for (int c = 0; c < 9; ++c) {
        sum_sq += std::pow(normal.dot(corners[row * 9 + c] - mean), 2);
        ++count;
      }
    }
  };
  double before_sq = 0, after_sq = 0;
  int before_n = 0, after_n = 0, photos = 0;
  for (const Image& photo : images) {
    const auto before = findChessboard(photo, 9, 6);
    const auto after = findChessboard(undistortFrame(*camera, photo), 9, 6);
    if (!before || !after) continue;
    rowBend(*before, before_sq, before_n);
    rowBend(*after, after_sq, after_n);
    ++photos;
  }
  ASSERT_GE(photos, 10);
  const double bend_before = std::sqrt(before_sq / before_n), bend_after = std::sqrt(after_sq / after_n);
  std::printf("%d photos: corners off their row's line, RMS %.3f px as taken, %.3f px undistorted\n", photos,
              bend_before, bend_after);
  // The lens bends the rows (1.03 px RMS measured); undistorted they are straight to within the
  // calibration's own reprojection error (0.45 px against 0.85 measured).
  EXPECT_GT(bend_before, 2 * bend_after);
  EXPECT_LT(bend_after, res.rms_reprojection_px);
}

// The image size is the one most photos have, whatever their order: a 1281 x 721 photo given
// first is cut to the others' 1280 x 720 (within the default 2 px) instead of deciding the size.
TEST(Chessboard, TheMostCommonSizeWinsInAnyOrder) {
  ASSERT_TRUE(testing::realDataPresent("calibration"));
  const std::filesystem::path dir = testing::realDataPath("calibration");
  std::vector<std::string> names;
  for (const char* n : {"calibration7.jpg", "calibration2.jpg", "calibration3.jpg", "calibration6.jpg"})
    names.push_back((dir / n).string());
  std::vector<Image> images;
  for (const std::string& n : names) images.push_back(readImage(n));
  ASSERT_EQ(images[0].width, 1281);
  const ChessboardResult first = calibrateChessboard(images, 9, 6, 0.025, names);
  std::reverse(images.begin(), images.end());
  std::reverse(names.begin(), names.end());
  const ChessboardResult last = calibrateChessboard(images, 9, 6, 0.025, names);
  for (const ChessboardResult* r : {&first, &last}) {
    EXPECT_EQ(r->intrinsics.width, 1280);
    EXPECT_EQ(r->intrinsics.height, 720);
    EXPECT_EQ(r->images_used, 4);
    ASSERT_EQ(r->fitted.size(), 1u);
    EXPECT_NE(r->fitted[0].find("calibration7.jpg: 1281x721 cut at the right and bottom to 1280x720"), std::string::npos)
        << r->fitted[0];
  }
  EXPECT_NEAR(first.intrinsics.fx, last.intrinsics.fx, 1e-6 * first.intrinsics.fx);
  // With no tolerance the odd photo is skipped with its size.
  const ChessboardResult strict = calibrateChessboard(images, 9, 6, 0.025, names, 0);
  EXPECT_EQ(strict.images_used, 3);
  ASSERT_EQ(strict.rejected.size(), 1u);
  EXPECT_NE(strict.rejected[0].find("calibration7.jpg: 1281x721, not the common 1280x720 (size tolerance 0 px)"),
            std::string::npos)
      << strict.rejected[0];
}

}  // namespace
}  // namespace mapnav
