#include "mapnav/map/geojson.h"

#include <gtest/gtest.h>

#include <random>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/map/geodesy.h"
#include "mapnav/map/map_io.h"
#include "mapnav/map/validation.h"
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
    ASSERT_EQ(r.centerline.size(), s.centerline.size());
    for (std::size_t k = 0; k < r.centerline.size(); ++k) {
      EXPECT_VEC2_NEAR(r.centerline.points()[k], s.centerline.points()[k], tol);
    }
  }
}

TEST(GeoJsonImport, CampusGeoJsonMatchesTheCampusMapWithinOneCentimetre) {
  const MapData native = loadMap(testing::mapPath("cmu_campus.json")).data();
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

TEST(GeoJsonExport, AMapWithoutOriginNeedsOne) {
  MapData data = loadMap(testing::mapPath("cmu_campus.json")).data();
  data.origin.reset();
  EXPECT_THROW(exportGeoJson(data), InvalidInput);
  EXPECT_NO_THROW(exportGeoJson(data, GeoOrigin{40.0, -80.0, 0.0}));
}

// Three lines drawn in geojson.io meeting at one point, one ending at a named Point: no ids, no
// from/to. The junction becomes a T, the free ends dead ends, the named point is used.
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

TEST(GeoJsonImport, UnsupportedGeometryIsNamedWithItsPointer) {
  Issues issues;
  EXPECT_FALSE(importGeoJson(readFile(testing::fixturePath("malformed/unsupported_geometry.geojson")), issues));
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].check, "geojson.unsupported_geometry");
  EXPECT_EQ(issues[0].where, "/features/0/geometry/type");
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
  EXPECT_THROW(options.validate(), InvalidInput);
}

}  // namespace
}  // namespace mapnav
