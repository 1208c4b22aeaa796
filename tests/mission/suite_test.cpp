// The suite of unseen maps (mission_sim/suite.h): its seed lists. The runs themselves are tested end to
// end through the CLI (tests/apps/suite_cli_test.cpp).
#include "mapnav/mission_sim/suite.h"

#include <gtest/gtest.h>

#include "mapnav/core/error.h"

namespace mapnav {
namespace {

TEST(SuiteSeeds, RangesAndListsInTheOrderGivenEachOnce) {
  EXPECT_EQ(parseSeedList("1-3"), (std::vector<std::uint64_t>{1, 2, 3}));
  EXPECT_EQ(parseSeedList("7"), (std::vector<std::uint64_t>{7}));
  EXPECT_EQ(parseSeedList("9,1-2,2,10-10"), (std::vector<std::uint64_t>{9, 1, 2, 10}));
}

TEST(SuiteSeeds, BadListsSayWhatIsWrong) {
  auto message = [](const std::string& text) {
    try {
      parseSeedList(text);
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("5-2"), "'5-2' is not a seed list: the range '5-2' runs backwards (its first seed is above its last)");
  EXPECT_EQ(message("x"), "'x' is not a seed list: 'x' is not a seed or a range (expected seeds and ranges of them, e.g. "
                          "1-30, 7 or 1,4,9-12)");
  EXPECT_NE(message(""), "no error");
  EXPECT_NE(message("1,"), "no error");
  EXPECT_NE(message("-3"), "no error");
  EXPECT_NE(message("1-2-3"), "no error");
}

}  // namespace
}  // namespace mapnav
