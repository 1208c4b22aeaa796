// Landmarks from OpenStreetMap nodes: tests/data/osm/landmarks.osm has a footway along
// y = 0 from x = 0 to 60 m and a node of each landmark tag beside it, one tree 24 m from it, one
// with a circumference in centimetres, and a node of another kind; each node's comment gives its
// metres east and north. And the real campus export's trees.
#include <algorithm>
#include <fstream>
#include <numbers>
#include <set>

#include <gtest/gtest.h>

#include "mapnav/core/error.h"
#include "mapnav/map/validation.h"
#include "mapnav/osm/osm_import.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

OsmImportOptions landmarksAtOrigin() {
  OsmImportOptions o;
  o.origin = GeoOrigin{42.05, -87.67, 0};
  return o;
}

std::filesystem::path landmarksOsm() { return testing::fixturePath("osm/landmarks.osm"); }

TEST(OsmLandmarks, EachTagGivesItsKindBesideTheRoadsAndTheFarTreeIsDropped) {
  const OsmImport imported = importOsm(landmarksOsm(), landmarksAtOrigin());
  const MapData& map = imported.map;
  const std::vector<Landmark> expected{
      // circumference 1.57 m: radius 1.57 / 2π = 0.24987 m; height 12 m.
      {"tree11", LandmarkKind::Tree, Vec2(10, 3), 1.57 / (2 * std::numbers::pi), 12.0, "",
       {{"osm_node", "11"}, {"natural", "tree"}, {"circumference", "1.57"}, {"height", "12"}}},
      {"pole12", LandmarkKind::Pole, Vec2(20, -2), 0.10, 6.0, "", {{"osm_node", "12"}, {"highway", "street_lamp"}, {"height", "6 m"}}},
      {"bench13", LandmarkKind::Bench, Vec2(30, 2.5), 0.80, 0.8, "", {{"osm_node", "13"}, {"amenity", "bench"}}},
      {"bollard14", LandmarkKind::Bollard, Vec2(40, 1.5), 0.08, 0.9, "", {{"osm_node", "14"}, {"barrier", "bollard"}}},
      {"manhole15", LandmarkKind::Manhole, Vec2(50, 0), 0.30, 0.0, "",
       {{"osm_node", "15"}, {"man_made", "manhole"}, {"manhole", "drain"}}},
      {"manhole16", LandmarkKind::Manhole, Vec2(55, 0.5), 0.30, 0.0, "", {{"osm_node", "16"}, {"manhole", "sewer"}}},
      // Node 17 at (30, 25) is 25 − 1 = 24 m from the 2 m footway's paving: dropped.
      // circumference=250 (centimetres?) is refused: a tree's default radius.
      {"tree18", LandmarkKind::Tree, Vec2(5, -4), 0.15, 6.0, "", {{"osm_node", "18"}, {"natural", "tree"}, {"circumference", "250"}}},
      // (69, 6): √(9² + 6²) − 1 = 9.82 m from the paving past the way's end at (60, 0): kept.
      {"tree19", LandmarkKind::Tree, Vec2(69, 6), 0.15, 6.0, "", {{"osm_node", "19"}, {"natural", "tree"}}}};
  ASSERT_EQ(map.landmarks.size(), expected.size());
  // Positions within 5 mm: the series for the metres per degree against GeographicLib.
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_TRUE(testing::landmarkNear(map.landmarks[i], expected[i], 0.005));
  EXPECT_EQ(imported.report.landmarks_found, 9u);
  EXPECT_EQ(imported.report.landmarks_far, 1u);
  ASSERT_EQ(imported.report.issues.size(), 1u);
  EXPECT_EQ(imported.report.issues[0].check, "osm.bad_size");
  EXPECT_EQ(imported.report.issues[0].where, "node/18");
  EXPECT_TRUE(validateMap(map).empty());  // nothing far, nothing standing on the paving
}

// With keep_far_landmarks the far tree stays, and the map's validation warns of it.
TEST(OsmLandmarks, KeepFarLandmarksKeepsTheFarTreeWhichValidationWarnsOf) {
  OsmImportOptions options = landmarksAtOrigin();
  options.keep_far_landmarks = true;
  const OsmImport imported = importOsm(landmarksOsm(), options);
  ASSERT_EQ(imported.map.landmarks.size(), 9u);
  EXPECT_EQ(imported.map.landmarks[6].id, "tree17");
  EXPECT_VEC2_NEAR(imported.map.landmarks[6].position, Vec2(30, 25), 0.005);
  EXPECT_EQ(imported.report.landmarks_far, 1u);
  const Issues issues = validateMap(imported.map);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].check, "landmarks.far_from_road");
  EXPECT_EQ(issues[0].where, "/landmarks/6/position");
  // A larger reach keeps it without the option.
  options.keep_far_landmarks = false;
  options.max_landmark_distance_m = 25;
  EXPECT_EQ(importOsm(landmarksOsm(), options).map.landmarks.size(), 9u);
}

TEST(OsmLandmarks, TheDefaultReachIsValidationsAndABadOneIsRefused) {
  EXPECT_EQ(OsmImportOptions{}.max_landmark_distance_m, ValidationOptions{}.max_landmark_distance_m);
  OsmImportOptions options;
  options.max_landmark_distance_m = -1;
  EXPECT_THROW(options.validate(), InvalidInput);
}

TEST(ImportOsmCli, CountsTheLandmarksFoundKeptAndDropped) {
  const auto dir = testing::freshTempDir();
  const auto out = dir / "landmarks.json";
  const auto r = testing::runCli({"map", "import-osm", landmarksOsm().string(), "-o", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("landmarks: 9 found, 8 kept (1 farther than 10 m from every road dropped; "
                       "--keep-far-landmarks keeps them)\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("(2 intersections, 1 roads, 8 landmarks; "), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("landmarks.osm:node/18: warning: osm.bad_size: circumference=250"), std::string::npos) << r.err;
  const auto kept = testing::runCli({"map", "import-osm", landmarksOsm().string(), "-o", out.string(), "--keep-far-landmarks"});
  ASSERT_EQ(kept.exit_code, 0) << kept.err;
  EXPECT_NE(kept.out.find("landmarks: 9 found, 9 kept (1 farther than 10 m from every road kept too)\n"), std::string::npos)
      << kept.out;
}

// The ids of the nodes of an OSM XML file tagged natural=tree, read from its text (not libosmium):
// the tags between a <node ...> and its </node>.
std::set<std::string> treeNodesInXml(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::set<std::string> trees;
  std::string line, node;
  while (std::getline(in, line)) {
    if (const auto at = line.find("<node id=\""); at != std::string::npos) {
      node = line.substr(at + 10, line.find('"', at + 10) - (at + 10));
    } else if (line.find("</node>") != std::string::npos || line.find("<way ") != std::string::npos) {
      node.clear();
    } else if (!node.empty() && line.find("<tag k=\"natural\" v=\"tree\"/>") != std::string::npos) {
      trees.insert(node);
    }
  }
  return trees;
}

// The real campus export (../shared/data/real/osm): its 38 tree nodes (counted from the XML here)
// are all found; 29 stand within 10 m of an imported walkway's paving and are kept, 9 (11.9 to
// 16.5 m off) are dropped, as an independent computation gave (python over the XML: distances from
// each tree to every walkable segment less half its width, none between 9 and 11 m).
TEST(OsmLandmarksReal, TheCampusImportsItsTreesBesideTheWalkways) {
  ASSERT_TRUE(testing::realDataPresent("osm/nu_campus_south.osm"));
  const auto file = testing::realDataPath("osm/nu_campus_south.osm");
  const std::set<std::string> in_xml = treeNodesInXml(file);
  ASSERT_EQ(in_xml.size(), 38u);
  OsmImportOptions options;
  options.repair = true;
  options.keep_far_landmarks = true;
  const OsmImport all = importOsm(file, options);
  std::set<std::string> imported;
  for (const Landmark& l : all.map.landmarks) {
    if (l.kind == LandmarkKind::Tree) imported.insert(l.properties.at("osm_node").text);
  }
  EXPECT_EQ(imported, in_xml);
  options.keep_far_landmarks = false;
  const OsmImport near = importOsm(file, options);
  const auto trees = std::count_if(near.map.landmarks.begin(), near.map.landmarks.end(),
                                   [](const Landmark& l) { return l.kind == LandmarkKind::Tree; });
  EXPECT_EQ(trees, 29);
  EXPECT_EQ(near.report.landmarks_found, 48u);  // and 10 benches, all beside a walkway
  EXPECT_EQ(near.report.landmarks_far, 9u);
  EXPECT_EQ(near.map.landmarks.size(), 39u);
  const Map map(near.map, file.string());  // valid
  EXPECT_EQ(map.landmarks().size(), 39u);
}

}  // namespace
}  // namespace mapnav
