#include "mapnav/logs/replay_log.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/core/json.h"
#include "mapnav/image/png.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

namespace fs = std::filesystem;

std::shared_ptr<const Camera> smallCamera() {
  CameraIntrinsics in;
  in.width = 8;
  in.height = 6;
  in.fx = 10.0;
  in.fy = 11.0;
  in.cx = 3.5;
  in.cy = 2.5;
  in.distortion = {0.01, -0.002, 0.0, 0.0};
  CameraMount mount;
  mount.offset = Vec2(0.25, -0.1);
  mount.height_m = 1.2;
  mount.tilt_rad = degToRad(20.0);
  mount.yaw_rad = degToRad(-3.0);
  return createCamera(LensModel::Pinhole, in, mount);
}

LogHeader smallHeader() {
  LogHeader header;
  header.name = "test log";
  header.camera = smallCamera();
  header.map = "../maps/example.json";
  header.frame_rate_hz = 5.0;
  return header;
}

Image frameImage(int k) {
  Image image(8, 6, 3);
  for (std::size_t i = 0; i < image.data.size(); ++i) image.data[i] = static_cast<std::uint8_t>(i * 7 + k * 31);
  return image;
}

Image maskImage(int k) {
  Image mask(8, 6, 1);
  for (int y = 0; y < 6; ++y) {
    for (int x = 0; x < 8; ++x) mask.pixel(x, y)[0] = (x + k) > 4 ? 255 : 0;
  }
  return mask;
}

LogFrame makeFrame(double t, double distance, double dheading_deg) {
  LogFrame frame;
  frame.t = t;
  frame.odometry = MotionIncrement{distance, degToRad(dheading_deg)};
  return frame;
}

/// A valid log of `n` frames (masks on the even ones, truth on every one, GNSS on frame 1).
void writeLog(const fs::path& dir, int n) {
  ReplayLogWriter writer(dir, smallHeader());
  for (int k = 0; k < n; ++k) {
    LogFrame frame = makeFrame(0.2 * k, 0.5 + 0.1 * k, k == 0 ? 0.0 : 1.5 * k);
    frame.truth = Pose2(1.0 + k, 2.0, degToRad(10.0 * k));
    if (k == 1) frame.gnss = GnssFix{Vec2(2.5, 1.75), 3.0};
    const Image mask = maskImage(k);
    writer.add(frame, frameImage(k), k % 2 == 0 ? &mask : nullptr);
  }
  writer.finish();
}

std::string line(double t, const std::string& image, const std::string& extra = "") {
  return R"({"t": )" + std::to_string(t) + R"(, "image": ")" + image +
         R"(", "odometry": {"distance_m": 0.5, "dheading_deg": 1.0})" + extra + "}";
}

/// A valid log whose frames.jsonl is replaced by `text` (images 000000..000004 exist).
fs::path logWithFrames(const std::string& text) {
  const fs::path dir = testing::freshTempDir() / "log";
  writeLog(dir, 5);
  writeFileAtomic(dir / "frames.jsonl", text);
  return dir;
}

std::string goodLines(int n) {
  std::string text;
  for (int k = 0; k < n; ++k) text += line(k, "images/00000" + std::to_string(k) + ".png") + "\n";
  return text;
}

/// Opens `dir` expecting a ValidationError on frames.jsonl; returns it.
ValidationError expectInvalid(const fs::path& dir, const ReadOptions& options = {}) {
  try {
    ReplayLog::open(dir, options);
  } catch (const ValidationError& e) {
    return e;
  }
  ADD_FAILURE() << "no ValidationError for " << dir;
  return ValidationError("none", {});
}

void expectBadLine(const fs::path& dir, const std::string& check, int line_number, const ReadOptions& options = {}) {
  const ValidationError e = expectInvalid(dir, options);
  ASSERT_FALSE(e.issues().empty());
  EXPECT_EQ(e.issues()[0].check, check) << e.what();
  EXPECT_EQ(e.issues()[0].line, line_number) << e.what();
  EXPECT_EQ(fs::path(e.file()).filename(), "frames.jsonl");
  const std::string what = e.what();
  EXPECT_NE(what.find("frames.jsonl:" + std::to_string(line_number) + ":"), std::string::npos) << what;
}

std::string fileBytes(const fs::path& path) { return readFile(path); }

// ---- round trip -------------------------------------------------------------------------------

TEST(ReplayLog, WriteThenReadRoundTrips) {
  const fs::path dir = testing::freshTempDir() / "log";
  writeLog(dir, 3);
  const ReplayLog log = ReplayLog::open(dir, ReadOptions{false, true});
  const LogHeader expected = smallHeader();
  EXPECT_EQ(log.header().name, "test log");
  EXPECT_EQ(log.header().map, "../maps/example.json");
  EXPECT_EQ(log.header().frame_rate_hz, 5.0);
  ASSERT_NE(log.header().camera, nullptr);
  EXPECT_EQ(log.header().camera->model(), expected.camera->model());
  EXPECT_EQ(log.header().camera->intrinsics(), expected.camera->intrinsics());
  EXPECT_EQ(log.header().camera->mount(), expected.camera->mount());
  EXPECT_EQ(*log.mapPath(), dir / "../maps/example.json");

  ASSERT_EQ(log.frames().size(), 3u);
  EXPECT_EQ(log.skipped(), 0u);
  EXPECT_TRUE(log.issues().empty());
  for (int k = 0; k < 3; ++k) {
    const LogFrame& f = log.frames()[static_cast<std::size_t>(k)];
    EXPECT_EQ(f.t, 0.2 * k);
    EXPECT_EQ(f.image, "images/00000" + std::to_string(k) + ".png");
    EXPECT_EQ(f.odometry.distance_m, 0.5 + 0.1 * k);
    EXPECT_DOUBLE_EQ(f.odometry.dheading_rad, degToRad(k == 0 ? 0.0 : 1.5 * k));
    ASSERT_TRUE(f.truth.has_value());
    EXPECT_POSE_NEAR(*f.truth, Pose2(1.0 + k, 2.0, degToRad(10.0 * k)), 1e-12);
    EXPECT_EQ(f.gnss.has_value(), k == 1);
    EXPECT_EQ(f.mask.has_value(), k % 2 == 0);
    const auto idx = static_cast<std::size_t>(k);
    EXPECT_EQ(log.image(idx), frameImage(k));
    const auto bytes = encodePng(frameImage(k));
    EXPECT_EQ(fileBytes(dir / f.image), std::string(bytes.begin(), bytes.end()));
    if (k % 2 == 0) {
      EXPECT_EQ(*f.mask, "masks/00000" + std::to_string(k) + ".png");
      EXPECT_EQ(log.mask(idx), maskImage(k));
    } else {
      EXPECT_FALSE(log.mask(idx).has_value());
    }
  }
  EXPECT_EQ(log.frames()[1].gnss->position, Vec2(2.5, 1.75));
  EXPECT_EQ(log.frames()[1].gnss->sigma_m, 3.0);
  EXPECT_THROW(log.image(3), InvalidInput);
  EXPECT_FALSE(fs::exists(dir.string() + ".partial-" + std::to_string(::getpid())));
}

TEST(ReplayLog, TheSameInputsGiveTheSameBytes) {
  const fs::path a = testing::freshTempDir() / "a";
  const fs::path b = testing::freshTempDir() / "b";
  writeLog(a, 3);
  writeLog(b, 3);
  for (const char* file : {"log.json", "frames.jsonl", "images/000001.png", "masks/000002.png"}) {
    EXPECT_EQ(fileBytes(a / file), fileBytes(b / file)) << file;
  }
}

TEST(ReplayLog, WriterLeavesNoFolderWithoutFinishOrOnException) {
  const fs::path dir = testing::freshTempDir() / "log";
  fs::path partial;
  {
    ReplayLogWriter writer(dir, smallHeader());
    partial = writer.partialDir();
    writer.add(makeFrame(0.0, 0.0, 0.0), frameImage(0));
    EXPECT_TRUE(fs::exists(partial / "images/000000.png"));
    EXPECT_FALSE(fs::exists(dir));
  }
  EXPECT_FALSE(fs::exists(dir));
  EXPECT_FALSE(fs::exists(partial));

  try {
    ReplayLogWriter writer(dir, smallHeader());
    writer.add(makeFrame(0.0, 0.0, 0.0), frameImage(0));
    throw std::runtime_error("the mission failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_FALSE(fs::exists(dir));
  EXPECT_FALSE(fs::exists(partial));
}

TEST(ReplayLog, WriterRejectsBadFramesAndRefusesToOverwrite) {
  const fs::path dir = testing::freshTempDir() / "log";
  {
    ReplayLogWriter writer(dir, smallHeader());
    writer.add(makeFrame(1.0, 0.0, 0.0), frameImage(0));
    EXPECT_THROW(writer.add(makeFrame(1.0, 0.0, 0.0), frameImage(1)), InvalidInput);  // t not increasing
    EXPECT_THROW(writer.add(makeFrame(2.0, std::numeric_limits<double>::infinity(), 0.0), frameImage(1)), InvalidInput);
    EXPECT_THROW(writer.add(makeFrame(2.0, 0.0, 0.0), Image(4, 4, 3)), InvalidInput);  // not the camera's size
    const Image rgb_mask(8, 6, 3);
    EXPECT_THROW(writer.add(makeFrame(2.0, 0.0, 0.0), frameImage(1), &rgb_mask), InvalidInput);
    EXPECT_EQ(writer.frameCount(), 1u);
  }
  LogHeader bad = smallHeader();
  bad.frame_rate_hz = 0.0;
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { ReplayLogWriter writer(dir, bad); },
                                                "LogHeader::frame_rate_hz = 0: must be finite and > 0"));
  bad = smallHeader();
  bad.camera = nullptr;
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { ReplayLogWriter writer(dir, bad); },
                                                "LogHeader::camera = 0: must be set (not null)"));
  ReadOptions no_lines;
  no_lines.max_line_bytes = 0;
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { ReplayLog::open(dir, no_lines); },
                                                "ReadOptions::max_line_bytes = 0: must be > 0"));

  fs::create_directories(dir);  // an empty folder is replaced
  writeLog(dir, 1);
  EXPECT_EQ(ReplayLog::open(dir).frames().size(), 1u);
  ReplayLogWriter again(dir, smallHeader());  // a full one is not
  EXPECT_THROW(again.finish(), IoError);
  EXPECT_EQ(ReplayLog::open(dir).frames().size(), 1u);
}

// ---- malformed frames.jsonl -------------------------------------------------------------------

TEST(ReplayLog, NotJsonLine) {
  const auto dir = logWithFrames(line(0, "images/000000.png") + "\nthis is not json\n" + line(2, "images/000002.png") + "\n");
  expectBadLine(dir, "log.not_json", 2);
}

TEST(ReplayLog, TruncatedLastLine) {
  const std::string full = line(2, "images/000002.png");
  const auto dir = logWithFrames(goodLines(2) + full.substr(0, full.size() / 2));
  expectBadLine(dir, "log.truncated", 3);
  // Skipped, it keeps what could be read of it (nothing: it is not JSON) and its line.
  ReadOptions skip;
  skip.skip_bad_frames = true;
  const ReplayLog log = ReplayLog::open(dir, skip);
  ASSERT_EQ(log.skippedLines().size(), 1u);
  EXPECT_EQ(log.skippedLines()[0].line, 3);
  EXPECT_EQ(log.skippedLines()[0].check, "log.truncated");
  EXPECT_FALSE(log.skippedLines()[0].t);
  EXPECT_EQ(log.lineOf(1), 2);
}

TEST(ReplayLog, LastLineWithoutNewlineIsFine) {
  std::string text = goodLines(3);
  text.pop_back();
  EXPECT_EQ(ReplayLog::open(logWithFrames(text)).frames().size(), 3u);
}

TEST(ReplayLog, MissingField) {
  const auto dir = logWithFrames(goodLines(1) + R"({"t": 1.0, "image": "images/000001.png"})" + "\n");
  expectBadLine(dir, "log.field", 2);
  const ValidationError e = expectInvalid(dir);
  EXPECT_NE(e.issues()[0].message.find("odometry"), std::string::npos) << e.what();
}

TEST(ReplayLog, WrongType) {
  const auto dir = logWithFrames(goodLines(2) +
                                 R"({"t": "2.0", "image": "images/000002.png", "odometry": {"distance_m": 0, "dheading_deg": 0}})" + "\n");
  expectBadLine(dir, "log.field", 3);
  EXPECT_EQ(expectInvalid(dir).issues()[0].where, "/t");
}

TEST(ReplayLog, TimeEqualOrDecreasing) {
  expectBadLine(logWithFrames(line(0, "images/000000.png") + "\n" + line(0, "images/000001.png") + "\n"), "log.time_order", 2);
  expectBadLine(logWithFrames(goodLines(3) + line(1.5, "images/000003.png") + "\n"), "log.time_order", 4);
}

TEST(ReplayLog, OverflowingOdometry) {
  const auto dir = logWithFrames(
      goodLines(1) + R"({"t": 1, "image": "images/000001.png", "odometry": {"distance_m": 1e999, "dheading_deg": 0}})" + "\n");
  expectBadLine(dir, "log.not_finite", 2);
}

TEST(ReplayLog, MissingImage) {
  expectBadLine(logWithFrames(goodLines(2) + line(2, "images/000099.png") + "\n"), "log.missing_image", 3);
  expectBadLine(logWithFrames(line(0, "images/000000.png", R"(, "mask": "masks/000077.png")") + "\n"), "log.missing_image", 1);
}

TEST(ReplayLog, CorruptImageWithVerifyImages) {
  const auto dir = logWithFrames(goodLines(3));
  writeFileAtomic(dir / "images/000001.png", std::string_view("\x89PNG\r\n\x1a\n not really"));
  EXPECT_EQ(ReplayLog::open(dir).frames().size(), 3u);  // not decoded without verify_images
  ReadOptions options;
  options.verify_images = true;
  expectBadLine(dir, "log.corrupt_image", 2, options);
}

TEST(ReplayLog, ImagePathOutsideTheFolder) {
  const auto dir = logWithFrames(goodLines(1) + line(1, "../x.png") + "\n");
  writePng(frameImage(0), dir.parent_path() / "x.png");  // it exists, and is still refused
  expectBadLine(dir, "log.bad_path", 2);
  expectBadLine(logWithFrames(line(0, "/etc/passwd") + "\n"), "log.bad_path", 1);
  expectBadLine(logWithFrames(line(0, "images/../../x.png") + "\n"), "log.bad_path", 1);
}

TEST(ReplayLog, SkipModeCountsBadFramesWithTheirLines) {
  const std::string text = line(0, "images/000000.png") + "\n" + "{oops\n" + line(2, "images/000002.png") + "\n" +
                           line(1, "images/000003.png") + "\n" + line(4, "images/000004.png") + "\n";
  const auto dir = logWithFrames(text);
  expectBadLine(dir, "log.not_json", 2);
  ReadOptions options;
  options.skip_bad_frames = true;
  const ReplayLog log = ReplayLog::open(dir, options);
  EXPECT_EQ(log.skipped(), 2u);
  ASSERT_EQ(log.frames().size(), 3u);
  EXPECT_EQ(log.frames()[2].image, "images/000004.png");
  ASSERT_EQ(log.issues().size(), 2u);
  EXPECT_EQ(log.issues()[0].check, "log.not_json");
  EXPECT_EQ(log.issues()[0].line, 2);
  EXPECT_EQ(log.issues()[1].check, "log.time_order");
  EXPECT_EQ(log.issues()[1].line, 4);
  for (const Issue& issue : log.issues()) EXPECT_EQ(issue.severity, Severity::Warning);
}

TEST(ReplayLog, EmptyFramesIsValidMissingIsAnIoError) {
  const auto dir = logWithFrames("");
  EXPECT_TRUE(ReplayLog::open(dir).frames().empty());
  fs::remove(dir / "frames.jsonl");
  EXPECT_THROW(ReplayLog::open(dir), IoError);
}

TEST(ReplayLog, NeverCrashesOnGarbage) {
  std::string garbage;
  for (int i = 0; i < 4096; ++i) garbage += static_cast<char>((i * 131 + 7) % 256);
  const auto dir = logWithFrames(goodLines(1) + garbage);
  EXPECT_THROW(ReplayLog::open(dir), ValidationError);
  ReadOptions skip;
  skip.skip_bad_frames = true;
  EXPECT_NO_THROW(ReplayLog::open(dir, skip));

  const auto long_dir = logWithFrames(goodLines(1) + R"({"t": 1, "image": ")" + std::string(10 << 20, 'a') + "\"}\n");
  expectBadLine(long_dir, "log.line_too_long", 2);
  const auto nested = logWithFrames(std::string(100000, '[') + "\n");
  expectBadLine(nested, "log.not_json", 1);
}

// ---- log.json ---------------------------------------------------------------------------------

/// A valid log whose log.json is edited by `edit`; returns the first log.json issue.
Issue badHeader(const std::function<void(Json&)>& edit) {
  const fs::path dir = testing::freshTempDir() / "log";
  writeLog(dir, 1);
  Json doc = Json::parse(readFile(dir / "log.json"));
  edit(doc);
  writeFileAtomic(dir / "log.json", dumpJson(doc));
  const ValidationError e = expectInvalid(dir);
  EXPECT_EQ(fs::path(e.file()).filename(), "log.json");
  if (e.issues().empty()) return {};
  return e.issues()[0];
}

TEST(ReplayLog, BadLogJson) {
  Issue issue = badHeader([](Json& doc) { doc["format"] = "mapnav-log/2"; });
  EXPECT_EQ(issue.check, "schema.format");
  EXPECT_EQ(issue.where, "/format");
  issue = badHeader([](Json& doc) { doc["camera"]["focal_px"][0] = -1.0; });
  EXPECT_EQ(issue.check, "schema.range");
  EXPECT_EQ(issue.where, "/camera/focal_px/0");
  issue = badHeader([](Json& doc) { doc["camera"].erase("mount"); });
  EXPECT_EQ(issue.check, "schema.required");
  EXPECT_EQ(issue.where, "/camera");
  issue = badHeader([](Json& doc) { doc["frame_rate_hz"] = 0.0; });
  EXPECT_EQ(issue.check, "schema.range");
  EXPECT_EQ(issue.where, "/frame_rate_hz");
  issue = badHeader([](Json& doc) { doc["frame_rate_hz"] = -5; });
  EXPECT_EQ(issue.where, "/frame_rate_hz");
  EXPECT_EQ(issue.message, "LogHeader::frame_rate_hz = -5: must be finite and > 0");  // LogHeader::validate()'s rule
  issue = badHeader([](Json& doc) { doc["units"]["angle"] = "rad"; });
  EXPECT_EQ(issue.check, "schema.enum");
  EXPECT_EQ(issue.where, "/units/angle");
  issue = badHeader([](Json& doc) { doc["surprise"] = 1; });
  EXPECT_EQ(issue.check, "schema.unknown_field");

  const fs::path dir = testing::freshTempDir() / "log";
  writeLog(dir, 1);
  writeFileAtomic(dir / "log.json", "{\"format\": ");
  const ValidationError e = expectInvalid(dir);
  ASSERT_FALSE(e.issues().empty());
  EXPECT_EQ(e.issues()[0].check, "json.syntax");
  EXPECT_EQ(e.issues()[0].line, 1);
}

TEST(ReplayLog, ExtensionsAreAllowed) {
  const fs::path dir = testing::freshTempDir() / "log";
  writeLog(dir, 1);
  Json doc = Json::parse(readFile(dir / "log.json"));
  doc["x-recorded-by"] = "test";
  doc["$schema"] = "../maps/schema/mapnav-log-1.schema.json";
  writeFileAtomic(dir / "log.json", dumpJson(doc));
  writeFileAtomic(dir / "frames.jsonl", line(0, "images/000000.png", R"(, "x-note": "hi")") + "\n");
  EXPECT_EQ(ReplayLog::open(dir).frames().size(), 1u);
}

TEST(ReplayLog, MissingLogJsonIsAnIoError) {
  const fs::path dir = testing::freshTempDir() / "log";
  writeLog(dir, 1);
  fs::remove(dir / "log.json");
  EXPECT_THROW(ReplayLog::open(dir), IoError);
  EXPECT_THROW(ReplayLog::open(testing::freshTempDir() / "nowhere"), IoError);
}

TEST(ReplayLog, ReadOptionsValidate) {
  ReadOptions options;
  EXPECT_NO_THROW(options.validate());
  options.max_line_bytes = 0;
  EXPECT_THROW(options.validate(), InvalidInput);
}

}  // namespace
}  // namespace mapnav
