// importKitti on tiny KITTI sequences written by the tests: known poses → hand-computed truth and
// odometry; bad sequences → errors naming the file and the line, and no log folder.
#include "mapnav/logs/kitti_import.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/image/png.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

namespace fs = std::filesystem;

// Three camera-to-world poses (KITTI: x right, y down, z forward): at the start; 2 m straight on;
// then turned 90° left (the optical axis along KITTI −x, R's third column (−1, 0, 0)) at
// (x, z) = (−1, 3), i.e. 1 m left of and 3 m ahead of the start.
const char* kPoses =
    "1 0 0 0 0 1 0 0 0 0 1 0\n"
    "1 0 0 0 0 1 0 0 0 0 1 2\n"
    "0 0 -1 -1 0 1 0 0 1 0 0 3\n";
const char* kCalib =
    "P0: 700 0 4 0 0 710 3 0 0 0 1 0\n"
    "P1: 700 0 4 -380 0 710 3 0 0 0 1 0\n";

class TinyKittiSequence : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = testing::freshTempDir();
    seq_ = root_ / "seq";
    fs::create_directories(seq_ / "image_0");
    for (int i = 0; i < 3; ++i) {
      Image grey(8, 6, 1);
      for (std::size_t k = 0; k < grey.data.size(); ++k) grey.data[k] = static_cast<std::uint8_t>(10 * i + k);
      writePng(grey, seq_ / "image_0" / ("00000" + std::to_string(i) + ".png"));
    }
    writeFileAtomic(seq_ / "poses.txt", kPoses);
    writeFileAtomic(seq_ / "calib.txt", kCalib);
  }
  // Nothing but the sequence is left beside the log that was not written.
  void expectNoLog() const {
    EXPECT_FALSE(fs::exists(root_ / "log"));
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(root_)) names.push_back(e.path().filename().string());
    EXPECT_EQ(names, std::vector<std::string>{"seq"});
  }
  // The ValidationError importKitti throws: its file and its one issue's line and check.
  void expectBadLine(const std::string& file, int line, const std::string& check, const std::string& words) {
    try {
      importKitti(seq_, root_ / "log");
      FAIL() << "no error";
    } catch (const ValidationError& e) {
      EXPECT_EQ(fs::path(e.file()).filename().string(), file);
      ASSERT_EQ(e.issues().size(), 1u);
      EXPECT_EQ(e.issues()[0].line, line);
      EXPECT_EQ(e.issues()[0].check, check);
      EXPECT_NE(e.issues()[0].message.find(words), std::string::npos) << e.issues()[0].message;
    }
    expectNoLog();
  }
  fs::path root_, seq_;
};

TEST(KittiGroundPose, MapsKittiAxesToTheGroundFrame) {
  // Camera 5 m ahead (z) and 2 m right (x) of the start, looking straight on: x = 5, y = −2.
  const double ahead[12] = {1, 0, 0, 2, 0, 1, 0, 0.3, 0, 0, 1, 5};
  EXPECT_POSE_NEAR(kittiGroundPose(ahead), Pose2(5, -2, 0), 1e-12);
  // Turned 30° right: the optical axis (sin 30°, 0, cos 30°) in KITTI (towards +x, the right).
  const double c = std::cos(degToRad(30)), s = std::sin(degToRad(30));
  const double right[12] = {c, 0, s, 0, 0, 1, 0, 0, -s, 0, c, 0};
  EXPECT_POSE_NEAR(kittiGroundPose(right), Pose2(0, 0, degToRad(-30)), 1e-12);
}

TEST_F(TinyKittiSequence, WritesTruthOdometryAndCamera) {
  const KittiImportResult r = importKitti(seq_, root_ / "log");
  EXPECT_EQ(r.frames, 3u);
  EXPECT_EQ(r.calib_row, "P0");
  EXPECT_EQ(r.images.filename().string(), "image_0");
  EXPECT_EQ(r.channels, 1);
  EXPECT_NEAR(r.duration_s, 0.2, 1e-12);
  EXPECT_NEAR(r.distance_m, 2 + std::sqrt(2.0), 1e-9);

  const ReplayLog log = ReplayLog::open(root_ / "log", ReadOptions{false, true});
  ASSERT_EQ(log.frames().size(), 3u);
  EXPECT_DOUBLE_EQ(log.header().frame_rate_hz, 10.0);
  EXPECT_EQ(log.header().name, "KITTI seq");
  const std::vector<Pose2> truth = {Pose2(0, 0, 0), Pose2(2, 0, 0), Pose2(3, 1, degToRad(90))};
  // Odometry: none at the start; 2 m straight on; the chord from (2, 0) to (3, 1), √2 m, turning 90°.
  const std::vector<std::pair<double, double>> odometry = {{0, 0}, {2, 0}, {std::sqrt(2.0), degToRad(90)}};
  for (std::size_t i = 0; i < 3; ++i) {
    const LogFrame& f = log.frames()[i];
    EXPECT_NEAR(f.t, 0.1 * static_cast<double>(i), 1e-12);
    ASSERT_TRUE(f.truth);
    EXPECT_POSE_NEAR(*f.truth, truth[i], 1e-9);
    EXPECT_NEAR(f.odometry.distance_m, odometry[i].first, 1e-9) << i;
    EXPECT_NEAR(f.odometry.dheading_rad, odometry[i].second, 1e-9) << i;
    // The images as they were, grey.
    EXPECT_EQ(log.image(i), readPng(seq_ / "image_0" / ("00000" + std::to_string(i) + ".png")));
  }
  // The camera: P0's fx, fy, cx, cy; KITTI's height, level.
  const Camera& cam = *log.header().camera;
  EXPECT_EQ(cam.width(), 8);
  EXPECT_EQ(cam.height(), 6);
  EXPECT_EQ(cam.intrinsics().fx, 700);
  EXPECT_EQ(cam.intrinsics().fy, 710);
  EXPECT_EQ(cam.intrinsics().cx, 4);
  EXPECT_EQ(cam.intrinsics().cy, 3);
  EXPECT_EQ(cam.mount().height_m, 1.65);
  EXPECT_EQ(cam.mount().tilt_rad, 0.0);
  // ... and the same camera as a file of its own.
  const auto file = loadCamera(root_ / "log" / "camera.json");
  EXPECT_EQ(file->intrinsics(), cam.intrinsics());
  EXPECT_EQ(file->mount(), cam.mount());
}

TEST_F(TinyKittiSequence, OptionsSetTheCameraMountAndTimes) {
  KittiImportOptions o;
  o.camera_height_m = 1.2;
  o.camera_tilt_deg = 5;
  o.frame_rate_hz = 4;
  o.name = "tiny";
  writeFileAtomic(seq_ / "times.txt", "0.5\n0.75\n1.5\n");
  importKitti(seq_, root_ / "log", o);
  const ReplayLog log = ReplayLog::open(root_ / "log");
  EXPECT_EQ(log.header().name, "tiny");
  EXPECT_EQ(log.header().camera->mount().height_m, 1.2);
  EXPECT_NEAR(log.header().camera->mount().tilt_rad, degToRad(5), 1e-15);
  EXPECT_DOUBLE_EQ(log.header().frame_rate_hz, 4);
  EXPECT_DOUBLE_EQ(log.frames()[1].t, 0.75);  // times.txt wins over the rate
  EXPECT_DOUBLE_EQ(log.frames()[2].t, 1.5);
}

TEST_F(TinyKittiSequence, MissingPosesIsAnIoErrorAndWritesNothing) {
  fs::remove(seq_ / "poses.txt");
  try {
    importKitti(seq_, root_ / "log");
    FAIL() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("poses.txt"), std::string::npos) << e.what();
  }
  expectNoLog();
}

TEST_F(TinyKittiSequence, FewerPosesThanImagesNamesTheLineAfterTheLast) {
  writeFileAtomic(seq_ / "poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 2\n");
  expectBadLine("poses.txt", 3, "kitti.count", "2 poses for 3 images");
}

TEST_F(TinyKittiSequence, MorePosesThanImagesNamesTheFirstExtraLine) {
  writeFileAtomic(seq_ / "poses.txt", std::string(kPoses) + "\n1 0 0 0 0 1 0 0 0 0 1 4\n");
  expectBadLine("poses.txt", 5, "kitti.count", "4 poses for 3 images");  // line 4 is blank
}

TEST_F(TinyKittiSequence, MalformedNumberNamesTheLine) {
  writeFileAtomic(seq_ / "poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 abc 0 1 0 0 0 0 1 2\n1 0 0 0 0 1 0 0 0 0 1 3\n");
  expectBadLine("poses.txt", 2, "kitti.number", "value 4 \"abc\"");
}

TEST_F(TinyKittiSequence, ShortLineAndNonRotationNameTheLine) {
  writeFileAtomic(seq_ / "poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 2\n1 0 0 0 0 1 0 0 0 0 1\n");
  expectBadLine("poses.txt", 3, "kitti.count", "got 11");
  writeFileAtomic(seq_ / "poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n2 0 0 0 0 1 0 0 0 0 1 2\n1 0 0 0 0 1 0 0 0 0 1 3\n");
  expectBadLine("poses.txt", 2, "kitti.rotation", "not a rotation");
}

TEST_F(TinyKittiSequence, BadCalibNamesTheLine) {
  writeFileAtomic(seq_ / "calib.txt", "P0: 700 0 4 0 0 710 3 0 0 0 1\n");
  expectBadLine("calib.txt", 1, "kitti.count", "projection matrix P0");
}

TEST_F(TinyKittiSequence, AnImageOfAnotherSizeLeavesNoHalfWrittenLog) {
  writePng(Image(9, 6, 1), seq_ / "image_0" / "000002.png");  // found while the log is being written
  EXPECT_THROW(importKitti(seq_, root_ / "log"), InvalidInput);
  expectNoLog();
}

TEST(KittiImportOptions, DefaultsAreValidAndBadFieldsAreNamed) {
  EXPECT_NO_THROW(KittiImportOptions{}.validate());
  KittiImportOptions o;
  o.camera_height_m = 0;
  try {
    o.validate();
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "KittiImportOptions::camera_height_m = 0: must be finite and > 0");
  }
  o = {};
  o.frame_rate_hz = -1;
  EXPECT_THROW(o.validate(), InvalidInput);
}

}  // namespace
}  // namespace mapnav
