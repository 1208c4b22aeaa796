// The test support's policy for real data (../shared/data/real): present, the check passes; missing,
// it fails with a message naming the folder, so that a test needing it fails instead of skipping.
#include <gtest/gtest.h>

#include <string>

#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

TEST(RealDataPolicy, AMissingDataSetFailsNamingItsFolder) {
  const ::testing::AssertionResult r = testing::realDataPresent("no-such-data-set");
  EXPECT_FALSE(r);
  const std::string message = r.message();
  EXPECT_NE(message.find("missing ../shared/data/real/no-such-data-set"), std::string::npos) << message;
  EXPECT_NE(message.find((testing::realDataPath("no-such-data-set")).string()), std::string::npos) << message;
}

TEST(RealDataPolicy, APresentDataSetPasses) {
  // The real data's README is part of the shared folder the tests need.
  EXPECT_TRUE(testing::realDataPresent("README.md"));
}

}  // namespace
}  // namespace mapnav
