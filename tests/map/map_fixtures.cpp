#include "map_fixtures.h"

namespace mapnav::testing {

MapData crossOfFourRoads() {
  MapData m;
  m.name = "cross of four roads";
  m.surfaces = {{"concrete", Appearance{Vec3(178, 176, 168), Vec3(10, 10, 10)}},
                {"grass", Appearance{Vec3(70, 120, 50), Vec3(14, 18, 12)}}};
  m.intersections = {{"I1", IntersectionKind::Cross, Vec2(0, 0), std::nullopt},
                     {"E", IntersectionKind::End, Vec2(20, 0), std::nullopt},
                     {"N", IntersectionKind::End, Vec2(0, 20), std::nullopt},
                     {"W", IntersectionKind::End, Vec2(-20, 0), std::nullopt},
                     {"S", IntersectionKind::End, Vec2(0, -20), std::nullopt}};
  const char* ends[] = {"E", "N", "W", "S"};
  for (int i = 0; i < 4; ++i) {
    Road r;
    r.id = "R" + std::to_string(i + 1);
    r.from = "I1";
    r.to = ends[i];
    r.centerline = Polyline2({Vec2(0, 0), m.intersections[static_cast<std::size_t>(i) + 1].position});
    r.width = 2.0;
    r.surface = "concrete";
    r.left = r.right = "grass";
    m.roads.push_back(r);
  }
  return m;
}

MapData crossWithOneLandmarkOfEachKind() {
  MapData m = crossOfFourRoads();
  m.origin = GeoOrigin{42.05, -87.67, 0.0};
  m.landmarks = {{"P1", LandmarkKind::Pole, Vec2(10, 2), 0.1, 5.0, "R1", {}},
                 {"T1", LandmarkKind::Tree, Vec2(-3, 12), 0.25, 8.0, "", {{"species", PropertyValue("Acer")},
                                                                         {"osm_node", PropertyValue("42")}}},
                 {"B1", LandmarkKind::Bench, Vec2(-12, -2.5), 0.8, 0.8, "", {{"height", PropertyValue("0.45 m")}}},
                 {"Bo1", LandmarkKind::Bollard, Vec2(2, -6), 0.08, 0.9, "R4", {}},
                 {"M1", LandmarkKind::Manhole, Vec2(15, 0), 0.3, 0.0, "", {}}};
  return m;
}

}  // namespace mapnav::testing
