#pragma once
// Maps for the tests: the example maps loaded once per test program, maps built in code (a straight
// road, an avenue with landmarks, a cross), and comparing landmarks. Header-only: the
// support library itself does not link the map module.
#include <filesystem>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "mapnav/map/map.h"
#include "mapnav/map/map_io.h"
#include "mapnav/testing/support.h"

namespace mapnav::testing {

/// Success when `actual` is `expected` with its position within `tolerance` (m) and every other
/// member (id, kind, radius, height, road, properties) equal; otherwise a failure naming each
/// member that differs.
inline ::testing::AssertionResult landmarkNear(const Landmark& actual, const Landmark& expected, double tolerance) {
  std::ostringstream diff;
  if (actual.id != expected.id) diff << " id " << actual.id << " != " << expected.id << ";";
  if (actual.kind != expected.kind) diff << " kind " << toString(actual.kind) << " != " << toString(expected.kind) << ";";
  if (!((actual.position - expected.position).norm() <= tolerance)) {
    diff << " position (" << actual.position.transpose() << ") is " << (actual.position - expected.position).norm()
         << " m from (" << expected.position.transpose() << ");";
  }
  if (actual.radius != expected.radius) diff << " radius " << actual.radius << " != " << expected.radius << ";";
  if (actual.height != expected.height) diff << " height " << actual.height << " != " << expected.height << ";";
  if (actual.road != expected.road) diff << " road \"" << actual.road << "\" != \"" << expected.road << "\";";
  if (actual.properties != expected.properties) {
    diff << " properties {";
    for (const auto& [key, value] : actual.properties) diff << key << ": " << value.text << ", ";
    diff << "} differ;";
  }
  if (diff.str().empty()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "landmark " << expected.id << ":" << diff.str();
}

/// The example map at `path` without its landmarks, named "<file> without landmarks": the scene
/// the frame-by-frame tests of the renderer and the pipelines chose their figures in, before the
/// maps had landmarks (what the landmarks do to those figures: docs/measurements.md).
inline Map withoutLandmarks(const std::filesystem::path& path) {
  MapData data = loadMap(path).data();
  data.landmarks.clear();
  return Map(std::move(data), path.filename().string() + " without landmarks");
}

/// maps/cmu_campus.json, loaded once per test program.
inline const Map& campusMap() {
  static const Map map = loadMap(mapPath("cmu_campus.json"));
  return map;
}

/// maps/cmu_campus.json without its landmarks (withoutLandmarks), loaded once per test program.
inline const Map& campusWithoutLandmarks() {
  static const Map map = withoutLandmarks(mapPath("cmu_campus.json"));
  return map;
}

/// A straight road R1 from A (0, 0) to B (length_m, 0), width_m of `surface` with `shoulder` on both
/// sides; no surfaces' colours (the caller's), no landmarks.
inline MapData straightRoad(const std::string& name, double length_m, double width_m, const std::string& surface,
                            const std::string& shoulder) {
  MapData m;
  m.name = name;
  m.intersections = {{"A", IntersectionKind::End, Vec2(0, 0), std::nullopt},
                     {"B", IntersectionKind::End, Vec2(length_m, 0), std::nullopt}};
  Road r;
  r.id = "R1";
  r.from = "A";
  r.to = "B";
  r.centerline = Polyline2({Vec2(0, 0), Vec2(length_m, 0)});
  r.width = width_m;
  r.surface = surface;
  r.left = r.right = shoulder;
  m.roads = {r};
  return m;
}

/// Concrete and grass, as the campus has them: the colours of straightRoad's surfaces.
inline std::vector<std::pair<std::string, Appearance>> concreteAndGrass() {
  return {{"concrete", {Vec3(178, 176, 168), Vec3(10, 10, 10)}}, {"grass", {Vec3(70, 120, 50), Vec3(14, 18, 12)}}};
}

/// A straight avenue with no intersection for 230 m: A (0, 0) to B (230, 0), 2.5 m of concrete
/// between lawns; with landmarks, a tree or a lamp post beside it every 24-35 m, alternating sides,
/// trees 1.2 m and posts 0.45 m beyond the paving (the kind's default size).
inline MapData landmarkAvenue(bool with_landmarks) {
  MapData m = straightRoad(with_landmarks ? "avenue with landmarks" : "avenue", 230, 2.5, "concrete", "grass");
  m.surfaces = concreteAndGrass();
  if (!with_landmarks) return m;
  const double at[] = {24, 52, 80, 104, 139, 165, 190, 218};  // gaps of 24-35 m
  for (int i = 0; i < 8; ++i) {
    const bool tree = i % 3 != 1;
    const double side = i % 2 == 0 ? 1 : -1;
    const LandmarkKind kind = tree ? LandmarkKind::Tree : LandmarkKind::Pole;
    const LandmarkSize size = defaultLandmarkSize(kind);
    m.landmarks.push_back(Landmark{(tree ? "T" : "P") + std::to_string(i + 1), kind, Vec2(at[i], side * (1.25 + (tree ? 1.2 : 0.45))),
                                   size.radius_m, size.height_m, "R1", {}});
  }
  return m;
}

}  // namespace mapnav::testing
