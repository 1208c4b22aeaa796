// importKittiRaw on the real drive of ../shared/data/real/kitti_raw (Ostring, Karlsruhe): frames,
// truth against an independent east-north computation, odometry against the OXTS track, the camera
// from the calibration chain, and bad drives (a copy with symlinked images) named and unwritten.
#include "mapnav/logs/kitti_raw_import.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>
#include <sstream>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/logs/gnss.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

namespace fs = std::filesystem;

const char* kDrive = "kitti_raw/2011_09_26/2011_09_26_drive_0013_sync";

/// lat, lon of OXTS packet `i` of the drive.
LatLon packet(std::size_t i) {
  char name[32];
  std::snprintf(name, sizeof name, "%010zu.txt", i);
  std::istringstream in(readFile(testing::realDataPath(kDrive) / "oxts" / "data" / name));
  LatLon p;
  in >> p.lat >> p.lon;
  return p;
}

/// East, north of `p` about `o` on the WGS84 ellipsoid's local radii (meridian M and prime vertical
/// N at the origin): independent of GeographicLib, within a few millimetres over 200 m.
Vec2 eastNorth(const LatLon& p, const LatLon& o) {
  const double a = 6378137.0, f = 1 / 298.257223563, e2 = f * (2 - f);
  const double phi = o.lat * kPi / 180, s = std::sin(phi);
  const double w = 1 - e2 * s * s;
  const double m = a * (1 - e2) / std::pow(w, 1.5), n = a / std::sqrt(w);
  return {(p.lon - o.lon) * kPi / 180 * n * std::cos(phi), (p.lat - o.lat) * kPi / 180 * m};
}

class KittiRawDrive : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!fs::exists(testing::realDataPath(kDrive))) return;
    dir_ = new fs::path(testing::freshTempDir() / "log");
    result_ = new KittiRawImportResult(importKittiRaw(testing::realDataPath(kDrive), *dir_));
  }
  static void TearDownTestSuite() {
    delete dir_;
    delete result_;
  }
  void SetUp() override { ASSERT_TRUE(testing::realDataPresent(kDrive)); }
  static fs::path* dir_;
  static KittiRawImportResult* result_;
};
fs::path* KittiRawDrive::dir_ = nullptr;
KittiRawImportResult* KittiRawDrive::result_ = nullptr;

// --grey: the same drive as a grey camera gives it, frame by frame the colour frames' luminance,
// everything else as the colour import's.
TEST_F(KittiRawDrive, AGreyImportIsTheColourFramesLuminance) {
  KittiRawImportOptions grey;
  grey.grey = true;
  const fs::path dir = testing::freshTempDir() / "grey";
  const KittiRawImportResult r = importKittiRaw(testing::realDataPath(kDrive), dir, grey);
  EXPECT_EQ(r.frames, result_->frames);
  const ReplayLog colour_log = ReplayLog::open(*dir_), grey_log = ReplayLog::open(dir);
  ASSERT_EQ(grey_log.frames().size(), colour_log.frames().size());
  for (std::size_t i : {std::size_t{0}, std::size_t{77}, std::size_t{143}}) {
    const Image colour = toRgb(colour_log.image(i)), seen = toRgb(grey_log.image(i));
    ASSERT_FALSE(isGreyFrame(colour.data.data(), colour.width, colour.height)) << "frame " << i;
    EXPECT_TRUE(seen == greyed(colour)) << "frame " << i;
    EXPECT_EQ(grey_log.frames()[i].truth->translation(), colour_log.frames()[i].truth->translation());
  }
}

TEST_F(KittiRawDrive, FramesAndTruthAtTheOxtsFixesEastNorthOfTheFirst) {
  const ReplayLog log = ReplayLog::open(*dir_);
  ASSERT_EQ(log.frames().size(), 144u);
  const LatLon origin = packet(0);
  EXPECT_DOUBLE_EQ(result_->origin.lat, origin.lat);
  for (std::size_t i : {std::size_t{0}, std::size_t{143}}) {
    ASSERT_TRUE(log.frames()[i].truth);
    const Vec2 expected = eastNorth(packet(i), origin);
    EXPECT_NEAR(log.frames()[i].truth->x(), expected.x(), 0.01) << "frame " << i;
    EXPECT_NEAR(log.frames()[i].truth->y(), expected.y(), 0.01) << "frame " << i;
  }
  // A GNSS fix every 10th frame: the truth degraded as a consumer receiver would, never the truth,
  // its errors within what it states (4 sigma per axis), and the import's own receiver model's.
  EXPECT_EQ(result_->gnss_fixes, 15u);
  ASSERT_TRUE(log.frames()[10].gnss);
  EXPECT_FALSE(log.frames()[11].gnss);
  const double stated = GnssReceiverOptions{}.statedSigma();
  GnssReceiverOptions receiver_options;
  receiver_options.seed = KittiRawImportOptions{}.seed + 1;
  GnssReceiver receiver(receiver_options);
  for (std::size_t i = 0; i < log.frames().size(); i += 10) {
    const LogFrame& f = log.frames()[i];
    ASSERT_TRUE(f.gnss && f.truth) << "frame " << i;
    const Vec2 error = f.gnss->position - f.truth->translation();
    EXPECT_GT(error.norm(), 1e-3) << "frame " << i;
    EXPECT_LT(error.cwiseAbs().maxCoeff(), 4 * stated) << "frame " << i;
    EXPECT_DOUBLE_EQ(f.gnss->sigma_m, stated);
    const GnssFix expected = receiver.measure(f.truth->translation(), f.t);
    EXPECT_NEAR((f.gnss->position - expected.position).norm(), 0, 1e-3) << "frame " << i;  // the log's rounding
  }
}

TEST_F(KittiRawDrive, OdometryIntegratesToTheOxtsTrackWithinOnePercent) {
  const ReplayLog log = ReplayLog::open(*dir_);
  Vec2 dead = log.frames().front().truth->translation();
  double heading = log.frames().front().truth->heading();
  double odometry = 0, track = 0;
  for (std::size_t i = 1; i < log.frames().size(); ++i) {
    const MotionIncrement& m = log.frames()[i].odometry;  // dead reckoning about the interval's mid heading
    dead += m.distance_m * Vec2(std::cos(heading + 0.5 * m.dheading_rad), std::sin(heading + 0.5 * m.dheading_rad));
    heading += m.dheading_rad;
    odometry += log.frames()[i].odometry.distance_m;
    track += (log.frames()[i].truth->translation() - log.frames()[i - 1].truth->translation()).norm();
  }
  EXPECT_GT(track, 150);
  EXPECT_NEAR(odometry / track, 1.0, 0.01);
  EXPECT_LT((dead - log.frames().back().truth->translation()).norm(), 0.01 * track);
}

TEST_F(KittiRawDrive, CameraFromTheCalibrationChainSitsWhereKittisDrawingPutsIt) {
  // KITTI's set-up drawing: the colour cameras 1.65 m above the road, level, about 1.1 m ahead of
  // the OXTS unit and 0.3 m to its right (the unit is left of the car's centre line).
  EXPECT_NEAR(result_->mount.height_m, 1.65, 0.05);
  EXPECT_NEAR(result_->mount.tilt_rad, 0, 0.02);
  EXPECT_NEAR(result_->mount.yaw_rad, 0, 0.02);
  EXPECT_NEAR(result_->mount.offset.x(), 1.1, 0.2);
  EXPECT_NEAR(result_->mount.offset.y(), -0.3, 0.2);
  EXPECT_NEAR(result_->intrinsics.fx, 721.5377, 1e-3);  // P_rect_02
  EXPECT_EQ(result_->intrinsics.width, 1242);
}

// The carriageway's kerbs marked by eye at the row 10 m ahead (tests/data/real/ostring_kerb_marks.json
// says how; every 5th frame), seen through the imported camera from the vehicle: a two-lane
// carriageway is two lanes of 3.25-3.5 m and two gutters and kerbs, 7-8.5 m between the grass
// edges; and the car changes lanes, from the left one (its centre 1.5-2 m from the left kerb) to
// the right one (5-5.5 m): a map that puts the carriageway at a fixed offset from the OXTS track
// is wrong.
TEST_F(KittiRawDrive, KerbMarksSeenThroughTheCameraSpanOneCarriagewayAndALaneChange) {
  const ReplayLog log = ReplayLog::open(*dir_);
  const auto marks = nlohmann::json::parse(readFile(testing::sourceDir() / "tests/data/real/ostring_kerb_marks.json"));
  const double row = marks["row"].get<double>();
  const Camera& camera = *log.header().camera;
  // Where the row meets the ground: 10 m ahead of the camera.
  const auto ahead = camera.backproject(Vec2(camera.width() / 2.0, row));
  ASSERT_TRUE(ahead);
  EXPECT_NEAR(ahead->x() - camera.mount().offset.x(), 10.0, 0.3);
  std::vector<double> widths;
  std::map<int, double> left_y;  // the left kerb's offset from the vehicle, m
  for (const char* set : {"frames", "survey_frames"}) {
    for (const auto& [frame, m] : marks[set].items()) {
      const auto side = [&](const char* key) -> std::optional<Vec2> {
        if (m[key].is_null()) return std::nullopt;
        return camera.backproject(Vec2(m[key].get<double>(), row));
      };
      const auto l = side("left"), r = side("right");
      if (l) left_y[std::stoi(frame)] = l->y();
      if (l && r) widths.push_back(l->y() - r->y());
    }
  }
  ASSERT_EQ(widths.size(), 18u);
  std::sort(widths.begin(), widths.end());
  const double median = 0.5 * (widths[8] + widths[9]);
  EXPECT_GT(median, 7.0);
  EXPECT_LT(median, 8.5);
  ASSERT_EQ(left_y.size(), 25u);
  for (const auto& [f, y] : left_y) {
    if (f <= 15) {
      EXPECT_LT(y, 2.5) << "frame " << f;
    } else if (f >= 95) {
      EXPECT_GT(y, 4.0) << "frame " << f;
    }
  }
  std::printf("kerb to kerb at 10 m: median %.2f m (%.2f-%.2f); left kerb from the vehicle: frame 0 %.2f m, frame 140 %.2f m\n",
              median, widths.front(), widths.back(), left_y.at(0), left_y.at(140));
}

TEST(KittiRawImportOptions, BadFieldsAreNamedAndTheOdometrysRulesAreTheOdometrys) {
  EXPECT_NO_THROW(KittiRawImportOptions{}.validate());
  KittiRawImportOptions o;
  o.camera = "04";
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { o.validate(); },
                                                "KittiRawImportOptions::camera = \"04\": must be 00, 01, 02 or 03"));
  o = {};
  o.gyro_bias_deg_s = 20;  // what OdometryNoiseOptions, which it is handed on to, takes
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { o.validate(); },
                                                "KittiRawImportOptions::gyro_bias_deg_s = 20: must be in [-10, 10]"));
  o = {};
  o.imu_height_m = 10;
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { o.validate(); },
                                                "KittiRawImportOptions::imu_height_m = 10: must be in (0, 10)"));
  o = {};
  o.origin = LatLon{91, 0};
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { o.validate(); }, "KittiRawImportOptions::origin = 91.000000,0.000000"));
}

TEST_F(KittiRawDrive, DegradedOdometryIsLongByItsScaleError) {
  KittiRawImportOptions o;
  o.scale_error = 0.02;
  o.gyro_bias_deg_s = 0.5;
  const fs::path out = testing::freshTempDir() / "degraded";
  importKittiRaw(testing::realDataPath(kDrive), out, o);
  const ReplayLog exact = ReplayLog::open(*dir_), degraded = ReplayLog::open(out);
  double a = 0, b = 0, da = 0, db = 0;
  for (std::size_t i = 1; i < exact.frames().size(); ++i) {
    a += exact.frames()[i].odometry.distance_m, b += degraded.frames()[i].odometry.distance_m;
    da += exact.frames()[i].odometry.dheading_rad, db += degraded.frames()[i].odometry.dheading_rad;
  }
  EXPECT_NEAR(b / a, 1.02, 1e-6);
  const double duration = exact.frames().back().t - exact.frames().front().t;
  EXPECT_NEAR(db - da, 0.5 * kPi / 180 * duration, 1e-6);
}

/// The drive's calibration and OXTS copied to a temp DATE/ folder, its images linked.
fs::path copyOfTheDrive() {
  const fs::path src = testing::realDataPath(kDrive);
  const fs::path date = testing::freshTempDir() / "2011_09_26";
  const fs::path drive = date / src.filename();
  fs::create_directories(drive);
  for (const char* f : {"calib_cam_to_cam.txt", "calib_imu_to_velo.txt", "calib_velo_to_cam.txt"})
    fs::copy_file(src.parent_path() / f, date / f);
  fs::create_directory_symlink(src / "image_02", drive / "image_02");
  fs::copy(src / "oxts", drive / "oxts", fs::copy_options::recursive);
  return drive;
}

TEST(KittiRawImport, BadDrivesAreNamedAndNothingIsWritten) {
  ASSERT_TRUE(testing::realDataPresent(kDrive));
  {
    const fs::path drive = copyOfTheDrive();
    std::ofstream(drive / "oxts" / "data" / "0000000007.txt") << "49.0 8.4 114\n";
    const fs::path out = drive.parent_path() / "out";
    try {
      importKittiRaw(drive, out);
      FAIL();
    } catch (const ValidationError& e) {
      EXPECT_NE(std::string(e.what()).find("0000000007.txt"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("30 OXTS fields"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(out));
  }
  {
    const fs::path drive = copyOfTheDrive();
    fs::remove(drive.parent_path() / "calib_velo_to_cam.txt");
    EXPECT_THROW(importKittiRaw(drive, drive.parent_path() / "out"), IoError);
    EXPECT_FALSE(fs::exists(drive.parent_path() / "out"));
  }
  {
    const fs::path drive = copyOfTheDrive();
    fs::remove(drive / "oxts" / "data" / "0000000143.txt");
    try {
      importKittiRaw(drive, drive.parent_path() / "out");
      FAIL();
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("144 images, 143 OXTS packets"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(kittiTimeOfDay("2011-09-26 13:10:51.175862102").value_or(0), 13 * 3600 + 10 * 60 + 51.175862102);
  EXPECT_FALSE(kittiTimeOfDay("2011-09-26T13:10:51"));
  EXPECT_FALSE(kittiTimeOfDay("13:10:51"));
}

}  // namespace
}  // namespace mapnav
