#include "mapnav/geometry/camera_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/geometry/polygon.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

std::unique_ptr<Camera> load(const std::string& name) { return loadCamera(testing::mapPath("cameras/" + name)); }

void expectSameCamera(const Camera& a, const Camera& b) {
  EXPECT_EQ(a.model(), b.model());
  EXPECT_EQ(a.intrinsics(), b.intrinsics());  // every double to the bit
  EXPECT_EQ(a.mount(), b.mount());
}

TEST(CameraJson, LoadsTheTerregatorPinhole) {
  const auto cam = load("terregator_pinhole.json");
  ASSERT_TRUE(cam);
  EXPECT_EQ(cam->model(), LensModel::Pinhole);
  EXPECT_EQ(cam->width(), 512);
  EXPECT_EQ(cam->height(), 480);
  EXPECT_EQ(cam->intrinsics().fx, 904.0);
  EXPECT_EQ(cam->intrinsics().fy, 904.0);
  EXPECT_EQ(cam->intrinsics().cx, 255.5);
  EXPECT_EQ(cam->intrinsics().cy, 239.5);
  EXPECT_TRUE(cam->intrinsics().distortion.empty());
  EXPECT_EQ(cam->mount().height_m, 1.5);
  EXPECT_EQ(cam->mount().tilt_rad, degToRad(22.0));
  EXPECT_EQ(cam->mount().roll_rad, 0.0);
  EXPECT_EQ(cam->mount().yaw_rad, 0.0);
  EXPECT_EQ(cam->mount().offset, Vec2(0, 0));
  // What its x-note says: 2.00 m ahead at the bottom edge, 11.99 m at the top, the trapezoid
  // 1.37 m wide near and 6.61 m far.
  EXPECT_NEAR(cam->backproject(Vec2(255.5, 479.5))->x(), 2.00, 0.005);
  EXPECT_NEAR(cam->backproject(Vec2(255.5, -0.5))->x(), 11.99, 0.005);
  const Polygon2 footprint = viewFootprint(*cam, 0.5, 30.0);
  ASSERT_EQ(footprint.size(), 4u);
  double near_width = 0, far_width = 0;
  for (const Vec2& p : footprint) (p.x() < 5 ? near_width : far_width) += std::abs(p.y());
  EXPECT_NEAR(near_width, 1.37, 0.005);
  EXPECT_NEAR(far_width, 6.61, 0.005);
}

TEST(CameraJson, LoadsTheTerregatorFisheye) {
  const auto cam = load("terregator_fisheye.json");
  ASSERT_TRUE(cam);
  EXPECT_EQ(cam->model(), LensModel::PaperFisheye);
  EXPECT_EQ(cam->intrinsics().fx, 257.0);
  EXPECT_EQ(cam->mount().tilt_rad, degToRad(20.0));
  // What its x-note says.
  EXPECT_NEAR(radToDeg(std::asin(256.0 / 257.0)), 85.0, 0.1);
  EXPECT_NEAR(cam->projectGround(Vec2(1, 0))->y(), 392, 0.5);
  EXPECT_NEAR(cam->projectGround(Vec2(2, 0))->y(), 314, 0.5);
  EXPECT_NEAR(cam->projectGround(Vec2(12, 0))->y(), 182, 0.5);
  EXPECT_NEAR(cam->backproject(Vec2(255.5, 479.5))->x(), 0.03, 0.005);
  EXPECT_FALSE(cam->backproject(Vec2(255.5, 151.0)));
  EXPECT_TRUE(cam->backproject(Vec2(255.5, 152.0)));
  EXPECT_FALSE(cam->ray(Vec2(-0.5, -0.5)));  // the corners are outside the lens' circle
  // The sidewalk 1 m to 12 m ahead is in view, a curved region.
  const Polygon2 footprint = viewFootprint(*cam, 1.0, 12.0);
  EXPECT_GT(footprint.size(), 4u);
  EXPECT_TRUE(contains(footprint, Vec2(1.2, 0)));
  EXPECT_TRUE(contains(footprint, Vec2(11.8, 2)));
}

TEST(CameraJson, ReadsTheName) {
  Issues issues;
  std::string name;
  const auto cam = parseCamera(readFile(testing::mapPath("cameras/terregator_pinhole.json")), issues, &name);
  ASSERT_TRUE(cam);
  EXPECT_TRUE(issues.empty());
  EXPECT_EQ(name, "Terregator camera, pin-hole model");
}

TEST(CameraJson, RoundTripIsExact) {
  for (const char* file : {"terregator_pinhole.json", "terregator_fisheye.json"}) {
    SCOPED_TRACE(file);
    const auto cam = load(file);
    const std::string text = cameraToJson(*cam, "again");
    Issues issues;
    std::string name;
    const auto back = parseCamera(text, issues, &name);
    ASSERT_TRUE(back) << text;
    EXPECT_TRUE(issues.empty());
    EXPECT_EQ(name, "again");
    expectSameCamera(*back, *cam);
    EXPECT_FALSE(std::signbit(back->mount().roll_rad));  // 0, not −0
    EXPECT_NE(text.find("\"tilt_deg\": " + std::string(cam->model() == LensModel::Pinhole ? "22.0" : "20.0")),
              std::string::npos);
    EXPECT_EQ(cameraToJson(*back, "again"), text);
  }
  // Every member, with distortion, an offset and angles given in radians.
  CameraIntrinsics in;
  in.width = 640;
  in.height = 360;
  in.fx = 401.25;
  in.fy = 399.0 + 1e-9;
  in.cx = 0.1 + 0.2;
  in.cy = 181.75;
  in.distortion = {-0.2, 0.05, 0.001, -0.001, 1.0 / 3.0};
  CameraMount m;
  m.offset = Vec2(0.35, -0.125);
  m.height_m = 0.9;
  m.tilt_rad = 0.38;
  m.roll_rad = degToRad(-2.5);
  m.yaw_rad = -0.2;
  for (LensModel model : {LensModel::Pinhole, LensModel::EquidistantFisheye, LensModel::PaperFisheye}) {
    SCOPED_TRACE(toString(model));
    CameraIntrinsics with = in;
    if (model == LensModel::EquidistantFisheye) with.distortion = {0.05, -0.01, 0.002, -0.0005};
    if (model == LensModel::PaperFisheye) with.distortion.clear();
    const auto cam = createCamera(model, with, m);
    const std::string text = cameraToJson(*cam);
    EXPECT_EQ(text.find("\"name\""), std::string::npos);
    Issues issues;
    const auto back = parseCamera(text, issues);
    ASSERT_TRUE(back) << text;
    EXPECT_EQ(back->model(), model);
    EXPECT_EQ(back->intrinsics(), with);
    EXPECT_EQ(back->mount().offset, m.offset);
    EXPECT_EQ(back->mount().height_m, m.height_m);
    EXPECT_EQ(back->mount().roll_rad, m.roll_rad);  // came from degrees: exact
    // Radians that no decimal number of degrees gives exactly come back within an ulp or two.
    EXPECT_DOUBLE_EQ(back->mount().tilt_rad, m.tilt_rad);
    EXPECT_DOUBLE_EQ(back->mount().yaw_rad, m.yaw_rad);
  }
  // Angles beyond the format's ranges: roll and yaw are wrapped, a tilt past ±90° cannot be written.
  m.yaw_rad = degToRad(270.0);
  Issues issues;
  const auto wrapped = parseCamera(cameraToJson(*createCamera(LensModel::Pinhole, in, m)), issues);
  ASSERT_TRUE(wrapped);
  EXPECT_NEAR(wrapped->mount().yaw_rad, degToRad(-90.0), 1e-12);
  m.tilt_rad = degToRad(100.0);
  EXPECT_THROW(cameraToJson(*createCamera(LensModel::Pinhole, in, m)), InvalidInput);
}

TEST(CameraJson, OptionalMembersTakeTheirDefaults) {
  Issues issues;
  const auto cam = parseCamera(R"({"format": "mapnav-camera/1", "model": "fisheye-equidistant",
    "image": {"width": 320.0, "height": 240, "x-sensor": "1/3 inch"},
    "focal_px": [100, 100], "principal_point": [159.5, 119.5],
    "mount": {"height_m": 0.5, "tilt_deg": -10, "x-mounted-by": "hand"}, "x-note": "no distortion, no name"})",
                               issues);
  ASSERT_TRUE(cam) << (issues.empty() ? "" : formatIssue(issues[0], "text"));
  EXPECT_TRUE(issues.empty());
  EXPECT_EQ(cam->width(), 320);
  EXPECT_TRUE(cam->intrinsics().distortion.empty());
  EXPECT_EQ(cam->mount().offset, Vec2(0, 0));
  EXPECT_EQ(cam->mount().roll_rad, 0.0);
  EXPECT_EQ(cam->mount().yaw_rad, 0.0);
  EXPECT_EQ(cam->mount().tilt_rad, degToRad(-10.0));
}

struct BadCamera {
  const char* what;
  std::string text;
  std::string check;
  std::string where;
};

// A valid pin-hole with one thing changed per case.
std::string pinholeWith(const std::string& focal, const std::string& model = "\"pinhole\"",
                        const std::string& distortion = "[]", const std::string& mount = R"({"height_m": 1.5, "tilt_deg": 22})",
                        const std::string& extra = "") {
  return R"({"format": "mapnav-camera/1", "name": "bad", "model": )" + model +
         R"(, "image": {"width": 512, "height": 480}, "focal_px": )" + focal +
         R"(, "principal_point": [255.5, 239.5], "distortion": )" + distortion + R"(, "mount": )" + mount + extra + "}";
}

std::vector<BadCamera> badCameras() {
  const std::string ok_focal = "[904, 904]";
  return {
      {"negative focal", pinholeWith("[-3, 904]"), "schema.range", "/focal_px/0"},
      {"zero focal", pinholeWith("[904, 0]"), "schema.range", "/focal_px/1"},
      {"one focal", pinholeWith("[904]"), "schema.type", "/focal_px"},
      {"string focal", pinholeWith("[904, \"904\"]"), "schema.type", "/focal_px/1"},
      {"huge focal", pinholeWith("[904, 1e999]"), "json.not_finite", ""},  // with its line and column
      {"unknown model", pinholeWith(ok_focal, "\"fisheye\""), "schema.enum", "/model"},
      {"model not a string", pinholeWith(ok_focal, "3"), "schema.type", "/model"},
      {"3 coefficients, pinhole", pinholeWith(ok_focal, "\"pinhole\"", "[-0.2, 0.05, 0.001]"), "camera.distortion_count",
       "/distortion"},
      {"6 coefficients, pinhole", pinholeWith(ok_focal, "\"pinhole\"", "[0, 0, 0, 0, 0, 0]"), "camera.distortion_count",
       "/distortion"},
      {"4 coefficients, paper fisheye", pinholeWith(ok_focal, "\"fisheye-orthographic\"", "[0.1, 0, 0, 0]"),
       "camera.distortion_count", "/distortion"},
      {"5 coefficients, equidistant", pinholeWith(ok_focal, "\"fisheye-equidistant\"", "[0.1, 0, 0, 0, 0]"),
       "camera.distortion_count", "/distortion"},
      {"distortion not an array", pinholeWith(ok_focal, "\"pinhole\"", "\"none\""), "schema.type", "/distortion"},
      {"distortion not numbers", pinholeWith(ok_focal, "\"pinhole\"", "[0, \"0\", 0, 0]"), "schema.type", "/distortion/1"},
      {"missing mount", R"({"format": "mapnav-camera/1", "model": "pinhole", "image": {"width": 512, "height": 480},
        "focal_px": [904, 904], "principal_point": [255.5, 239.5]})",
       "schema.required", ""},
      {"missing image", R"({"format": "mapnav-camera/1", "model": "pinhole", "focal_px": [904, 904],
        "principal_point": [255.5, 239.5], "mount": {"height_m": 1.5, "tilt_deg": 22}})",
       "schema.required", ""},
      {"unknown member", pinholeWith(ok_focal, "\"pinhole\"", "[]", R"({"height_m": 1.5, "tilt_deg": 22})", R"(, "lens": "zoom")"),
       "schema.unknown_field", "/lens"},
      {"unknown mount member", pinholeWith(ok_focal, "\"pinhole\"", "[]", R"({"height_m": 1.5, "tilt_deg": 22, "pitch_deg": 3})"),
       "schema.unknown_field", "/mount/pitch_deg"},
      {"missing tilt", pinholeWith(ok_focal, "\"pinhole\"", "[]", R"({"height_m": 1.5})"), "schema.required", "/mount"},
      {"zero height", pinholeWith(ok_focal, "\"pinhole\"", "[]", R"({"height_m": 0, "tilt_deg": 22})"), "schema.range",
       "/mount/height_m"},
      {"tilt beyond 90", pinholeWith(ok_focal, "\"pinhole\"", "[]", R"({"height_m": 1.5, "tilt_deg": 95})"), "schema.range",
       "/mount/tilt_deg"},
      {"yaw beyond 180", pinholeWith(ok_focal, "\"pinhole\"", "[]", R"({"height_m": 1.5, "tilt_deg": 22, "yaw_deg": -200})"),
       "schema.range", "/mount/yaw_deg"},
      {"mount not an object", pinholeWith(ok_focal, "\"pinhole\"", "[]", "[1.5, 22]"), "schema.type", "/mount"},
      {"wrong format", R"({"format": "mapnav-camera/2", "model": "pinhole", "image": {"width": 512, "height": 480},
        "focal_px": [904, 904], "principal_point": [255.5, 239.5], "mount": {"height_m": 1.5, "tilt_deg": 22}})",
       "schema.format", "/format"},
      {"zero width", R"({"format": "mapnav-camera/1", "model": "pinhole", "image": {"width": 0, "height": 480},
        "focal_px": [904, 904], "principal_point": [255.5, 239.5], "mount": {"height_m": 1.5, "tilt_deg": 22}})",
       "schema.range", "/image/width"},
      {"fractional height", R"({"format": "mapnav-camera/1", "model": "pinhole", "image": {"width": 512, "height": 480.5},
        "focal_px": [904, 904], "principal_point": [255.5, 239.5], "mount": {"height_m": 1.5, "tilt_deg": 22}})",
       "schema.type", "/image/height"},
      {"not an object", "[1, 2]", "schema.type", ""},
  };
}

TEST(CameraJson, EveryProblemHasItsCheckAndPointer) {
  for (const BadCamera& bad : badCameras()) {
    SCOPED_TRACE(bad.what);
    Issues issues;
    EXPECT_FALSE(parseCamera(bad.text, issues));
    ASSERT_EQ(issues.size(), 1u) << (issues.empty() ? "" : formatIssue(issues[0], "text") + " ...");
    EXPECT_EQ(issues[0].severity, Severity::Error);
    EXPECT_EQ(issues[0].check, bad.check) << formatIssue(issues[0], "text");
    EXPECT_EQ(issues[0].where, bad.where) << formatIssue(issues[0], "text");
  }
}

TEST(CameraJson, ReportsEveryProblemAtOnce) {
  Issues issues;
  EXPECT_FALSE(parseCamera(R"({"format": "mapnav-camera/1", "model": "zoom", "image": {"width": -1, "height": 480},
    "focal_px": [0, 904], "principal_point": [255.5, 239.5], "mount": {"height_m": -1, "tilt_deg": 22}, "colour": 1})",
                           issues));
  std::vector<std::pair<std::string, std::string>> found;
  for (const Issue& i : issues) found.emplace_back(i.check, i.where);
  const std::vector<std::pair<std::string, std::string>> expected{{"schema.enum", "/model"},
                                                                  {"schema.range", "/image/width"},
                                                                  {"schema.range", "/focal_px/0"},
                                                                  {"schema.range", "/mount/height_m"},
                                                                  {"schema.unknown_field", "/colour"}};
  EXPECT_EQ(found, expected);
}

TEST(CameraJson, SyntaxErrorsHaveALine) {
  Issues issues;
  EXPECT_FALSE(parseCamera("{\"format\": \"mapnav-camera/1\",\n  \"model\": }", issues));
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].check, "json.syntax");
  EXPECT_EQ(issues[0].line, 2);
}

TEST(CameraJson, LoadCameraThrows) {
  const auto dir = testing::freshTempDir();
  EXPECT_THROW(loadCamera(dir / "missing.json"), IoError);
  writeFileAtomic(dir / "bad.json", pinholeWith("[-3, 904]"));
  try {
    loadCamera(dir / "bad.json");
    FAIL() << "no exception";
  } catch (const ValidationError& e) {
    EXPECT_EQ(e.file(), (dir / "bad.json").string());
    ASSERT_EQ(e.issues().size(), 1u);
    EXPECT_EQ(e.issues()[0].where, "/focal_px/0");
  }
  writeFileAtomic(dir / "good.json", cameraToJson(*load("terregator_fisheye.json")));
  expectSameCamera(*loadCamera(dir / "good.json"), *load("terregator_fisheye.json"));
}

}  // namespace
}  // namespace mapnav
