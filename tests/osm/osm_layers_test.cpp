// Layers: tests/data/osm/layers.osm has a footway tunnel (way 202, layer -1) and a
// footbridge (way 203, layer 1) crossing the ground walk (way 200, y = 0) at x = 20 and x = 60 m
// without shared nodes. It imports with and without --repair; the same file with the tunnel's tags
// taken away has a same-layer crossing, which is still an error (and --repair joins it).
#include <fstream>
#include <set>

#include <gtest/gtest.h>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/map/geojson.h"
#include "mapnav/map/map_io.h"
#include "mapnav/map/predict.h"
#include "mapnav/map/validation.h"
#include "mapnav/osm/osm_import.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

namespace fs = std::filesystem;
using testing::runCli;

OsmImportOptions options(bool repair) {
  OsmImportOptions o;
  o.origin = GeoOrigin{42.05, -87.67, 0};
  o.repair = repair;
  return o;
}

fs::path fixture() { return testing::fixturePath("osm/layers.osm"); }

// The fixture with the tunnel's `tunnel` and `layer` tags taken away: way 202 on the ground.
fs::path withoutTunnelTags() {
  std::string text = readFile(fixture());
  for (const std::string tag : {"    <tag k=\"tunnel\" v=\"yes\"/>\n", "    <tag k=\"layer\" v=\"-1\"/>\n"}) {
    const auto at = text.find(tag);
    EXPECT_NE(at, std::string::npos) << tag;
    text.erase(at, tag.size());
  }
  const fs::path file = testing::freshTempDir() / "same_layer.osm";
  std::ofstream(file) << text;
  return file;
}

const Road& roadOf(const MapData& map, const std::string& id) {
  for (const Road& r : map.roads) {
    if (r.id == id) return r;
  }
  throw NotFound("no road " + id);
}

std::string formatIssues(const Issues& issues, const std::string& file) {
  std::string out;
  for (const Issue& i : issues) out += formatIssue(i, file) + "\n";
  return out;
}

std::multiset<std::string> errorChecks(const Issues& issues) {
  std::multiset<std::string> out;
  for (const Issue& i : issues) {
    if (i.severity == Severity::Error) out.insert(i.check);
  }
  return out;
}

TEST(OsmLayers, ATunnelAndABridgeCrossingOtherWaysImportWithAndWithoutRepair) {
  for (const bool repair : {false, true}) {
    const OsmImport imported = importOsm(fixture(), options(repair));
    const MapData& map = imported.map;
    EXPECT_TRUE(errorChecks(validateMap(map)).empty()) << "repair " << repair;
    EXPECT_TRUE(imported.report.repairs.empty()) << "nothing to repair: the crossings are on other layers";
    // The ground walk is cut only at node 2, where way 201 leaves it.
    EXPECT_EQ(roadOf(map, "w200-1").to, "n2");
    EXPECT_EQ(roadOf(map, "w200-2").from, "n2");
    const Road& tunnel = roadOf(map, "w202");
    EXPECT_EQ(tunnel.layer, -1);
    EXPECT_EQ(tunnel.structure, RoadStructure::Tunnel);
    const Road& bridge = roadOf(map, "w203");
    EXPECT_EQ(bridge.layer, 1);
    EXPECT_EQ(bridge.structure, RoadStructure::Bridge);
    EXPECT_EQ(roadOf(map, "w200-1").layer, 0);
    EXPECT_EQ(roadOf(map, "w200-1").structure, RoadStructure::None);
  }
}

// covered=yes (a roofed way) is a tunnel to the view: not seen from above or outside; its layer
// stays the tagged one.
TEST(OsmLayers, ACoveredWayIsATunnelOnItsTaggedLayer) {
  std::string text = readFile(fixture());
  const std::string bridge = "<tag k=\"bridge\" v=\"yes\"/>";
  text.replace(text.find(bridge), bridge.size(), "<tag k=\"covered\" v=\"yes\"/>");
  const fs::path file = testing::freshTempDir() / "covered.osm";
  std::ofstream(file) << text;
  const MapData map = importOsm(file, options(false)).map;
  EXPECT_EQ(roadOf(map, "w203").structure, RoadStructure::Tunnel);
  EXPECT_EQ(roadOf(map, "w203").layer, 1);
  EXPECT_TRUE(errorChecks(validateMap(map)).empty());
}

TEST(OsmLayers, LayerAndStructureSurviveTheJsonMapAndGeoJson) {
  const MapData map = importOsm(fixture(), options(false)).map;
  const std::string json = mapToJson(map);
  EXPECT_NE(json.find("\"layer\": -1"), std::string::npos);
  EXPECT_NE(json.find("\"structure\": \"tunnel\""), std::string::npos);
  Issues issues;
  const auto back = parseMap(json, issues);
  ASSERT_TRUE(back) << formatIssues(issues, "map");
  EXPECT_EQ(roadOf(*back, "w202").layer, -1);
  EXPECT_EQ(roadOf(*back, "w203").structure, RoadStructure::Bridge);
  const auto geo = importGeoJson(exportGeoJson(map), issues);
  ASSERT_TRUE(geo) << formatIssues(issues, "geojson");
  EXPECT_EQ(roadOf(geo->map, "w202").structure, RoadStructure::Tunnel);
  EXPECT_EQ(roadOf(geo->map, "w203").layer, 1);
  EXPECT_TRUE(errorChecks(validateMap(geo->map)).empty());
  // Bad values are named.
  std::string bad = json;
  bad.replace(bad.find("\"structure\": \"tunnel\""), 21, "\"structure\": \"ramp\"");
  EXPECT_FALSE(parseMap(bad, issues));
  EXPECT_NE(formatIssues(issues, "map").find("unknown road structure \"ramp\""), std::string::npos);
}

TEST(OsmLayers, ASameLayerCrossingIsStillAnErrorAndRepairJoinsIt) {
  const fs::path file = withoutTunnelTags();
  const OsmImport plain = importOsm(file, options(false));
  EXPECT_EQ(errorChecks(validateMap(plain.map)), std::multiset<std::string>{"roads.crossing_without_intersection"});
  EXPECT_EQ(roadOf(plain.map, "w202").layer, 0);
  EXPECT_TRUE(osmRepairCanFix("roads.crossing_without_intersection"));
  EXPECT_FALSE(osmRepairCanFix("roads.self_intersection"));
  const OsmImport repaired = importOsm(file, options(true));
  EXPECT_TRUE(errorChecks(validateMap(repaired.map)).empty());
  ASSERT_EQ(repaired.report.repairs.size(), 1u);
  EXPECT_EQ(repaired.report.repairs[0], "added intersection x1 where way 200 crosses way 202 at (20.0, 0.0) m");
}

TEST(OsmLayers, TheCliImportsTheFixtureAndHintsRepairOnlyForWhatItRepairs) {
  const fs::path dir = testing::freshTempDir();
  for (const char* repair : {"", "--repair"}) {
    std::vector<std::string> args{"map", "import-osm", fixture().string(), "-o", (dir / "layers.json").string()};
    if (*repair != '\0') args.emplace_back(repair);
    const auto r = runCli(args);
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  }
  const fs::path same = withoutTunnelTags();
  auto r = runCli({"map", "import-osm", same.string(), "-o", (dir / "same.json").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("(1 errors; --repair may fix the 1 roads.crossing_without_intersection); nothing written"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "same.json"));
  r = runCli({"map", "import-osm", same.string(), "-o", (dir / "same.json").string(), "--repair"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// The predicted view leaves the tunnel out when the vehicle is outside it (on the ground walk,
// looking east at the point where the tunnel passes under), and has it when the vehicle is in it.
TEST(OsmLayers, ATunnelIsInTheViewOnlyFromInsideIt) {
  const Map map(importOsm(fixture(), options(false)).map);
  CameraIntrinsics in;
  in.width = 640;
  in.height = 480;
  in.fx = in.fy = 500;
  in.cx = 319.5;
  in.cy = 239.5;
  CameraMount mount;
  mount.height_m = 1.5;
  mount.tilt_rad = 0.35;
  const auto camera = createCamera(LensModel::Pinhole, in, mount);
  auto regions = [&](const Pose2& pose) {
    std::set<std::string> ids;
    for (const PredictedRegion& r : predictView(map, pose, *camera).view.regions) ids.insert(r.id);
    return ids;
  };
  const std::set<std::string> outside = regions(Pose2(14, 0, 0));  // 6 m before the crossing, facing it
  EXPECT_TRUE(outside.contains("w200-1"));
  EXPECT_FALSE(outside.contains("w202"));
  const std::set<std::string> inside = regions(Pose2(20, -8, kPi / 2));  // in the tunnel, facing north
  EXPECT_TRUE(inside.contains("w202"));
}

}  // namespace
}  // namespace mapnav
