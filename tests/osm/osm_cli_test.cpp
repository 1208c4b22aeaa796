// `mapnav map import-osm` end to end: what it prints, exit codes, and that a failure writes nothing.
#include <fstream>

#include <gtest/gtest.h>

#include "mapnav/map/map_io.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;
using testing::runCli;

TEST(ImportOsmCli, TheRealCampusImportsWithItsRepairsListedAndValidates) {
  ASSERT_TRUE(testing::realDataPresent("osm/nu_campus_south.osm"));
  const fs::path dir = testing::freshTempDir();
  const fs::path out = dir / "campus.json";
  const auto r = runCli({"map", "import-osm", testing::realDataPath("osm/nu_campus_south.osm").string(), "-o",
                         out.string(), "--repair"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("8301 nodes, 1008 ways; kept 385 ways"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("repair: merged node 4774727997 with node 4773912810 (0.36 m apart)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("wrote " + out.string() + " (497 intersections, 660 roads; 2 repairs"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("nu_campus_south.osm:way/"), std::string::npos) << "data warnings name the OSM element";
  const Map map = loadMap(out);
  EXPECT_EQ(map.findRoad("w1088626459-1")->properties.at("osm_way"), "1088626459");
  const auto v = runCli({"map", "validate", "--quiet", out.string()});
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
}

TEST(ImportOsmCli, BadInputExitsNonZeroNamingTheProblemAndWritesNothing) {
  ASSERT_TRUE(testing::realDataPresent("osm/nu_campus_south.osm"));
  const fs::path dir = testing::freshTempDir();
  const fs::path broken = dir / "broken.osm", out = dir / "out.json";
  std::ofstream(broken) << "<?xml version='1.0'?>\n<osm version=\"0.6\">\n  <way id=\"1\">\n</osm>\n";
  auto r = runCli({"map", "import-osm", broken.string(), "-o", out.string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("broken.osm:4:"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  r = runCli({"map", "import-osm", testing::realDataPath("osm/nu_campus_south.osm").string(), "-o", out.string(),
              "--highways", "bridleway"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no way with highway=bridleway"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  r = runCli({"map", "import-osm", broken.string(), "-o", out.string(), "--bbox", "1,2,3"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--bbox"), std::string::npos) << r.err;
  r = runCli({"map", "import-osm", "--help"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("--repair"), std::string::npos);
}

}  // namespace
}  // namespace mapnav
