#include "mapnav/navigator/road_position.h"

#include <gtest/gtest.h>

#include <string>

#include "mapnav/core/error.h"
#include "mapnav/map/generate.h"
#include "mapnav/navigator/route.h"

namespace mapnav {
namespace {

/// The InvalidInput message parseRoadPosition gives for `text` ("" when it parses).
std::string parseError(const std::string& text) {
  try {
    parseRoadPosition(text);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

TEST(RoadPositionText, ParsesRoadNodeMetersAndTheOptionalLateralOffset) {
  EXPECT_EQ(parseRoadPosition("R1@I1+3"), (RoadPosition{"R1", "I1", 3.0, 0.0}));
  EXPECT_EQ(parseRoadPosition("Road_7-b@I12+2.5/-0.4"), (RoadPosition{"Road_7-b", "I12", 2.5, -0.4}));
  EXPECT_EQ(parseRoadPosition("R1@I1+3./+1"), (RoadPosition{"R1", "I1", 3.0, 1.0}));
}

TEST(RoadPositionText, MalformedTextIsAnInvalidInputSayingWhatIsExpected) {
  for (const std::string text : {"", "R1", "R1@I1", "R1@I1+", "1R@I1+3", "R1@I1+-3", "R1@I1+3/", "R1@I1+3/x",
                                 "R1@I1+.5", "R1@I1+3 ", "R 1@I1+3", "R1@@I1+3", "R1@I1+3/+0.4/1", "R1@I1+1e3"}) {
    EXPECT_NE(parseError(text).find("expected ROAD@NODE+METERS[/LATERAL]"), std::string::npos) << text;
  }
}

// Found with fuzz_road_position: numbers beyond the range of a double escaped as
// std::out_of_range (std::stod) instead of InvalidInput, past loadMission's handler.
TEST(RoadPositionText, NumbersBeyondTheRangeOfADoubleAreInvalidInput) {
  const std::string huge(400, '9');
  EXPECT_NE(parseError("R1@I1+" + huge).find("out of range"), std::string::npos);
  EXPECT_NE(parseError("R1@I1+3/-" + huge).find("out of range"), std::string::npos);
}

// Found with fuzz_road_position: std::regex matched recursively, one stack frame per
// character, so a long identifier overflowed the stack (a segmentation fault).
TEST(RoadPositionText, AVeryLongIdentifierParsesWithoutExhaustingTheStack) {
  const std::string road = "R" + std::string(1000000, 'a');
  EXPECT_EQ(parseRoadPosition(road + "@I1+3").road, road);
}

// Found with fuzz_road_position: toString printed 6 significant digits ("%g"), so the
// trace header named a different start than the mission's, and 1e6 m printed as "1e+06", which
// does not parse.
TEST(RoadPositionText, ToStringReadsBackToTheSamePosition) {
  for (const RoadPosition& p : {RoadPosition{"R1", "I1", 3.0, 0.0}, RoadPosition{"R1", "I1", 1.0 / 3.0, -0.4},
                                RoadPosition{"R2", "I3", 1e6, 0.5}, RoadPosition{"R2", "I3", 123456.789, 1e-9}}) {
    EXPECT_EQ(parseRoadPosition(toString(p)), p) << toString(p);
  }
  EXPECT_EQ(toString(RoadPosition{"R1", "I1", 3.0, 0.0}), "R1@I1+3");
  EXPECT_EQ(toString(RoadPosition{"R1", "I1", 2.5, -0.4}), "R1@I1+2.5/-0.4");
  EXPECT_EQ(toString(RoadPosition{"R1", "I1", 1e6, 0.5}), "R1@I1+1000000/+0.5");
}

// A position just past the end of a 0.878061 m road: the message prints enough digits not to say
// "0.879 m is beyond the road's 0.88 m", and the same from toPose and from a route.
TEST(RoadPositionRange, TheMessageNeverContradictsTheComparison) {
  MapData data = makeGridMap(GridMapOptions{2, 2, 30, 2});  // for its surfaces
  data.intersections.resize(2);
  data.intersections[1].position = Vec2(0.878061, 0);
  data.roads.resize(1);
  Road& road = data.roads.front();
  road.from = data.intersections[0].id;
  road.to = data.intersections[1].id;
  road.width = 0.5;
  road.centerline = Polyline2({Vec2(0, 0), Vec2(0.878061, 0)});
  const Map map(data);
  const RoadPosition p{road.id, road.from, 0.879};
  const std::string want = "road position " + toString(p) + ": 0.879 m is beyond the road's 0.878 m";
  auto message = [&](auto&& call) -> std::string {
    try {
      call();
    } catch (const InvalidInput& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(message([&] { toPose(map, p); }), want);
  RoadGraph graph(map);
  EXPECT_EQ(message([&] { graph.route(p, RoadPosition{road.id, road.from, 0.1}); }), want);
  EXPECT_EQ(message([&] { toPose(map, RoadPosition{road.id, road.from, -0.5}); }),
            "road position " + road.id + "@" + road.from + "+-0.5: -0.50 m is outside the road's 0.88 m");
}

}  // namespace
}  // namespace mapnav
