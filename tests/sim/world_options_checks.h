#pragma once
// Checks shared by the tests of WorldOptions' fields (world_test, world_threads_test,
// world_texels_test, world_landmarks_test): a bad value is named by validate() and by the reader.
#include <gtest/gtest.h>

#include <string>

#include "mapnav/core/error.h"
#include "mapnav/sim/world.h"
#include "mapnav/sim/world_io.h"
#include "mapnav/testing/support.h"

namespace mapnav::simtest {

/// Success when `o.validate()` throws InvalidInput naming `field`.
inline ::testing::AssertionResult rejectedNaming(const WorldOptions& o, const std::string& field) {
  return testing::throwsInvalidInputNaming([&] { o.validate(); }, field);
}

/// Expects parseWorldOptions to read {"FIELD": good} without an issue and to report {"FIELD": bad} as
/// one issue at /world/FIELD; returns the options read from the good one, for the caller to check.
inline WorldOptions readsGoodAndNamesBad(const std::string& field, const std::string& good, const std::string& bad) {
  Issues issues;
  const WorldOptions read = parseWorldOptions("{\"" + field + "\": " + good + "}", "/world", issues);
  EXPECT_TRUE(issues.empty()) << field << ": " << good;
  issues.clear();
  parseWorldOptions("{\"" + field + "\": " + bad + "}", "/world", issues);
  EXPECT_EQ(issues.size(), 1u) << field << ": " << bad;
  if (!issues.empty()) {
    EXPECT_EQ(issues[0].where, "/world/" + field);
  }
  return read;
}

}  // namespace mapnav::simtest
