// The suite of unseen maps (mission_sim/suite.h): its seed lists and a run's record (what a run done
// on another machine sends home). The runs themselves are tested end to end through the CLI
// (tests/apps/suite_cli_test.cpp).
#include "mapnav/mission_sim/suite.h"

#include <gtest/gtest.h>

#include "mapnav/core/error.h"
#include "mapnav/testing/support.h"
#include "mapnav/vision/pipelines.h"

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

// Two short runs and a run that threw, each sent through its record: the rows, the summary and the
// suite's JSON (wall times included) are the same bytes as from the runs themselves.
TEST(SuiteRunRecord, ARunThroughItsRecordPrintsTheSameRowsSummaryAndJson) {
  registerBuiltinPipelines();
  SuiteOptions options;
  options.seeds = {3, 4};
  options.max_frames = 3;
  options.camera = testing::mapPath("cameras/terregator_pinhole.json");
  options.folder = testing::freshTempDir();
  std::vector<SuiteRun> runs;
  for (const std::uint64_t seed : options.seeds) runs.push_back(runSuiteSeed(seed, options));
  SuiteRun threw;
  threw.seed = 9;
  threw.junctions = "cross T";
  threw.error = true;
  threw.outcome = "error: the map has no road";
  threw.wall_s = 0.1234567891;
  runs.push_back(threw);
  ASSERT_FALSE(runs[0].run_json.empty()) << runs[0].outcome;
  ASSERT_GT(runs[0].metrics.frames, 0u);

  std::vector<SuiteRun> sent;
  for (const SuiteRun& r : runs) sent.push_back(suiteRunFromJson(suiteRunToJson(r)));
  for (std::size_t i = 0; i < runs.size(); ++i) {
    EXPECT_EQ(suiteRowText(sent[i], true), suiteRowText(runs[i], true)) << i;
    EXPECT_EQ(sent[i].mission, runs[i].mission);
    EXPECT_EQ(sent[i].route_m, runs[i].route_m);
  }
  EXPECT_EQ(suiteSummaryText(summarizeSuite(sent), true), suiteSummaryText(summarizeSuite(runs), true));
  EXPECT_EQ(suiteJson(options, sent, summarizeSuite(sent), true), suiteJson(options, runs, summarizeSuite(runs), true));
}

TEST(SuiteRunRecord, ABrokenRecordSaysWhatIsWrong) {
  EXPECT_TRUE(testing::throwsInvalidInputNaming([] { suiteRunFromJson("{\"seed\": 3"); }, "not a suite run record"));
  EXPECT_TRUE(testing::throwsInvalidInputNaming([] { suiteRunFromJson(R"({"seed": 3})"); }, "metrics"));
  EXPECT_TRUE(testing::throwsInvalidInputNaming([] { suiteRunFromJson(R"({"seed": "x", "metrics": {}})"); }, "'{\"seed\""));
}

}  // namespace
}  // namespace mapnav
