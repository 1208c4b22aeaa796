// OpenStreetMap import: a hand-made OSM file whose expected map is worked out by hand,
// malformed files, and the real campus export in ../shared/data/real/osm.
#include <cmath>
#include <fstream>
#include <iostream>
#include <numbers>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "mapnav/core/error.h"
#include "mapnav/map/map.h"
#include "mapnav/map/validation.h"
#include "mapnav/navigator/route.h"
#include "mapnav/osm/osm_import.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

using testing::freshTempDir;
using testing::realDataPath;

constexpr double kLat0 = 42.05, kLon0 = -87.67;
// Metres per degree on the WGS84 ellipsoid at kLat0, from the series expansion of the meridian and
// parallel arcs (independent of GeographicLib; good to millimetres over tens of metres).
const double kPhi = kLat0 * std::numbers::pi / 180.0;
const double kMetresPerDegLat = 111132.92 - 559.82 * std::cos(2 * kPhi) + 1.175 * std::cos(4 * kPhi) - 0.0023 * std::cos(6 * kPhi);
const double kMetresPerDegLon = 111412.84 * std::cos(kPhi) - 93.5 * std::cos(3 * kPhi) + 0.118 * std::cos(5 * kPhi);

std::string node(long id, double east, double north) {
  char text[200];
  std::snprintf(text, sizeof text, "  <node id=\"%ld\" version=\"1\" lat=\"%.9f\" lon=\"%.9f\"/>\n", id,
                kLat0 + north / kMetresPerDegLat, kLon0 + east / kMetresPerDegLon);
  return text;
}

std::string way(long id, std::initializer_list<long> refs, std::initializer_list<std::pair<const char*, const char*>> tags) {
  std::string out = "  <way id=\"" + std::to_string(id) + "\" version=\"1\">\n";
  for (long r : refs) out += "    <nd ref=\"" + std::to_string(r) + "\"/>\n";
  for (const auto& [k, v] : tags) out += "    <tag k=\"" + std::string(k) + "\" v=\"" + v + "\"/>\n";
  return out + "  </way>\n";
}

// A footway east along y = 0 (nodes 1, 2, 3 at x = 0, 10, 30), a footway north from node 2 to
// node 4 (10, 20); a footway 5 → 6 crossing the first at x = 20 without a shared node; a footway
// 7 → 8 east, starting 0.2 m from node 4 (a duplicate node); steps 3 → 9; a street (not walkable).
std::filesystem::path writeSmallOsm(const std::filesystem::path& dir) {
  std::string xml = "<?xml version='1.0' encoding='UTF-8'?>\n<osm version=\"0.6\" generator=\"test\">\n";
  xml += node(1, 0, 0) + node(2, 10, 0) + node(3, 30, 0) + node(4, 10, 20) + node(5, 20, -10) + node(6, 20, 10) +
         node(7, 10.2, 20) + node(8, 24, 20) + node(9, 40, 0) + node(10, 0, 50) + node(11, 30, 50);
  xml += way(100, {1, 2, 3}, {{"highway", "footway"}, {"surface", "asphalt"}, {"width", "3 m"}, {"name", "Main walk"}});
  xml += way(101, {2, 4}, {{"highway", "footway"}, {"width", "wide"}});
  xml += way(102, {5, 6}, {{"highway", "footway"}});
  xml += way(103, {7, 8}, {{"highway", "path"}});
  xml += way(104, {3, 9}, {{"highway", "steps"}});
  xml += way(105, {10, 11}, {{"highway", "residential"}});
  xml += "</osm>\n";
  const auto file = dir / "small.osm";
  std::ofstream(file) << xml;
  return file;
}

OsmImportOptions atOrigin() {
  OsmImportOptions o;
  o.origin = GeoOrigin{kLat0, kLon0, 0};
  return o;
}

const Road& roadById(const MapData& map, const std::string& id) {
  for (const Road& r : map.roads) {
    if (r.id == id) return r;
  }
  throw NotFound("no road " + id);
}
const Intersection& intersectionById(const MapData& map, const std::string& id) {
  for (const Intersection& x : map.intersections) {
    if (x.id == id) return x;
  }
  throw NotFound("no intersection " + id);
}

std::multiset<std::string> checks(const Issues& issues) {
  std::multiset<std::string> out;
  for (const Issue& i : issues) out.insert(i.check);
  return out;
}

TEST(OsmImport, SplitsWaysAtSharedNodesAndInfersKinds) {
  const OsmImport imported = importOsm(writeSmallOsm(freshTempDir()), atOrigin());
  const MapData& map = imported.map;
  EXPECT_EQ(imported.report.nodes_read, 11u);
  EXPECT_EQ(imported.report.ways_read, 6u);
  EXPECT_EQ(imported.report.ways_kept, 5u);  // the residential street is not walkable
  // Way 100 is cut at node 2 (shared with 101): w100-1, w100-2; the others are one piece each.
  std::set<std::string> ids;
  for (const Road& r : map.roads) ids.insert(r.id);
  EXPECT_EQ(ids, (std::set<std::string>{"w100-1", "w100-2", "w101", "w102", "w103", "w104"}));
  EXPECT_EQ(roadById(map, "w100-1").from, "n1");
  EXPECT_EQ(roadById(map, "w100-1").to, "n2");
  EXPECT_EQ(roadById(map, "w100-2").to, "n3");
  EXPECT_NEAR(roadById(map, "w100-2").centerline.length(), 20.0, 0.02);
  EXPECT_NEAR(intersectionById(map, "n4").position.x(), 10.0, 0.02);
  EXPECT_NEAR(intersectionById(map, "n4").position.y(), 20.0, 0.02);
  // Node 2: 100 runs straight through, 101 leaves at 90 degrees: a T. Node 3: w100-2 and the
  // steps run on straight: not an L. Node 1: an end.
  EXPECT_EQ(intersectionById(map, "n2").kind, IntersectionKind::T);
  EXPECT_EQ(intersectionById(map, "n3").kind, IntersectionKind::Other);
  EXPECT_EQ(intersectionById(map, "n1").kind, IntersectionKind::End);
  // Tags: width "3 m", asphalt, the name and the OSM ids kept; a bad width falls back to 2 m.
  const Road& main = roadById(map, "w100-1");
  EXPECT_DOUBLE_EQ(main.width, 3.0);
  EXPECT_EQ(main.surface, "asphalt");
  EXPECT_EQ(main.left, "grass");
  EXPECT_EQ(main.properties.at("osm_way"), "100");
  EXPECT_EQ(main.properties.at("name"), "Main walk");
  EXPECT_EQ(intersectionById(map, "n2").properties.at("osm_node"), "2");
  EXPECT_DOUBLE_EQ(roadById(map, "w101").width, 2.0);
  EXPECT_DOUBLE_EQ(roadById(map, "w103").width, 1.5);  // path
  EXPECT_EQ(roadById(map, "w103").surface, "gravel");
  EXPECT_DOUBLE_EQ(roadById(map, "w104").cost_factor, 20.0);  // steps
  // Reported, not repaired: the duplicate node, the crossing, the bad width, the steps.
  const auto found = checks(imported.report.issues);
  EXPECT_EQ(found.count("osm.duplicate_node"), 1u);
  EXPECT_EQ(found.count("osm.crossing_without_node"), 1u);
  EXPECT_EQ(found.count("osm.bad_width"), 1u);
  EXPECT_EQ(found.count("osm.steps"), 1u);
  EXPECT_TRUE(imported.report.repairs.empty());
  // ... and the map's validation sees the crossing as an error.
  EXPECT_EQ(checks(validateMap(map)).count("roads.crossing_without_intersection"), 1u);
}

TEST(OsmImport, RepairMergesCloseNodesAndJoinsCrossings) {
  OsmImportOptions options = atOrigin();
  options.repair = true;
  const OsmImport imported = importOsm(writeSmallOsm(freshTempDir()), options);
  const MapData& map = imported.map;
  ASSERT_EQ(imported.report.repairs.size(), 2u);
  EXPECT_EQ(imported.report.repairs[0], "merged node 7 with node 4 (0.20 m apart)");
  EXPECT_EQ(imported.report.repairs[1], "added intersection x1 where way 100 crosses way 102 at (20.0, 0.0) m");
  // The crossing cuts both ways there: a cross of four roads.
  const Intersection& x1 = intersectionById(map, "x1");
  EXPECT_EQ(x1.kind, IntersectionKind::Cross);
  EXPECT_NEAR(x1.position.x(), 20.0, 0.02);
  EXPECT_NEAR(x1.position.y(), 0.0, 0.02);
  EXPECT_EQ(roadById(map, "w100-2").to, "x1");
  EXPECT_EQ(roadById(map, "w100-3").from, "x1");
  EXPECT_EQ(roadById(map, "w102-1").to, "x1");
  // The path now starts at node 4, which joins two roads at a right angle: an L.
  EXPECT_EQ(roadById(map, "w103").from, "n4");
  EXPECT_EQ(intersectionById(map, "n4").kind, IntersectionKind::L);
  EXPECT_EQ(checks(imported.report.issues).count("osm.duplicate_node"), 0u);
  // The repaired map is valid and all one network.
  const Issues issues = validateMap(map);
  EXPECT_FALSE(hasErrors(issues));
  EXPECT_EQ(checks(issues).count("topology.disconnected"), 0u);
}

TEST(OsmImport, BboxCutsWaysAtItsBorder) {
  OsmImportOptions options = atOrigin();
  // West of x = 25 m: node 3 (x = 30) and node 9 are outside, so way 100 ends at node 2 and the
  // steps are gone.
  options.bbox = std::array<double, 4>{kLon0 - 0.001, kLat0 - 0.001, kLon0 + 25.0 / kMetresPerDegLon, kLat0 + 0.001};
  const OsmImport imported = importOsm(writeSmallOsm(freshTempDir()), options);
  std::set<std::string> ids;
  for (const Road& r : imported.map.roads) ids.insert(r.id);
  EXPECT_EQ(ids, (std::set<std::string>{"w100", "w101", "w102", "w103"}));
  EXPECT_EQ(imported.report.ways_kept, 4u);
}

TEST(OsmImport, InferredKinds) {
  const double pi = std::numbers::pi;
  EXPECT_EQ(inferIntersectionKind({0.3}), IntersectionKind::End);
  EXPECT_EQ(inferIntersectionKind({0, pi / 2}), IntersectionKind::L);
  EXPECT_EQ(inferIntersectionKind({0, pi - 0.2}), IntersectionKind::Other);  // 11 degrees off straight
  EXPECT_EQ(inferIntersectionKind({0, pi, pi / 2}), IntersectionKind::T);
  EXPECT_EQ(inferIntersectionKind({0, 2 * pi / 3, -2 * pi / 3}), IntersectionKind::Y);
  EXPECT_EQ(inferIntersectionKind({0, pi / 2, pi, -pi / 2}), IntersectionKind::Cross);
  EXPECT_EQ(inferIntersectionKind({0, 0.5, pi, -pi / 2}), IntersectionKind::Plaza);
  EXPECT_EQ(inferIntersectionKind({0, 1, 2, 3, 4}), IntersectionKind::Plaza);
}

TEST(OsmImport, BadFilesAndOptionsSayWhatIsWrong) {
  const auto dir = freshTempDir();
  const auto broken = dir / "broken.osm";
  std::ofstream(broken) << "<?xml version='1.0'?>\n<osm version=\"0.6\">\n  <node id=\"1\" lat=\"1\" lon=\"2\">\n</osm>\n";
  try {
    importOsm(broken);
    FAIL() << "malformed XML was accepted";
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("broken.osm:4:"), std::string::npos) << what;
    EXPECT_NE(what.find("malformed OSM XML"), std::string::npos) << what;
  }
  EXPECT_THROW(importOsm(dir / "absent.osm"), IoError);
  const auto empty = dir / "streets.osm";
  std::ofstream(empty) << "<?xml version='1.0'?>\n<osm version=\"0.6\">\n" << node(1, 0, 0) << node(2, 5, 0)
                       << way(1, {1, 2}, {{"highway", "primary"}}) << "</osm>\n";
  try {
    importOsm(empty);
    FAIL() << "a file with nothing walkable was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("nothing to import"), std::string::npos) << e.what();
  }
  OsmImportOptions bad;
  bad.merge_distance_m = -1;
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { bad.validate(); },
                                                "OsmImportOptions::merge_distance_m = -1: must be finite and >= 0"));
  bad = {};
  bad.widths["steps"] = 0;  // a width by highway has default_width_m's rule
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { bad.validate(); },
                                                "OsmImportOptions::widths[steps] = 0: must be finite and > 0"));
  bad = {};
  bad.shoulder = "lava";
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { bad.validate(); },
                                                "OsmImportOptions::shoulder = \"lava\": must be a standard surface"));
  OsmImportOptions box;
  box.bbox = std::array<double, 4>{10, 5, 9, 6};  // west > east
  EXPECT_THROW(box.validate(), InvalidInput);
  EXPECT_NO_THROW(OsmImportOptions().validate());
}

// The real campus: every pair of its intersections is routed or lies in different pieces of the
// network (the data does not connect them). The pieces come from the Map (a union-find over roads),
// the routes from Boost.Graph: two independent answers that must agree.
TEST(OsmImportReal, CampusImportsValidAndRoutesOrExplains100RandomPairs) {
  ASSERT_TRUE(testing::realDataPresent("osm/nu_campus_south.osm"));
  const auto file = realDataPath("osm/nu_campus_south.osm");
  OsmImportOptions options;
  options.repair = true;
  const OsmImport imported = importOsm(file, options);
  EXPECT_GT(imported.map.roads.size(), 200u);
  EXPECT_FALSE(imported.report.repairs.empty());
  const Map map(imported.map, file.string());  // throws when invalid
  std::vector<std::size_t> piece(map.intersections().size());
  for (std::size_t c = 0; c < map.components().size(); ++c) {
    for (std::size_t i : map.components()[c]) piece[i] = c;
  }
  RoadGraph graph(map);
  MapData two_way_data = imported.map;
  for (Road& r : two_way_data.roads) r.oneway = false;
  const Map two_way(two_way_data, file.string());
  RoadGraph two_way_graph(two_way);
  std::size_t one_way = 0, disconnected = 0;
  std::mt19937 rng(10);
  std::uniform_int_distribution<std::size_t> pick(0, map.intersections().size() - 1);
  std::size_t routed = 0;
  for (int k = 0; k < 100; ++k) {
    const std::size_t a = pick(rng), b = pick(rng);
    const auto from = map.roadsAt(map.intersections()[a].id).front();
    const auto to = map.roadsAt(map.intersections()[b].id).front();
    const RouteResult r = graph.route({from.road->id, map.intersections()[a].id, 0, 0},
                                      {to.road->id, map.intersections()[b].id, 0, 0});
    const std::string pair = map.intersections()[a].id + " → " + map.intersections()[b].id + ": " + r.reason;
    if (r.route) {
      ++routed;
      EXPECT_EQ(piece[a], piece[b]) << pair;
    } else if (piece[a] == piece[b]) {
      // Connected, so only the data's one-way cycleways can stand in the way: without them the
      // route must be found.
      EXPECT_NE(r.reason.find("one-way"), std::string::npos) << pair;
      EXPECT_TRUE(two_way_graph.route({from.road->id, map.intersections()[a].id, 0, 0},
                                      {to.road->id, map.intersections()[b].id, 0, 0}).route.has_value()) << pair;
      ++one_way;
    } else {
      ++disconnected;
    }
  }
  EXPECT_GT(routed, 50u);  // most of the campus is one network
  std::cout << "campus: " << map.roads().size() << " roads, " << map.intersections().size() << " intersections, "
            << map.components().size() << " pieces; 100 random pairs: " << routed << " routed, " << one_way
            << " blocked by one-way ways, " << disconnected << " not connected in the data\n";
}

}  // namespace
}  // namespace mapnav
