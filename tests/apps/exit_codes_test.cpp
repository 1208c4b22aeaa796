// The exit codes of `mapnav`, by the kind of mistake and the same in every command, whichever check
// finds it (CLI11's parse, its range checks, a command's own parse, the library): 2 the command line
// itself is wrong or a file cannot be read; 1 what was given is wrong. Run end to end on the built tool.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;
using testing::runCli;

// No command, an unknown one, a missing argument (one CLI11 requires, one only another makes
// necessary: predict's pose), not a number where one is due, a file that is not there.
TEST(Cli, UsageErrorsExitTwo) {
  const std::string map = testing::mapPath("cmu_campus.json").string();
  const std::string camera = testing::mapPath("cameras/terregator_pinhole.json").string();
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {}, {"frobnicate"}, {"map"}, {"map", "validate"}, {"map", "render", map},
           {"map", "validate", "/no/such/file.json"}, {"map", "render", "--width", "many", map, "-o", "x.png"},
           {"route", "--map", map, "--from", "R1@I1+3"}, {"predict", "--map", map, "--camera", camera}}) {
    const auto r = runCli(args);
    EXPECT_EQ(r.exit_code, 2) << (args.empty() ? "" : args.back());
    EXPECT_NE(r.err.find("mapnav: error: "), std::string::npos) << r.err;
  }
}

// What was given is wrong, whichever check finds it (CLI11's range check, a command's own parse, the
// library): exit 1 in every command, the message naming the option.
TEST(Cli, WrongValuesExitOneInEveryCommand) {
  const std::string map = testing::mapPath("cmu_campus.json").string();
  const fs::path dir = testing::freshTempDir();
  struct Case {
    std::vector<std::string> args;
    std::string names;
  };
  for (const Case& c : std::vector<Case>{
           {{"map", "render", "--width", "3", map, "-o", (dir / "x.png").string()}, "--width"},
           {{"map", "import-geojson", testing::mapPath("cmu_campus.geojson").string(), "-o", (dir / "x.json").string(),
             "--origin", "91,0"},
            "--origin \"91,0\""},
           {{"log", "import-kitti-raw", dir.string(), "-o", (dir / "log").string(), "--origin", "91,0"}, "--origin"},
           {{"route", "--map", map, "--from", "R1", "--to", "R3@I3+2"}, "R1"},
           {{"suite", "random-campus", "--seeds", "1", "--junctions", "0"}, "--junctions"},
           {{"run", "--mission", testing::mapPath("missions/campus_dialogue.json").string(), "--map-options",
             R"({"park_reset_sigma_m": 0})"},
            "--map-options: MapModuleOptions: option park_reset_sigma_m = 0: must be > 0"},
           {{"suite", "random-campus", "--seeds", "1", "--map-options", R"({"park_reset_sigm": 1})"},
            "--map-options: MapModuleOptions: unknown option \"park_reset_sigm\""}}) {
    const auto r = runCli(c.args);
    EXPECT_EQ(r.exit_code, 1) << c.args[0] << " " << c.args[1] << ": " << r.err;
    EXPECT_EQ(r.err.rfind("mapnav: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(c.names), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  EXPECT_FALSE(fs::exists(dir / "x.png"));
  EXPECT_FALSE(fs::exists(dir / "x.json"));
  EXPECT_FALSE(fs::exists(dir / "log"));
}

TEST(Cli, BadOriginIsWrongInput) {
  const fs::path dir = testing::freshTempDir();
  for (const std::string origin : {"40.4", "91,0", "40.4,abc", "40,-80,1,2"}) {
    const auto r = runCli({"map", "export-geojson", testing::mapPath("cmu_campus.json").string(), "-o", (dir / "x.geojson").string(),
                           "--origin", origin});
    EXPECT_EQ(r.exit_code, 1) << origin;
    EXPECT_NE(r.err.find("--origin"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "x.geojson"));
}

// A value out of its range or not understood is wrong input (1); one CLI11's type check rejects
// (not a number for a numeric option) is a usage error (2).
TEST(Cli, BenchRefusesBadOptionsNamingTheOption) {
  struct Case {
    std::vector<std::string> args;
    std::string option;
    int exit_code;
  };
  for (const Case& c : std::vector<Case>{{{"--sizes", "8"}, "--sizes", 1},
                                         {{"--sizes", "64,5000"}, "--sizes", 1},
                                         {{"--sizes", "64,abc"}, "--sizes", 1},
                                         {{"--sizes", "64.5"}, "--sizes", 1},
                                         {{"--sizes", ""}, "--sizes", 1},
                                         {{"--min-time", "0"}, "--min-time", 1},
                                         {{"--min-time", "-1"}, "--min-time", 1},
                                         {{"--min-time", "soon"}, "--min-time", 1},
                                         {{"--threads", "-1"}, "--threads", 1},
                                         {{"--threads", "many"}, "--threads", 2},
                                         {{"--road-model", "curve"}, "--road-model", 1},
                                         {{"--route-sizes", "2"}, "--route-sizes", 1},
                                         {{"--route-sizes", "100,5e6"}, "--route-sizes", 1},
                                         {{"--route-sizes", "100.5"}, "--route-sizes", 1},
                                         {{"--irregular-route-sizes", "2"}, "--irregular-route-sizes", 1},
                                         {{"--loop-frames", "-1"}, "--loop-frames", 1}}) {
    std::vector<std::string> args{"bench"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const auto r = runCli(args);
    EXPECT_EQ(r.exit_code, c.exit_code) << c.args.back();
    EXPECT_NE(r.err.find("mapnav: error: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.option), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
}

}  // namespace
}  // namespace mapnav
