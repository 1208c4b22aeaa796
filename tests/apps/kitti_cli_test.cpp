// `mapnav log import-kitti` and `mapnav log track`: a bad sequence end to end, the path agreement on
// a synthetic straight road, and the real KITTI sequence (../shared/data/real/kitti_vo_seq1)
// imported and tracked by both road pipelines.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "mapnav/core/io.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/image/png.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;
using testing::runCli;

TEST(KittiCli, MalformedPoseLineIsNamedAndNothingIsWritten) {
  const fs::path dir = testing::freshTempDir();
  fs::create_directories(dir / "seq" / "image_0");
  for (int i = 0; i < 2; ++i) writePng(Image(4, 3, 1), dir / "seq" / "image_0" / ("00000" + std::to_string(i) + ".png"));
  writeFileAtomic(dir / "seq" / "calib.txt", "P0: 700 0 2 0 0 700 1 0 0 0 1 0\n");
  writeFileAtomic(dir / "seq" / "poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 1e999\n");
  const auto r = runCli({"log", "import-kitti", (dir / "seq").string(), "-o", (dir / "log").string()});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("poses.txt:2:1: error: kitti.number: value 12 \"1e999\" is not a finite number"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "log"));
  // A missing calib.txt is an I/O error.
  fs::remove(dir / "seq" / "calib.txt");
  writeFileAtomic(dir / "seq" / "poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 1\n");
  const auto missing = runCli({"log", "import-kitti", (dir / "seq").string(), "-o", (dir / "log").string()});
  EXPECT_EQ(missing.exit_code, 2) << missing.err;
  EXPECT_NE(missing.err.find("calib.txt"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(dir / "log"));
}

// A straight road 2 m wide (grey on green grass, under a pale sky) driven down its middle, 1.5 m a
// frame for 14 frames: frames 0 to 8 have 7 m or more of path ahead, the last 5 less.
TEST(LogTrackCli, JsonHoldsThePathAgreementOnAStraightRoad) {
  const fs::path dir = testing::freshTempDir() / "log";
  std::shared_ptr<const Camera> camera =
      createCamera(LensModel::Pinhole, CameraIntrinsics{640, 480, 400, 400, 319.5, 239.5, {}},
                   CameraMount{Vec2::Zero(), 1.5, degToRad(10), 0.0, 0.0});
  Image frame(640, 480, 3);
  for (int v = 0; v < frame.height; ++v)
    for (int u = 0; u < frame.width; ++u) {
      const auto g = camera->backproject(Vec2(u, v));
      const std::array<std::uint8_t, 3> rgb = !g ? std::array<std::uint8_t, 3>{180, 200, 230}
                                              : std::abs(g->y()) <= 1.0 ? std::array<std::uint8_t, 3>{110, 110, 110}
                                                                        : std::array<std::uint8_t, 3>{60, 120, 50};
      std::copy(rgb.begin(), rgb.end(), frame.pixel(u, v));
    }
  {
    ReplayLogWriter writer(dir, LogHeader{"straight road", camera, "", 10.0});
    for (int i = 0; i < 14; ++i) {
      LogFrame f;
      f.t = 0.1 * i;
      f.odometry.distance_m = i == 0 ? 0.0 : 1.5;
      f.truth = Pose2(1.5 * i, 0, 0);
      writer.add(f, frame);
    }
    writer.finish();
  }
  // The edge tracker (the default) finds both edges from the sides of eval segmentation's trapezoid,
  // and the centre line between them on the path; its road region starts at the traces' first
  // points, a little above the bottom row, so the nearest samples in view may fall outside it. (From
  // the default lane bootstrap, on the road's edges, its traces stop at row 230, short of the 15 m
  // path's row 210: frame 0 holds 0.60 of the path.)
  const auto r = runCli({"log", "track", dir.string(), "--trapezoid", "0.5,0.2,0.7,0.98", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["per_frame"].size(), 14u);
  for (int i = 0; i < 14; ++i) {
    const auto& f = j["per_frame"][i];
    ASSERT_TRUE(f["ok"].get<bool>()) << f.dump();
    if (i >= 9) {  // 6 m or less ahead
      EXPECT_EQ(f["path_status"], "path too short") << f.dump();
      EXPECT_TRUE(f["path_inside"].is_null()) << f.dump();
      EXPECT_TRUE(f["path_offset_m"].is_null()) << f.dump();
      continue;
    }
    EXPECT_EQ(f["path_status"], "measured") << f.dump();
    EXPECT_GE(f["path_inside"].get<double>(), 0.9) << f.dump();
    EXPECT_LE(std::abs(f["path_offset_m"].get<double>()), 0.05) << f.dump();
    if (i >= 7) {  // 9 and 7.5 m ahead: no direction over 5-10 m
      EXPECT_TRUE(f["path_angle_deg"].is_null()) << f.dump();
    } else {
      EXPECT_LE(f["path_angle_deg"].get<double>(), 0.5) << f.dump();
    }
  }
  const auto& p = j["path_agreement"];
  EXPECT_EQ(p["frames"], 14);
  EXPECT_EQ(p["measured"], 9);
  EXPECT_EQ(p["unmeasured"]["path_too_short"], 5);
  EXPECT_EQ(p["unmeasured"]["no_truth"], 0);
  EXPECT_EQ(p["no_road_found"], 0);
  EXPECT_GE(p["inside_goal_frames"].get<int>(), 7) << p.dump();  // 8 when written (frame 0: 0.925)
  EXPECT_EQ(p["angle_frames"], 7);
  EXPECT_EQ(p["angle_goal_frames"], 7);
  EXPECT_EQ(p["angle_goal_fraction"], 1.0);
  EXPECT_EQ(p["offset_pairs"], 8);
  EXPECT_EQ(p["offset_goal_fraction"], 1.0);
  EXPECT_EQ(p["goals"]["angle_deg"], 3.0);
  // The table gives the same, the headline before the count of frames tracked.
  const auto table = runCli({"log", "track", dir.string(), "--trapezoid", "0.5,0.2,0.7,0.98"});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("centre line within 3 deg of the path in 7 of 7 (1.000) frames"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("not measured: 5 of 14 frames (no truth 0, path too short 5, path out of view 0)"),
            std::string::npos)
      << table.out;
  EXPECT_LT(table.out.find("path agreement"), table.out.find("frames tracked")) << table.out;
  // The camera (1.5 m up, 10° down, f = 400) sees the ground at row 470.4 1.788 m ahead: a lane
  // ending at 1 m is refused, naming the option; a lane and a trapezoid together are a usage error.
  const auto short_lane = runCli({"log", "track", dir.string(), "--lane", "3,1"});
  EXPECT_EQ(short_lane.exit_code, 1) << short_lane.err;
  EXPECT_NE(short_lane.err.find("--lane: the lane: the far end 1 m is not beyond the nearest ground in view, 1.79 m ahead"), std::string::npos)
      << short_lane.err;
  const auto both = runCli({"log", "track", dir.string(), "--lane", "3,30", "--trapezoid", "0.5,0.2,0.7,0.98"});
  EXPECT_EQ(both.exit_code, 2) << both.err;
  EXPECT_NE(both.err.find("excludes"), std::string::npos) << both.err;
}

class RealKittiSequence : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!fs::is_directory(testing::realDataPath("kitti_vo_seq1"))) return;
    dir_ = new fs::path(testing::freshTempDir());
    const auto r = runCli({"log", "import-kitti", testing::realDataPath("kitti_vo_seq1").string(), "-o",
                           (*dir_ / "log").string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override {
    ASSERT_TRUE(testing::realDataPresent("kitti_vo_seq1"));
    ASSERT_NE(dir_, nullptr) << "the import of kitti_vo_seq1 failed (SetUpTestSuite)";
  }
  // `mapnav log track` --json over the imported log.
  static nlohmann::json track(const std::vector<std::string>& more) {
    std::vector<std::string> a = {"log", "track", (*dir_ / "log").string(), "--json"};
    a.insert(a.end(), more.begin(), more.end());
    const auto r = runCli(a);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out);
  }
  static fs::path* dir_;
};
fs::path* RealKittiSequence::dir_ = nullptr;

TEST_F(RealKittiSequence, ImportsTruthFromThePoses) {
  const ReplayLog log = ReplayLog::open(*dir_ / "log");
  ASSERT_EQ(log.frames().size(), 51u);
  EXPECT_EQ(log.header().camera->width(), 1226);
  EXPECT_EQ(log.header().camera->height(), 370);
  EXPECT_NEAR(log.header().camera->intrinsics().fx, 707.0912, 1e-9);
  // The last line of poses.txt: t = (−0.981436, −1.190278, 59.83857), R_02 = −0.01674529,
  // R_22 = 0.9998149: 59.84 m ahead, 0.98 m left, heading atan2(0.01674529, 0.9998149).
  const LogFrame& last = log.frames().back();
  EXPECT_POSE_NEAR(*last.truth, Pose2(59.83857, 0.981436, std::atan2(0.01674529, 0.9998149)), 1e-6);
  EXPECT_NEAR(last.t, 5.0, 1e-12);
  double driven = 0;
  for (const LogFrame& f : log.frames()) driven += f.odometry.distance_m;
  EXPECT_GT(driven, 59.84);  // at least the straight line from the start ...
  EXPECT_LT(driven, 59.84 + 0.1);  // ... and the road is straight
}

// The grass verge's edge (grass → kerb) on row 314 (about 9 m ahead), read off the images by hand
// (the grey levels along the row): column 436 in frame 0, 442 in frame 25, 462 in frame 50. The right
// kerb is lost behind parked cars and driveways in most frames, so the tracker reports the left
// edge alone (single_edge) there.
TEST_F(RealKittiSequence, EdgeTrackerFollowsTheVergeSmoothly) {
  const fs::path sheet = *dir_ / "edges.png";
  const auto j = track({"--pipeline", "edge-tracker", "--trapezoid", "0.36,0.1,0.6,0.98", "--options",
                        R"({"single_edge":true})", "--contact-sheet", sheet.string()});
  EXPECT_EQ(j["frames"], 51);
  EXPECT_GE(j["tracked"].get<int>(), 43) << j.dump();  // 45 when written, 47 since grey frames use the grey level
  int verge = 0;  // frames with the left edge (a frame may also be tracked on the right kerb alone)
  for (const auto& f : j["per_frame"]) {
    if (!f["ok"].get<bool>() || f["left_u"].is_null()) continue;
    ++verge;
    EXPECT_GT(f["left_u"].get<double>(), 420) << f.dump();
    EXPECT_LT(f["left_u"].get<double>(), 475) << f.dump();
  }
  EXPECT_GE(verge, 43) << j.dump();  // 46 of 51
  EXPECT_GT(j["per_frame"][50]["left_u"].get<double>(), j["per_frame"][0]["left_u"].get<double>() + 10);
  EXPECT_LE(j["max_jump_px"]["left"].get<double>(), 6) << j.dump();  // 3.0 when written
  // The last 6 frames have less than 7 m of truth ahead (about 1.2 m a frame); the others are measured.
  EXPECT_EQ(j["path_agreement"]["measured"], 45) << j["path_agreement"].dump();
  EXPECT_EQ(j["path_agreement"]["unmeasured"]["path_too_short"], 6) << j["path_agreement"].dump();
  // Eight overlays at half size (613 x 185), two a row 4 px apart: 2 x 613 + 4 by 4 x 185 + 3 x 4.
  const Image s = readPng(sheet);
  EXPECT_EQ(s.width, 1230);
  EXPECT_EQ(s.height, 752);
}

// The Hough road finder with the prior: the lane's centre line on row 314 lies between the verge's
// edge (436-462, above) and the parked cars' kerb; columns 520-760 hold the lane in every frame (by
// eye on the overlays). Without the prior (prior_px 0) the Hough's maximum jumps to the grass verge:
// 37 of 51 frames on the lane, largest jump 458.5 px when written; with prior_px 20 and the found
// road carried forward by the odometry, 51 of 51 and 19.9 px.
TEST_F(RealKittiSequence, HoughRoadFinderHoldsTheLaneWithThePrior) {
  const auto onLane = [](const nlohmann::json& j) {
    int n = 0;
    for (const auto& f : j["per_frame"])
      n += !f["centre_u"].is_null() && f["centre_u"].get<double>() >= 520 && f["centre_u"].get<double>() <= 760;
    return n;
  };
  const fs::path sheet = *dir_ / "hough.png";
  const auto j = track({"--pipeline", "cluster-perceptron", "--trapezoid", "0.36,0.1,0.6,0.98", "--options",
                        R"({"balance_classes":true,"prior_px":20})", "--contact-sheet", sheet.string()});
  EXPECT_EQ(j["frames"], 51);
  EXPECT_EQ(j["tracked"], 51) << j.dump();
  EXPECT_GE(onLane(j), 50) << j.dump();  // 51 when written
  EXPECT_LE(j["max_jump_px"]["centre"].get<double>(), 25) << j.dump();  // 19.9 when written
  // Against the true future path (docs/kitti.md): when written, the road band held ≥ 95 % of the path
  // in 45 of 45 measured frames, the centre line was within 3° of it in 39 of 42, and its offset to
  // the path changed by ≤ 0.3 m in 43 of 43 pairs.
  const auto& p = j["path_agreement"];
  EXPECT_EQ(p["measured"], 45) << p.dump();
  EXPECT_GE(p["inside_goal_fraction"].get<double>(), 0.9) << p.dump();
  EXPECT_GE(p["angle_goal_fraction"].get<double>(), 0.85) << p.dump();
  EXPECT_GE(p["offset_goal_fraction"].get<double>(), 0.9) << p.dump();
  EXPECT_TRUE(fs::exists(sheet));
  // The same without the prior leaves the lane in more than 10 frames (14 when written).
  const auto free = track({"--pipeline", "cluster-perceptron", "--trapezoid", "0.36,0.1,0.6,0.98", "--options",
                           R"({"balance_classes":true,"prior_px":0})"});
  EXPECT_LE(onLane(free), 41) << free.dump();  // 37 when written
  EXPECT_GE(free["max_jump_px"]["centre"].get<double>(), 200) << free.dump();  // 458.5 when written
}

// The vision goals of docs/kitti.md at the defaults: `log track` bootstraps from the vehicle's 3 m lane on the ground
// (the camera's 1.65 m height: 6.5 to 30 m ahead), and the Hough finder trains its grey frames with
// balanced classes, and `log track` has it keep to 20 px of the centre line carried from the last
// frame (--prior-px). When
// written: the road band held ≥ 95 % of the path in 45 of 45 frames, covering a median 0.132 of the
// ground in view (the trivial "everything below the horizon" covers 1), the centre line was within 3°
// of the path in 42 of 42, its offset changed by ≤ 0.3 m in 41 of 43 pairs.
TEST_F(RealKittiSequence, HoughRoadFinderMeetsThePathGoalsAtTheDefaults) {
  const auto j = track({"--pipeline", "cluster-perceptron"});
  EXPECT_EQ(j["tracked"], 51) << j.dump();
  const auto& p = j["path_agreement"];
  EXPECT_EQ(p["measured"], 45) << p.dump();
  EXPECT_GE(p["inside_goal_fraction"].get<double>(), 0.9) << p.dump();
  EXPECT_LE(p["median_ground_share"].get<double>(), 0.3) << p.dump();
  EXPECT_GE(p["angle_goal_fraction"].get<double>(), 0.9) << p.dump();
  EXPECT_GE(p["offset_goal_fraction"].get<double>(), 0.9) << p.dump();
  // Grey frames trained as colour frames are (the non-road gate, unbalanced) miss the path's direction
  // (within 3° in 28 of 42 frames when written).
  const auto unbalanced = track({"--pipeline", "cluster-perceptron", "--options", R"({"grey_balance_classes":false})"});
  EXPECT_LE(unbalanced["path_agreement"]["angle_goal_fraction"].get<double>(), 0.8) << unbalanced["path_agreement"].dump();
  // Without the tracking prior the Hough's maximum leaves the lane: the offset to the path jumps by
  // more than 0.3 m in most pairs (within it in 10 of 43 when written).
  const auto free = track({"--pipeline", "cluster-perceptron", "--prior-px", "0"});
  EXPECT_LE(free["path_agreement"]["offset_goal_fraction"].get<double>(), 0.5) << free["path_agreement"].dump();
}

}  // namespace
}  // namespace mapnav
