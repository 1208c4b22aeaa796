// The JSON Schema in maps/schema and the C++ loader must agree: run Debian's python3-jsonschema
// (through scripts/check_schema.py) over the examples and fixtures and compare verdicts.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <sstream>
#include <tuple>

#include "mapnav/core/io.h"
#include "mapnav/core/json.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/map/map_io.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;

// FILE → true when the schema accepts it.
std::map<std::string, bool> schemaVerdicts(const std::vector<fs::path>& files,
                                           const std::string& schema = "mapnav-map-1.schema.json") {
  std::string command = std::string(MAPNAV_SYSTEM_PYTHON) + " " + (testing::sourceDir() / "scripts/check_schema.py").string() +
                        " " + (testing::sourceDir() / "maps/schema" / schema).string();
  for (const fs::path& f : files) command += " '" + f.string() + "'";
  command += " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  EXPECT_NE(pipe, nullptr);
  std::string output;
  char buffer[4096];
  while (pipe != nullptr && std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  if (pipe != nullptr) ::pclose(pipe);
  std::map<std::string, bool> verdicts;
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) {
    for (const fs::path& f : files) {
      const std::string prefix = f.string() + ": ";
      if (line.rfind(prefix, 0) == 0) verdicts[f.string()] = line.substr(prefix.size(), 2) == "ok";
    }
  }
  EXPECT_EQ(verdicts.size(), files.size()) << output;
  return verdicts;
}

bool loaderAccepts(const fs::path& file) {
  Issues issues;
  return loadMap(file, issues).has_value();
}

TEST(MapSchema, AcceptsEveryExampleAndValidFixture) {
  const std::vector<fs::path> files{testing::mapPath("cmu_campus.json"), testing::mapPath("park_path.json"),
                                    testing::fixturePath("maps/valid/minimal.json")};
  for (const auto& [file, ok] : schemaVerdicts(files)) {
    EXPECT_TRUE(ok) << file;
    EXPECT_TRUE(loaderAccepts(file)) << file;
  }
}

// Where the schema can see a problem (x-expect.schema_rejects), schema and loader both reject;
// where it cannot (references between objects, geometry), only the loader does.
TEST(MapSchema, AgreesWithTheLoaderOnEveryInvalidFixture) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(testing::fixturePath("maps/invalid"))) files.push_back(entry.path());
  const auto verdicts = schemaVerdicts(files);
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.filename().string());
    const Json expect = Json::parse(readFile(file))["x-expect"];
    const bool schema_rejects = expect["schema_rejects"];
    EXPECT_EQ(!verdicts.at(file.string()), schema_rejects);
    if (schema_rejects) {
      EXPECT_FALSE(loaderAccepts(file));
    }
  }
}

TEST(MapSchema, RejectsEveryMalformedMapFile) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(testing::fixturePath("malformed"))) {
    if (entry.path().extension() == ".json") files.push_back(entry.path());
  }
  ASSERT_GE(files.size(), 18u);
  for (const auto& [file, ok] : schemaVerdicts(files)) {
    EXPECT_FALSE(ok) << file;
    EXPECT_FALSE(loaderAccepts(file)) << file;
  }
}

// ---- cameras (mapnav-camera/1) -----------------------------------------------------------------------

constexpr const char* kCameraSchema = "mapnav-camera-1.schema.json";

bool cameraLoaderAccepts(const fs::path& file) {
  Issues issues;
  return parseCamera(readFile(file), issues) != nullptr;
}

TEST(CameraSchema, AcceptsBothTerregatorCameras) {
  const std::vector<fs::path> files{testing::mapPath("cameras/terregator_pinhole.json"),
                                    testing::mapPath("cameras/terregator_fisheye.json")};
  for (const auto& [file, ok] : schemaVerdicts(files, kCameraSchema)) {
    EXPECT_TRUE(ok) << file;
    EXPECT_TRUE(cameraLoaderAccepts(file)) << file;
  }
}

TEST(CameraSchema, AgreesWithTheLoader) {
  const std::string mount = R"("mount": {"height_m": 1.5, "tilt_deg": 22})";
  auto camera = [&](const std::string& model, const std::string& middle, const std::string& tail) {
    return R"({"format": "mapnav-camera/1", "model": ")" + model + R"(", "image": {"width": 512, "height": 480}, )" + middle +
           R"("principal_point": [255.5, 239.5], )" + tail + "}";
  };
  // name → (text, valid)
  const std::vector<std::tuple<std::string, std::string, bool>> cases{
      {"pinhole5", camera("pinhole", R"("focal_px": [904, 904], "distortion": [-0.2, 0.05, 0.001, -0.001, 0], )", mount), true},
      {"equidistant4", camera("fisheye-equidistant", R"("focal_px": [180, 180], "distortion": [0.05, -0.01, 0.002, -0.0005], )",
                              mount), true},
      {"integral_float_width", R"({"format": "mapnav-camera/1", "model": "pinhole", "image": {"width": 512.0, "height": 480},
        "focal_px": [904, 904], "principal_point": [255.5, 239.5], "mount": {"height_m": 1.5, "tilt_deg": 22}})", true},
      {"negative_focal", camera("pinhole", R"("focal_px": [-3, 904], )", mount), false},
      {"unknown_model", camera("fisheye", R"("focal_px": [904, 904], )", mount), false},
      {"pinhole3", camera("pinhole", R"("focal_px": [904, 904], "distortion": [-0.2, 0.05, 0.001], )", mount), false},
      {"paper4", camera("fisheye-orthographic", R"("focal_px": [257, 257], "distortion": [0, 0, 0, 0], )", mount), false},
      {"equidistant5", camera("fisheye-equidistant", R"("focal_px": [180, 180], "distortion": [0, 0, 0, 0, 0], )", mount),
       false},
      {"missing_mount", camera("pinhole", R"("focal_px": [904, 904], )", R"("x-mount": {})"), false},
      {"unknown_member", camera("pinhole", R"("focal_px": [904, 904], "lens": "zoom", )", mount), false},
      {"tilt_95", camera("pinhole", R"("focal_px": [904, 904], )", R"("mount": {"height_m": 1.5, "tilt_deg": 95})"), false},
      {"zero_height", camera("pinhole", R"("focal_px": [904, 904], )", R"("mount": {"height_m": 0, "tilt_deg": 9})"), false},
  };
  const fs::path dir = testing::freshTempDir();
  std::vector<fs::path> files;
  for (const auto& [name, text, valid] : cases) {
    files.push_back(dir / (name + ".json"));
    writeFileAtomic(files.back(), text);
  }
  const auto verdicts = schemaVerdicts(files, kCameraSchema);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(std::get<0>(cases[i]));
    EXPECT_EQ(verdicts.at(files[i].string()), std::get<2>(cases[i]));
    EXPECT_EQ(cameraLoaderAccepts(files[i]), std::get<2>(cases[i]));
  }
}

}  // namespace
}  // namespace mapnav
