// `mapnav eval segmentation --bev`: scoring in a bird's-eye grid end to end, on a hand-made camera and
// photo set whose counts are worked out by hand, and its usage errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mapnav/core/io.h"
#include "mapnav/image/png.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;
using testing::runCli;

// A level pin-hole 1 m above the ground, 7 × 4 pixels, f = 2 px, principal point (3, 1): a ground
// point x m right and z m ahead projects to u = 3 + 2x / z, v = 1 + 2 / z; the horizon is row 1.
const char* kCamera = R"({"format": "mapnav-camera/1", "model": "pinhole", "image": {"width": 7, "height": 4},
  "focal_px": [2.0, 2.0], "principal_point": [3.0, 1.0], "distortion": [],
  "mount": {"x": 0.0, "y": 0.0, "height_m": 1.0, "tilt_deg": 0.0, "roll_deg": 0.0, "yaw_deg": 0.0}})";

// In `dir`, two photos of `width` × 4 with the same label: road (1) at pixels 9, 10, 16, 18, 22 (index v · width +
// u), ignored (2) at 19, non-road (0) elsewhere; the photo grey on the road, green elsewhere.
fs::path handMadeSet(const fs::path& dir, int width) {
  fs::create_directories(dir / "images");
  fs::create_directories(dir / "labels");
  Image label(width, 4, 1), photo(width, 4, 3);
  for (int i = 0; i < width * 4; ++i) {
    const bool road = i == 9 || i == 10 || i == 16 || i == 18 || i == 22;
    label.data[static_cast<std::size_t>(i)] = road ? 1 : (i == 19 ? 2 : 0);
    const std::uint8_t rgb[3] = {static_cast<std::uint8_t>(road ? 128 : 40), static_cast<std::uint8_t>(road ? 128 : 140),
                                 static_cast<std::uint8_t>(road ? 128 : 40)};
    std::copy_n(rgb, 3, photo.data.begin() + 3 * i);
  }
  for (const std::string stem : {"a", "b"}) {
    writePng(photo, dir / "images" / (stem + ".png"));
    writePng(label, dir / "labels" / (stem + ".png"));
  }
  writeFileAtomic(dir / "camera.json", std::string(kCamera));
  return dir;
}

std::vector<std::string> bevEvalArgs(const fs::path& dir, const std::vector<std::string>& more) {
  std::vector<std::string> a = {"eval",     "segmentation", "--images",        (dir / "images").string(),
                                "--labels", (dir / "labels").string(), "--road-values", "1",
                                "--ignore-values", "2"};
  a.insert(a.end(), more.begin(), more.end());
  return a;
}

// The grid x −4..4, z 0..8 in 2 m cells: 4 × 4 cells, centres x = −3, −1, 1, 3 and z = 7, 5, 3, 1.
// Their pixels (u rounded, v rounded):
//   z = 7 and z = 5: v 1.29, 1.4 → row 1; u → 2, 3, 3, 4     pixels 9, 10, 10, 11 (twice)
//   z = 3:           v 1.67 → row 2;      u 1, 2.33, 3.67, 5  pixels 15, 16, 18, 19
//   z = 1:           v 3 → row 3;         u −3, 1, 5, 9       outside, 22, 26, outside
// 14 cells in the image. "Below the horizon" is rows 2 and 3 (pixels 14-27), so per cell:
//   rows 1: 9, 10, 10 road not predicted (FN 3), 11 TN, twice → FN 6
//   row 2: 15 FP, 16 TP, 18 TP, 19 ignored; row 3: 22 TP, 26 FP → TP 3, FP 2, FN 6: IoU 3/11.
// Per pixel the same baseline is TP 3 (16, 18, 22), FN 2 (9, 10), FP 10 (rows 2-3: 14 pixels less the
// 3 road and the ignored 19): IoU 3/15. The default trapezoid (rows 2.8-3.92, u 2.61-4.39 on row 3)
// covers pixels 24 and 25, both non-road and sampled by no cell: IoU 0 either way.
TEST(EvalCli, BirdsEyeGridScoresTheBaselinesCellByCell) {
  const fs::path dir = handMadeSet(testing::freshTempDir(), 7);
  const std::string camera = (dir / "camera.json").string();
  const auto bev =
      runCli(bevEvalArgs(dir, {"--camera", camera, "--bev", "--bev-range", "-4,4,0,8", "--bev-cell", "2", "--json"}));
  ASSERT_EQ(bev.exit_code, 0) << bev.out << bev.err;
  const auto j = nlohmann::json::parse(bev.out);
  EXPECT_EQ(j["space"], "bev");
  EXPECT_EQ(j["bev"]["columns"], 4);
  EXPECT_EQ(j["bev"]["rows"], 4);
  EXPECT_EQ(j["bev"]["cells_in_image"], 14);
  EXPECT_EQ(j["bev"]["x_m"], nlohmann::json::array({-4.0, 4.0}));
  EXPECT_EQ(j["bev"]["z_m"], nlohmann::json::array({0.0, 8.0}));
  EXPECT_DOUBLE_EQ(j["bev"]["cell_m"].get<double>(), 2.0);
  EXPECT_NEAR(j["baseline_horizon_iou"].get<double>(), 3.0 / 11.0, 1e-4);
  EXPECT_NEAR(j["baseline_bootstrap_iou"].get<double>(), 0.0, 1e-12);
  if (!j["iou"].is_null()) {
    EXPECT_NEAR(j["margin"].get<double>(), j["iou"].get<double>() - 3.0 / 11.0, 2e-4) << bev.out;
  }

  const auto image = runCli(bevEvalArgs(dir, {"--camera", camera, "--json"}));
  ASSERT_EQ(image.exit_code, 0) << image.out << image.err;
  const auto i = nlohmann::json::parse(image.out);
  EXPECT_EQ(i["space"], "image");
  EXPECT_TRUE(i["bev"].is_null());
  EXPECT_NEAR(i["baseline_horizon_iou"].get<double>(), 3.0 / 15.0, 1e-4);
  EXPECT_NEAR(i["baseline_bootstrap_iou"].get<double>(), 0.0, 1e-12);

  // The text says which space it scored, and the overlays come in both.
  const fs::path overlays = dir / "overlays";
  const auto text = runCli(bevEvalArgs(dir, {"--camera", camera, "--bev", "--bev-range", "-4,4,0,8", "--bev-cell", "2",
                                          "--overlays", overlays.string()}));
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("scored in a bird's-eye grid (KITTI road benchmark): x -4..4 m, z 0..8 m, 2 m cells; 14 of "
                          "16 cells in the image"),
            std::string::npos)
      << text.out;
  const Image a = readPng(overlays / "a.bev.png");
  EXPECT_EQ(a.width, 4);
  EXPECT_EQ(a.height, 4);
  EXPECT_EQ(readPng(overlays / "a.png").width, 7);
}

TEST(EvalCli, BirdsEyeGridNeedsTheCameraOfThePhotos) {
  const fs::path dir = handMadeSet(testing::freshTempDir(), 7);
  // No camera: a usage error naming the missing option, nothing scored.
  auto r = runCli(bevEvalArgs(dir, {"--bev"}));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--bev needs --camera FILE"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  // Grid options without --bev.
  r = runCli(bevEvalArgs(dir, {"--bev-cell", "0.1"}));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--bev-cell requires --bev"), std::string::npos) << r.err;
  // A bad grid names the option and the field.
  r = runCli(bevEvalArgs(dir, {"--camera", (dir / "camera.json").string(), "--bev", "--bev-range", "4,-4,0,8"}));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--bev-range / --bev-cell: BevGrid::x_max_m = -4: must be > x_min_m"), std::string::npos) << r.err;
  r = runCli(bevEvalArgs(dir, {"--camera", (dir / "camera.json").string(), "--bev", "--bev-range", "4,-4,0"}));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--bev-range"), std::string::npos) << r.err;
  // A grid the camera does not see (behind it): the camera's file and the grid named.
  r = runCli(bevEvalArgs(dir, {"--camera", (dir / "camera.json").string(), "--bev", "--bev-range", "-4,4,-8,-1"}));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find((dir / "camera.json").string() +
                       ": no cell of the grid (x -4..4 m, z -8..-1 m) projects into the image of the camera"),
            std::string::npos)
      << r.err;

  // The camera's image must be the photos' size: the error names the file and both sizes.
  const fs::path wide = handMadeSet(dir / "wide", 8);
  const std::string camera = (dir / "camera.json").string();
  r = runCli(bevEvalArgs(wide, {"--camera", camera, "--bev"}));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(camera + ": the camera's image is 7x4 but the photos are 8x4"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace mapnav
