#include "mapnav/map/geojson.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include <nlohmann/json.hpp>

#include "map_fixtures.h"
#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/map/geodesy.h"
#include "mapnav/map/map_io.h"
#include "mapnav/map/validation.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

// Same network: ids, kinds, topology, widths and surfaces equal; every coordinate within `tol`.
void expectSameNetwork(const MapData& a, const MapData& b, double tol) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.surfaces, b.surfaces);
  ASSERT_EQ(a.intersections.size(), b.intersections.size());
  for (std::size_t i = 0; i < a.intersections.size(); ++i) {
    const Intersection &x = a.intersections[i], &y = b.intersections[i];
    SCOPED_TRACE(x.id);
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.kind, y.kind);
    EXPECT_VEC2_NEAR(x.position, y.position, tol);
    EXPECT_EQ(x.properties, y.properties);
    ASSERT_EQ(x.shape.has_value(), y.shape.has_value());
    if (x.shape) {
      ASSERT_EQ(x.shape->size(), y.shape->size());
      for (std::size_t k = 0; k < x.shape->size(); ++k) EXPECT_VEC2_NEAR((*x.shape)[k], (*y.shape)[k], tol);
    }
  }
  ASSERT_EQ(a.roads.size(), b.roads.size());
  for (std::size_t i = 0; i < a.roads.size(); ++i) {
    const Road &r = a.roads[i], &s = b.roads[i];
    SCOPED_TRACE(r.id);
    EXPECT_EQ(r.id, s.id);
    EXPECT_EQ(r.from, s.from);
    EXPECT_EQ(r.to, s.to);
    EXPECT_EQ(r.width, s.width);
    EXPECT_EQ(std::tie(r.surface, r.left, r.right, r.oneway, r.cost_factor),
              std::tie(s.surface, s.left, s.right, s.oneway, s.cost_factor));
    EXPECT_EQ(std::tie(r.layer, r.structure, r.properties), std::tie(s.layer, s.structure, s.properties));
    ASSERT_EQ(r.centerline.size(), s.centerline.size());
    for (std::size_t k = 0; k < r.centerline.size(); ++k) {
      EXPECT_VEC2_NEAR(r.centerline.points()[k], s.centerline.points()[k], tol);
    }
  }
}

TEST(GeoJsonImport, CampusGeoJsonMatchesTheCampusMapWithinOneCentimetre) {
  const MapData native = testing::campusMap().data();
  Issues issues;
  const auto imported = importGeoJson(readFile(testing::mapPath("cmu_campus.geojson")), issues);
  ASSERT_TRUE(imported);
  EXPECT_TRUE(issues.empty());
  EXPECT_TRUE(validateMap(imported->map).empty());
  expectSameNetwork(imported->map, native, 0.01);
}

TEST(GeoJsonExport, ExportThenImportGivesTheSameMapWithinAMillimetre) {
  const MapData park = loadMap(testing::mapPath("park_path.json")).data();
  Issues issues;
  const auto back = importGeoJson(exportGeoJson(park), issues);
  ASSERT_TRUE(back);
  expectSameNetwork(back->map, park, 0.001);
  ASSERT_TRUE(back->map.origin);
  EXPECT_EQ(*back->map.origin, *park.origin);
}

// Properties mapnav does not interpret, of every JSON type and nested, on a road and on a point
// intersection: GeoJSON -> map -> GeoJSON gives each feature's properties equal as JSON values to
// the input's, through the JSON map file too, and a second round trip gives the same text.
TEST(GeoJsonExport, ARoundTripKeepsArbitraryNestedPropertiesLossless) {
  const std::string nested = R"({"osm_way": 12, "tags": {"a": [1, 2.5, null, true, {"b": "c", "d": []}]}, "name": "Main walk",
    "note": null, "kind": "footbridge", "ratio": -1e-7, "flag": false, "unicode": "Straße \u00e9"})";
  const std::string text = R"({"type": "FeatureCollection", "mapnav": {"format": "mapnav-map/1", "name": "kept",
    "origin": {"lat": 42.05, "lon": -87.67, "alt": 0}, "surfaces": {"concrete": {"rgb": [178, 176, 168], "spread": [10, 10, 10]},
    "grass": {"rgb": [72, 122, 52], "spread": [16, 16, 16]}}}, "features": [
    {"type": "Feature", "properties": {"id": "A", "kind": "end", "osm_node": "5", "levels": [0, {"x": 1}]},
     "geometry": {"type": "Point", "coordinates": [-87.67, 42.05]}},
    {"type": "Feature", "properties": {"id": "B", "kind": "end"}, "geometry": {"type": "Point", "coordinates": [-87.6698, 42.05]}},
    {"type": "Feature", "properties": )" + nested.substr(0, nested.size() - 1) + R"(, "id": "R", "from": "A", "to": "B"},
     "geometry": {"type": "LineString", "coordinates": [[-87.67, 42.05], [-87.6698, 42.05]]}}]})";
  Issues issues;
  const auto first = importGeoJson(text, issues);
  ASSERT_TRUE(first) << (issues.empty() ? "" : issues[0].message);
  const Road& road = first->map.roads.at(0);
  EXPECT_EQ(road.properties.at("name"), PropertyValue("Main walk"));
  EXPECT_EQ(road.properties.at("osm_way"), PropertyValue::json("12"));
  EXPECT_EQ(road.properties.at("kind"), PropertyValue("footbridge"));  // a road's kind is not interpreted
  EXPECT_EQ(road.properties.at("tags"), PropertyValue::json(R"({"a":[1,2.5,null,true,{"b":"c","d":[]}]})"));
  EXPECT_EQ(road.properties.size(), 8u);
  EXPECT_EQ(first->map.intersections.at(0).properties.at("levels"), PropertyValue::json(R"([0,{"x":1}])"));
  // Each feature's properties as exported equal the input's as JSON values (member order aside).
  const std::string exported = exportGeoJson(first->map);
  const auto in = nlohmann::json::parse(text), out = nlohmann::json::parse(exported);
  ASSERT_EQ(out["features"].size(), 3u);
  EXPECT_EQ(out["features"][0]["properties"], in["features"][0]["properties"]);
  auto road_in = in["features"][2]["properties"], road_out = out["features"][2]["properties"];
  for (const char* added : {"width", "surface", "left", "right"}) road_out.erase(added);  // the defaults, written out
  EXPECT_EQ(road_out, road_in);
  // Through the JSON map file, and a second round trip: the same map, the same GeoJSON text.
  const auto reread = parseMap(mapToJson(first->map), issues);
  ASSERT_TRUE(reread);
  EXPECT_EQ(*reread, first->map);
  const auto second = importGeoJson(exported, issues);
  ASSERT_TRUE(second);
  expectSameNetwork(first->map, second->map, 1e-3);
  EXPECT_EQ(exportGeoJson(second->map), exported);
  // A kept property named like a member mapnav writes (an OSM way's surface tag) goes inside
  // mapnav_kept and comes back out of it.
  MapData shadowing = first->map;
  shadowing.roads[0].properties["surface"] = "paving_stones";
  shadowing.roads[0].properties["id"] = PropertyValue::json("7");
  const std::string with_kept = exportGeoJson(shadowing);
  EXPECT_EQ(nlohmann::json::parse(with_kept)["features"][2]["properties"]["mapnav_kept"],
            nlohmann::json::parse(R"({"id": 7, "surface": "paving_stones"})"));
  const auto third = importGeoJson(with_kept, issues);
  ASSERT_TRUE(third);
  EXPECT_EQ(third->map.roads[0].properties, shadowing.roads[0].properties);
  EXPECT_EQ(third->map.roads[0].surface, "concrete");
}

TEST(GeoJsonExport, AMapWithoutOriginNeedsOne) {
  MapData data = testing::campusMap().data();
  data.origin.reset();
  EXPECT_THROW(exportGeoJson(data), InvalidInput);
  EXPECT_NO_THROW(exportGeoJson(data, GeoOrigin{40.0, -80.0, 0.0}));
}

// Three lines drawn in geojson.io meeting at one point, one ending at a named Point: no ids, no
// from/to. The junction becomes a T, the free ends dead ends, the named point is used.
// How well the roads are placed: the file's mapnav.position_sigma_m, else the import's default
// (kGeoJsonPositionSigmaM, said among the assumptions); a feature's own is its road's; export writes
// the map's so that export -> import keeps it.
TEST(GeoJsonImport, PositionSigmaIsTheFilesElseTheImportsDefaultAndAFeaturesIsItsRoads) {
  const std::string line = R"({"type": "Feature", "properties": {"id": "R", "position_sigma_m": 2}, "geometry": {"type": "LineString", "coordinates": [[-80.0, 40.0], [-80.0, 40.001]]}})";
  auto doc = [&](const std::string& meta) {
    return R"({"type": "FeatureCollection", )" + meta + R"("features": [)" + line + "]}";
  };
  Issues issues;
  const auto plain = importGeoJson(doc(""), issues);
  ASSERT_TRUE(plain) << (issues.empty() ? "" : formatIssue(issues[0], "inline"));
  EXPECT_EQ(plain->map.position_sigma_m, kGeoJsonPositionSigmaM);
  EXPECT_EQ(plain->map.roads[0].position_sigma_m, 2.0);
  EXPECT_EQ(plain->assumptions.front(), "the roads placed to 0.5 m (1 sigma; the file's mapnav member does not say)");
  const auto stated = importGeoJson(doc(R"("mapnav": {"position_sigma_m": 0.2}, )"), issues);
  ASSERT_TRUE(stated);
  EXPECT_EQ(stated->map.position_sigma_m, 0.2);
  EXPECT_TRUE(stated->assumptions.empty() || stated->assumptions.front().find("placed") == std::string::npos);
  MapData exact = stated->map;
  exact.position_sigma_m = 0;
  const auto back = importGeoJson(exportGeoJson(exact), issues);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->map.position_sigma_m, 0.0);
  EXPECT_EQ(back->map.roads[0].position_sigma_m, 2.0);
}

TEST(GeoJsonImport, InfersNodesKindsAndIdsFromSharedEndPoints) {
  const LocalFrame frame(GeoOrigin{40.0, -80.0, 0.0});
  auto pos = [&](double x, double y) {
    const LatLon g = frame.toGeodetic(Vec2(x, y));
    char text[64];
    std::snprintf(text, sizeof text, "[%.9f, %.9f]", g.lon, g.lat);
    return std::string(text);
  };
  auto line = [&](const std::string& p, const std::string& q) {
    return R"({"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": [)" + p + ", " + q + "]}}";
  };
  const std::string text = R"({"type": "FeatureCollection", "mapnav": {"origin": {"lat": 40.0, "lon": -80.0}}, "features": [
    {"type": "Feature", "properties": {"id": "A", "kind": "end"}, "geometry": {"type": "Point", "coordinates": )" +
                           pos(30, 0.4) + "}}, " + line(pos(0, 0), pos(30, 0)) + ", " + line(pos(0, 0), pos(-30, 0)) +
                           ", " + line(pos(0, 0), pos(0, -25)) + "]}";
  Issues issues;
  const auto imported = importGeoJson(text, issues);
  ASSERT_TRUE(imported) << (issues.empty() ? "" : formatIssue(issues[0], "inline"));
  const MapData& m = imported->map;
  ASSERT_EQ(m.intersections.size(), 4u);
  ASSERT_EQ(m.roads.size(), 3u);
  EXPECT_EQ(m.roads[0].id, "R1");
  EXPECT_EQ(m.roads[0].from, "J1");
  EXPECT_EQ(m.roads[0].to, "A");
  EXPECT_EQ(m.roads[1].from, "J1");
  EXPECT_EQ(m.roads[2].from, "J1");
  // R1 ends 0.4 m from A (within the 1 m snap tolerance) and is snapped onto it.
  ASSERT_EQ(m.intersections[0].id, "A");
  EXPECT_VEC2_NEAR(m.intersections[0].position, Vec2(30, 0.4), 1e-4);  // 9-decimal lon/lat: 0.1 mm
  EXPECT_EQ(m.roads[0].centerline.back(), m.intersections[0].position);
  const auto kind = [&](const std::string& id) {
    for (const Intersection& x : m.intersections) {
      if (x.id == id) return x.kind;
    }
    return IntersectionKind::Other;
  };
  EXPECT_EQ(kind("J1"), IntersectionKind::T);
  EXPECT_EQ(kind("A"), IntersectionKind::End);
  EXPECT_EQ(m.roads[0].width, 2.0);
  EXPECT_EQ(m.roads[0].surface, "concrete");
  EXPECT_TRUE(validateMap(m).empty());
  EXPECT_EQ(imported->road_features[0], "/features/1");
  EXPECT_EQ(imported->toFeaturePointer("/roads/0/centerline/1"), "/features/1/geometry/coordinates/1");
  EXPECT_EQ(imported->toFeaturePointer("/roads/2/width"), "/features/3/properties/width");
  EXPECT_EQ(imported->toFeaturePointer("/intersections/0/position"), "/features/0/geometry/coordinates");
  EXPECT_EQ(imported->toFeaturePointer("/intersections/1/kind"), "/intersections/1/kind");  // made, no feature
}

// Street centre lines as OpenStreetMap extracts give them: names only, a street in parts, streets
// that cross at a shared interior vertex, one that nearly meets another's end.
TEST(GeoJsonImport, PlainCentreLinesAreCutWhereTheyMeetAndNamedAfterTheirStreets) {
  Issues issues;
  GeoJsonImportOptions options;
  options.default_width_m = 7;
  options.default_surface = "asphalt";
  const auto imported = importGeoJson(readFile(testing::fixturePath("maps/valid/street_centre_lines.geojson")), issues, options);
  ASSERT_TRUE(imported) << (issues.empty() ? "" : formatIssue(issues[0], "inline"));
  const MapData& m = imported->map;
  std::vector<std::string> ids;
  for (const Road& r : m.roads) ids.push_back(r.id);
  // Main Street cut at its middle vertex, Cross Street's two parts, the third named by its feature id.
  EXPECT_EQ(ids, (std::vector<std::string>{"Main_Street-1", "Main_Street-2", "Cross_Street-1", "Cross_Street-2",
                                           "Weg_ueber_die_Bruecke"}));
  EXPECT_EQ(m.roads[4].properties.at("name").text, "Weg über die Brücke");
  const auto node = [&](const std::string& id) -> const Intersection& {
    return *std::find_if(m.intersections.begin(), m.intersections.end(), [&](const Intersection& x) { return x.id == id; });
  };
  // The four pieces meet at one node, a cross; the third street's start, 0.44 m north of Main
  // Street's end (within the 1 m snap), shares that end's node.
  EXPECT_EQ(m.roads[0].to, m.roads[1].from);
  EXPECT_EQ(m.roads[2].to, m.roads[0].to);
  EXPECT_EQ(m.roads[3].from, m.roads[0].to);
  EXPECT_EQ(node(m.roads[0].to).kind, IntersectionKind::Cross);
  EXPECT_EQ(m.roads[4].from, m.roads[1].to);
  EXPECT_EQ(m.intersections.size(), 6u);
  for (const Road& r : m.roads) {
    EXPECT_EQ(r.width, 7.0);
    EXPECT_EQ(r.surface, "asphalt");
  }
  EXPECT_TRUE(validateMap(m).empty());
  const auto said = [&](const std::string& words) {
    return std::any_of(imported->assumptions.begin(), imported->assumptions.end(),
                       [&](const std::string& a) { return a.find(words) != std::string::npos; });
  };
  EXPECT_TRUE(said("5 roads without a width: 7 m")) << ::testing::PrintToString(imported->assumptions);
  EXPECT_TRUE(said("3 road features named"));
  EXPECT_TRUE(said("1 MultiLineString"));
  EXPECT_TRUE(said("1 centre lines cut"));
  EXPECT_TRUE(said("6 intersections made"));
}

// The (check, where) of each issue of an import that must fail; `issues` keeps them whole.
using Found = std::vector<std::pair<std::string, std::string>>;
Found refusedWith(const std::string& text, Issues& issues) {
  issues.clear();
  EXPECT_FALSE(importGeoJson(text, issues));
  Found found;
  for (const Issue& issue : issues) found.emplace_back(issue.check, issue.where);
  return found;
}

TEST(GeoJsonImport, UnsupportedGeometryIsNamedWithItsPointer) {
  Issues issues;
  EXPECT_EQ(refusedWith(readFile(testing::fixturePath("malformed/unsupported_geometry.geojson")), issues),
            (Found{{"geojson.unsupported_geometry", "/features/0/geometry/type"}}));
}

// Landmarks go out as Point features with a `landmark` property and come back equal: ids,
// kinds, sizes, roads and kept properties exactly, positions within a millimetre.
TEST(GeoJsonExport, LandmarksRoundTripMapToGeoJsonToMapEqual) {
  const MapData map = testing::crossWithOneLandmarkOfEachKind();
  ASSERT_TRUE(validateMap(map).empty());
  const std::string text = exportGeoJson(map);
  const auto doc = nlohmann::json::parse(text);
  ASSERT_EQ(doc["features"].size(), 5u + 4u + 5u);  // intersections, roads, then landmarks
  EXPECT_EQ(doc["features"][9]["properties"],
            nlohmann::json::parse(R"({"landmark": "pole", "id": "P1", "radius": 0.1, "height": 5.0, "road": "R1"})"));
  EXPECT_EQ(doc["features"][10]["properties"],
            nlohmann::json::parse(R"({"landmark": "tree", "id": "T1", "radius": 0.25, "height": 8.0, "species": "Acer",
                                      "osm_node": "42"})"));
  EXPECT_EQ(doc["features"][10]["geometry"]["type"], "Point");
  // The bench's kept OSM `height` tag beside mapnav's height: inside mapnav_kept.
  EXPECT_EQ(doc["features"][11]["properties"]["height"], 0.8);
  EXPECT_EQ(doc["features"][11]["properties"]["mapnav_kept"], nlohmann::json::parse(R"({"height": "0.45 m"})"));
  Issues issues;
  const auto back = importGeoJson(text, issues);
  ASSERT_TRUE(back) << (issues.empty() ? "" : formatIssue(issues[0], "inline"));
  EXPECT_TRUE(issues.empty());
  EXPECT_TRUE(back->assumptions.empty()) << ::testing::PrintToString(back->assumptions);
  expectSameNetwork(back->map, map, 0.001);
  ASSERT_EQ(back->map.landmarks.size(), 5u);
  for (std::size_t i = 0; i < map.landmarks.size(); ++i) {
    EXPECT_TRUE(testing::landmarkNear(back->map.landmarks[i], map.landmarks[i], 0.001));
  }
  EXPECT_EQ(exportGeoJson(back->map), text);
}

// tests/data/maps/valid/landmarks_each_kind.geojson: a 60 m road east from A and one landmark of
// each kind drawn as a Point, at metres east/north of the file's origin (42.05 N, 87.67 W) written
// as lon/lat with the series for the metres per degree there (as in tests/osm). They are
// landmarks, not intersections, with their kind's size where the feature gives none.
TEST(GeoJsonImport, PointsWithALandmarkPropertyAreLandmarksOfEachKind) {
  Issues issues;
  const auto imported = importGeoJson(readFile(testing::fixturePath("maps/valid/landmarks_each_kind.geojson")), issues);
  ASSERT_TRUE(imported) << (issues.empty() ? "" : formatIssue(issues[0], "inline"));
  const MapData& m = imported->map;
  EXPECT_EQ(m.intersections.size(), 2u);
  EXPECT_EQ(m.roads.size(), 1u);
  ASSERT_EQ(m.landmarks.size(), 5u);
  // P1's `kind` is not interpreted (a landmark's kind is `landmark`): kept with the other members.
  const std::vector<Landmark> expected{
      {"P1", LandmarkKind::Pole, Vec2(10, 2.5), 0.12, 4.5, "R1", {{"kind", "lamp"}, {"ref", "lamp 7"}}},
      {"L1", LandmarkKind::Tree, Vec2(20, -3), 0.15, 6.0, "", {{"species", "Quercus rubra"}}},  // no id: made; a tree's size
      {"B1", LandmarkKind::Bench, Vec2(30, 2), 0.9, 0.85, "", {}},
      {"Bo1", LandmarkKind::Bollard, Vec2(40, 1.5), 0.1, 0.9, "", {}},  // a bollard's height
      {"M1", LandmarkKind::Manhole, Vec2(50, 0), 0.3, 0.0, "", {}}};    // a cover's size, flat
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_TRUE(testing::landmarkNear(m.landmarks[i], expected[i], 0.005));
  EXPECT_TRUE(validateMap(m).empty());
  EXPECT_EQ(imported->assumptions, (std::vector<std::string>{"the roads placed to 0.5 m (1 sigma; the file's mapnav member does not say)",
                                      "3 landmarks without a radius or a height: their kind's size"}));
  EXPECT_EQ(imported->landmark_features[1], "/features/4");
  EXPECT_EQ(imported->toFeaturePointer("/landmarks/1/kind"), "/features/4/properties/landmark");
  EXPECT_EQ(imported->toFeaturePointer("/landmarks/2/radius"), "/features/5/properties/radius");
  EXPECT_EQ(imported->toFeaturePointer("/landmarks/4/position"), "/features/7/geometry/coordinates");
}

TEST(GeoJsonImport, AnUnknownLandmarkKindIsAnErrorAtItsFeaturesLandmarkProperty) {
  Issues issues;
  ASSERT_EQ(refusedWith(readFile(testing::fixturePath("malformed/landmark_unknown_kind.geojson")), issues),
            (Found{{"schema.enum", "/features/4/properties/landmark"}}));
  EXPECT_NE(issues[0].message.find("\"lamppost\""), std::string::npos) << issues[0].message;
  EXPECT_NE(issues[0].message.find("pole, tree, bench, bollard, manhole"), std::string::npos) << issues[0].message;
}

// A landmark that is not a Point and a size that is not a number are errors at the feature; a size
// the map refuses is validation's, its pointer translated into the GeoJSON file.
TEST(GeoJsonImport, LandmarkErrorsPointIntoTheFeature) {
  const std::string bad = R"({"type": "FeatureCollection", "features": [
    {"type": "Feature", "properties": {"landmark": "tree"},
     "geometry": {"type": "LineString", "coordinates": [[-87.67, 42.05], [-87.6699, 42.05]]}},
    {"type": "Feature", "properties": {"landmark": "bench", "radius": "wide"}, "geometry": {"type": "Point", "coordinates": [-87.67, 42.05]}}]})";
  Issues issues;
  EXPECT_EQ(refusedWith(bad, issues), (Found{{"geojson.unsupported_geometry", "/features/0/geometry/type"},
                                             {"schema.type", "/features/1/properties/radius"}}));

  MapData map = testing::crossWithOneLandmarkOfEachKind();
  map.landmarks[2].radius = -1;
  issues.clear();
  const auto imported = importGeoJson(exportGeoJson(map), issues);
  ASSERT_TRUE(imported);
  std::vector<std::string> where;
  for (const Issue& issue : validateMap(imported->map)) {
    if (issue.check == "landmarks.invalid_size") where.push_back(imported->toFeaturePointer(issue.where));
  }
  EXPECT_EQ(where, (std::vector<std::string>{"/features/11/properties/radius"}));
}

// LocalCartesian's east/north against the geodesic on WGS84: random pairs up to 1 km apart around
// CMU agree within a centimetre.
TEST(LocalFrame, DistancesAgreeWithGeodesicsWithinOneCentimetreOverOneKilometre) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> coord(-700.0, 700.0);
  // At altitude h the local frame measures lengths at that height, (R + h) / R times the geodesic
  // on the ellipsoid: 4.4e-5 at CMU's 280 m, 3.8 cm over 870 m. On the ellipsoid (h = 0) they agree.
  const double earth_radius = 6371000.0;
  for (const double alt : {0.0, 280.0}) {
    SCOPED_TRACE(alt);
    const LocalFrame frame(GeoOrigin{40.4433, -79.9436, alt});
    int compared = 0;
    for (int i = 0; i < 500; ++i) {
      const Vec2 a(coord(rng), coord(rng)), b(coord(rng), coord(rng));
      const double local = (a - b).norm();
      if (local > 1000.0) continue;
      ++compared;
      const double geodesic = geodesicDistance(frame.toGeodetic(a), frame.toGeodetic(b));
      EXPECT_NEAR(local, geodesic * (1 + alt / earth_radius), 0.01);
    }
    EXPECT_GT(compared, 200);
    // And the round trip local → geodetic → local is exact to the precision of lat/lon in degrees.
    const Vec2 p(987.654, -321.0);
    EXPECT_VEC2_NEAR(frame.toLocal(frame.toGeodetic(p)), p, 1e-8);
  }
}

TEST(GeoJsonImportOptions, DefaultsAreValid) {
  EXPECT_NO_THROW(GeoJsonImportOptions{}.validate());
  GeoJsonImportOptions options;
  options.default_width_m = 0;
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { options.validate(); },
                                                "GeoJsonImportOptions::default_width_m = 0: must be finite and > 0"));
  options = {};
  options.default_shoulder = "";
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { options.validate(); },
                                                "GeoJsonImportOptions::default_shoulder = \"\": must be non-empty"));
}

}  // namespace
}  // namespace mapnav
