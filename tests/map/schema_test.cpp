// The JSON Schema in maps/schema and the C++ loader must agree: run Debian's python3-jsonschema
// (through scripts/check_schema.py) over the examples and fixtures and compare verdicts.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <sstream>

#include "mapnav/core/io.h"
#include "mapnav/core/json.h"
#include "mapnav/map/map_io.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;

// FILE → true when the schema accepts it.
std::map<std::string, bool> schemaVerdicts(const std::vector<fs::path>& files) {
  std::string command = std::string(MAPNAV_SYSTEM_PYTHON) + " " + (testing::sourceDir() / "scripts/check_schema.py").string() +
                        " " + (testing::sourceDir() / "maps/schema/mapnav-map-1.schema.json").string();
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

}  // namespace
}  // namespace mapnav
