#pragma once
// Comparing landmarks (issue 28) in the tests of the modules that read and write them. Header-only:
// the support library itself does not link the map module.
#include <sstream>

#include <gtest/gtest.h>

#include "mapnav/map/map.h"

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

}  // namespace mapnav::testing
