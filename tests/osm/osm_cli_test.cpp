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
  EXPECT_NE(r.out.find("wrote " + out.string() + " (497 intersections, 660 roads, 39 landmarks; 2 repairs"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("nu_campus_south.osm:way/"), std::string::npos) << "data warnings name the OSM element";
  const Map map = loadMap(out);
  EXPECT_EQ(map.findRoad("w1088626459-1")->properties.at("osm_way"), "1088626459");
  const auto v = runCli({"map", "validate", "--quiet", out.string()});
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
}

// The real campus imported, exported as GeoJSON and imported again keeps every OSM tag
// the import copied (osm_node, osm_way, highway, name, surface; a landmark's), element by element.
TEST(ImportOsmCli, TheCampusKeepsEveryCopiedOsmTagThroughGeoJson) {
  ASSERT_TRUE(testing::realDataPresent("osm/nu_campus_south.osm"));
  const fs::path dir = testing::freshTempDir();
  const fs::path json = dir / "campus.json", geo = dir / "campus.geojson", back = dir / "back.json";
  auto r = runCli({"map", "import-osm", testing::realDataPath("osm/nu_campus_south.osm").string(), "-o", json.string(),
                   "--repair"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = runCli({"map", "export-geojson", json.string(), "-o", geo.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = runCli({"map", "import-geojson", geo.string(), "-o", back.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Map a = loadMap(json), b = loadMap(back);
  std::size_t tags = 0, names = 0;
  ASSERT_EQ(a.roads().size(), b.roads().size());
  for (const Road& road : a.roads()) {
    const Road* again = b.findRoad(road.id);
    ASSERT_NE(again, nullptr) << road.id;
    EXPECT_EQ(again->properties, road.properties) << road.id;
    tags += road.properties.size();
    names += road.properties.contains("name");
  }
  ASSERT_EQ(a.intersections().size(), b.intersections().size());
  for (const Intersection& x : a.intersections()) {
    const Intersection* again = b.findIntersection(x.id);
    ASSERT_NE(again, nullptr) << x.id;
    EXPECT_EQ(again->properties, x.properties) << x.id;
    tags += x.properties.size();
  }
  // The 39 landmarks too (a tree's natural tag, a bench's amenity), in the same order.
  ASSERT_EQ(a.landmarks().size(), 39u);
  ASSERT_EQ(b.landmarks().size(), 39u);
  for (std::size_t i = 0; i < a.landmarks().size(); ++i) {
    EXPECT_EQ(b.landmarks()[i].id, a.landmarks()[i].id);
    EXPECT_EQ(b.landmarks()[i].properties, a.landmarks()[i].properties) << a.landmarks()[i].id;
  }
  // 660 roads with osm_way and highway each, some named; 495 of 497 intersections are OSM nodes
  // (2 were added by --repair).
  EXPECT_GT(names, 0u);
  EXPECT_GE(tags, 2 * 660u + 495u);
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
  EXPECT_EQ(r.exit_code, 1);  // a malformed value: wrong input
  EXPECT_NE(r.err.find("--bbox"), std::string::npos) << r.err;
  r = runCli({"map", "import-osm", "--help"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("--repair"), std::string::npos);
}

}  // namespace
}  // namespace mapnav
