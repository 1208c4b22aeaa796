// Reading traces back: the dialogue of hand-written records, and every bad line reported with its
// line number.
#include "mapnav/mission/trace.h"

#include <gtest/gtest.h>

#include "mapnav/core/error.h"

namespace mapnav {
namespace {

std::vector<std::pair<int, std::string>> problems(const std::string& text) {
  try {
    traceDialogue(text, "t.jsonl");
  } catch (const ValidationError& e) {
    EXPECT_EQ(e.file(), "t.jsonl");
    std::vector<std::pair<int, std::string>> out;
    for (const Issue& i : e.issues()) out.emplace_back(i.line, i.check + ": " + i.message);
    return out;
  }
  return {};
}

TEST(TraceDialogue, SaysTheNavigatorsCommandAsThePaperDoes) {
  const std::string text =
      R"({"t":1.5,"frame":3,"module":"Navigator","type":"MotionCommand","payload":{"sequence":4,"aborts":3,"kind":"drive","reason":"","road":"R1","drive_m":2.5,"same_road":true,"next_turn":{"at":"I1","onto":"R2","direction":"right","degrees":-90.0},"path_ends_at_goal":false,"speed_mps":0.6,"setpoint":{"speed_mps":0.6,"turn_rate_deg_s":0.0},"lookahead":[1,2],"path":[[0,0],[1,0]]}})"
      "\n"
      R"({"t":1.5,"frame":3,"module":"MotionControl","type":"Executing","payload":{"sequence":4,"executes":true,"kind":"drive"}})"
      "\n";
  EXPECT_EQ(traceDialogue(text, "t.jsonl"),
            "Navigator: Drive on it 2.5 meters and turn to right 90 degrees.\nMotion Control: Ok. I drive.\n");
}

TEST(TraceDialogue, EveryBadLineIsReportedWithItsNumber) {
  const std::string good = R"({"t":0,"frame":null,"module":"MotionControl","type":"Executing","payload":{"sequence":null,"executes":false,"kind":"stop"}})";
  const std::string text = good + "\n" +                                            // 1
                           "not json\n" +                                           // 2
                           "\n" +                                                   // 3: blank, skipped
                           R"({"t":"soon","frame":1,"module":"Map","type":"Halt","payload":{}})" "\n" +  // 4
                           R"({"t":1,"frame":1,"module":"Vision","type":"Halt","payload":{"reason":"x"}})" "\n" +  // 5
                           R"({"t":1,"frame":1,"module":"Map","type":"Halt","payload":{}})" "\n" +  // 6
                           R"({"t":1,"frame":-2,"module":"Map","type":"CurrentPosition","payload":{}})" "\n" +  // 7
                           good;                                                    // 8, no newline at the end
  const auto got = problems(text);
  ASSERT_EQ(got.size(), 5u);
  EXPECT_EQ(got[0].first, 2);
  EXPECT_EQ(got[0].second.rfind("trace.not_json: not JSON", 0), 0u) << got[0].second;
  EXPECT_EQ(got[1], (std::pair<int, std::string>{4, "trace.field: /t: expected a number, got string"}));
  EXPECT_EQ(got[2], (std::pair<int, std::string>{5, "trace.field: /payload/control_to: missing"}));
  EXPECT_EQ(got[3], (std::pair<int, std::string>{6, "trace.type: /type: Map does not write \"Halt\" records"}));
  EXPECT_EQ(got[4], (std::pair<int, std::string>{7, "trace.field: /frame: expected a frame number or null"}));
}

TEST(TraceDialogue, AnEmptyFileIsNotATrace) {
  const auto got = problems("\n\n");
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].second, "trace.empty: no records: not a mapnav trace");
}

}  // namespace
}  // namespace mapnav
