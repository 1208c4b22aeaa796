// `mapnav calibrate chessboard` on the 20 shared photos: the image size is the most common
// one whatever the order the photos are given in, the two 1281×721 photos are cut to 1280×720 by
// default (--size-tolerance 2) or listed with their size and skipped (--size-tolerance 0), and the
// camera written is the same, byte for byte, in three orders.
#include <algorithm>
#include <filesystem>
#include <random>

#include <gtest/gtest.h>

#include "mapnav/core/io.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

namespace fs = std::filesystem;
using testing::runCli;

std::vector<std::string> photos() {
  std::vector<std::string> out;
  for (int i = 1; i <= 20; ++i) out.push_back(testing::realDataPath("calibration/calibration" + std::to_string(i) + ".jpg").string());
  return out;
}

testing::CommandResult calibrate(const std::vector<std::string>& images, const fs::path& output,
                             const std::vector<std::string>& extra = {}) {
  std::vector<std::string> args{"calibrate", "chessboard"};
  args.insert(args.end(), images.begin(), images.end());
  args.insert(args.end(), {"--board", "9x6", "-o", output.string()});
  args.insert(args.end(), extra.begin(), extra.end());
  return runCli(args);
}

TEST(CalibrateChessboardCli, TheSameCameraInEveryOrderWithTheOddSizedPhotosCut) {
  ASSERT_TRUE(testing::realDataPresent("calibration"));
  const fs::path out = testing::freshTempDir() / "camera.json";
  std::vector<std::string> in_order = photos(), reversed = photos(), odd_first = photos();
  std::reverse(reversed.begin(), reversed.end());
  // A 1281×721 photo (calibration15) first: the reference size used to be the first usable photo's.
  std::shuffle(odd_first.begin(), odd_first.end(), std::mt19937(27));
  std::iter_swap(odd_first.begin(), std::find(odd_first.begin(), odd_first.end(), photos()[14]));
  std::string first_camera, first_report;
  for (const auto* order : {&in_order, &reversed, &odd_first}) {
    const auto r = calibrate(*order, out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string camera = readFile(out);
    if (first_camera.empty()) {
      first_camera = camera;
      first_report = r.out;
    }
    EXPECT_EQ(camera, first_camera);
    EXPECT_EQ(r.out, first_report);
  }
  // 17 photos show the whole board (1, 4 and 5 cut it off); 7 and 15 are cut to the common size.
  EXPECT_NE(first_report.find("calibrated from 17 of 20 images (1280x720, the most common size)"), std::string::npos)
      << first_report;
  EXPECT_NE(first_report.find("calibration15.jpg: 1281x721 cut at the right and bottom to 1280x720"), std::string::npos);
  EXPECT_NE(first_report.find("calibration7.jpg: 1281x721 cut at the right and bottom to 1280x720"), std::string::npos);
  EXPECT_NE(first_report.find("calibration1.jpg: no 9x6 chessboard found"), std::string::npos);
}

TEST(CalibrateChessboardCli, WithoutToleranceTheOtherSizesAreListedAndSkipped) {
  ASSERT_TRUE(testing::realDataPresent("calibration"));
  const fs::path out = testing::freshTempDir() / "camera.json";
  std::vector<std::string> odd_first = photos();
  std::iter_swap(odd_first.begin(), odd_first.begin() + 14);  // calibration15, 1281×721, first
  auto r = calibrate(odd_first, out, {"--size-tolerance", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("calibrated from 15 of 20 images (1280x720, the most common size)"), std::string::npos) << r.out;
  for (const char* odd : {"calibration15.jpg", "calibration7.jpg"}) {
    EXPECT_NE(r.out.find(std::string(odd) + ": 1281x721, not the common 1280x720 (size tolerance 0 px)"),
              std::string::npos)
        << r.out;
  }
  r = calibrate(odd_first, out, {"--size-tolerance", "-1"});
  EXPECT_EQ(r.exit_code, 1);  // a value out of range: wrong input
  EXPECT_NE(r.err.find("--size-tolerance"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace mapnav
