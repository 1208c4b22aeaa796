// The tokens as JSON (tokens/token_json.h) on small hand-made tokens: each field where the layout
// says, each number rounded to its step (worked out by hand below), frames as the tokens hold them.
#include "mapnav/tokens/token_json.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mapnav {
namespace {

TEST(TokenJson, ADetectionRoundsMetresPixelsAndScoresToTheirSteps) {
  DetectedObject d;
  d.confidence = 0.123456;  // scores to 1e-4: 0.1235
  DetectedLine line;
  line.label = "R1.left.0";
  line.score = 0.98766;                                      // 0.9877
  line.image = Segment2{Vec2(10.004, 20.006), Vec2(30, 40)};  // pixels to 0.01: 10 (10.004), 20.01
  line.vehicle = Segment2{Vec2(1.23456, -0.00004), Vec2(5, 0)};  // metres to 1e-4: 1.2346, -0.0 -> 0
  d.lines.push_back(line);
  d.region_image = {Vec2(1, 2), Vec2(3, 4), Vec2(5, 6)};
  d.region_vehicle = {Vec2(9, 9)};  // not written: the outline in pixels is the region
  DetectedLandmark seen;
  seen.id = "T1";
  seen.found = true;
  seen.image_base = Vec2(100.126, 50);
  seen.covariance << 4, 0, 0, 2.25;  // sigmas 2 and 1.5 px
  seen.score = 0.5;
  d.landmarks.push_back(seen);
  DetectedLandmark missed;
  missed.id = "T2";
  missed.reason = "no vertical edge pair near the prediction";
  d.landmarks.push_back(missed);
  const Json j = toJson(d);
  EXPECT_EQ(j.dump(),
            R"({"status":"ok","reason":"","confidence":0.1235,)"
            R"("lines":[{"label":"R1.left.0","score":0.9877,"frame_edge":false,"image":[[10.0,20.01],[30.0,40.0]],)"
            R"("vehicle":[[1.2346,0.0],[5.0,0.0]]}],"region_image":[[1.0,2.0],[3.0,4.0],[5.0,6.0]],"centerline":null,)"
            R"("landmarks":[{"id":"T1","found":true,"image_base":[100.13,50.0],"sigma_px":[2.0,1.5],"score":0.5},)"
            R"({"id":"T2","found":false,"reason":"no vertical edge pair near the prediction"}],"step":null})");
  EXPECT_FALSE(std::signbit(j["lines"][0]["vehicle"][0][1].get<double>()));  // -0 is written as 0
}

TEST(TokenJson, APositionsSigmasAreAcrossAndAlongItsHeading) {
  CurrentPosition p;
  p.pose = Pose2(1, 2, kPi / 2);  // facing world +y: along = world y, across = world x
  p.covariance << 4, 0, 0,  //
      0, 1, 0,              //
      0, 0, 0.01;           // heading sigma 0.1 rad = 5.72958 degrees (six digits)
  p.status = PositionStatus::Corrected;
  const Json j = toJson(p);
  EXPECT_EQ(j["pose"].dump(), R"({"x":1.0,"y":2.0,"heading_deg":90.0})");
  EXPECT_EQ(j["sigma"].dump(), R"({"lateral_m":2.0,"along_m":1.0,"heading_deg":5.72958})");
  EXPECT_EQ(j["covariance"].dump(), "[4.0,0.0,0.0,1.0,0.0,0.01]");
  EXPECT_EQ(j["status"], "corrected");
  EXPECT_TRUE(j["rejected_fit"].is_null());
}

TEST(TokenJson, APredictionWritesItsSegmentsWithTheirOwnerAndItsRelationsByType) {
  PredictedObject view;
  view.footprint = {Vec2(1, -2), Vec2(10, -5), Vec2(10, 5), Vec2(1, 2)};
  PredictedRegion region;
  region.id = "R1";
  region.kind = "straight road";
  region.surface = "asphalt";
  region.segments = {"R1.left.0"};
  view.regions.push_back(region);
  InterestSegment s;
  s.id = "R1.left.0";
  s.owner = "R1";
  s.side = "left";
  s.vehicle = Segment2{Vec2(2, 1.5), Vec2(9, 1.5)};
  s.image = Segment2{Vec2(100.556, 200), Vec2(300, 100)};
  view.segments.push_back(s);
  SegmentRelation parallel;
  parallel.a = "R1.left.0";
  parallel.b = "R1.right.0";
  parallel.separation_m = 3.00004;  // 3.0
  SegmentRelation crossing;
  crossing.type = SegmentRelation::Type::Crossing;
  crossing.a = "R1.left.0";
  crossing.b = "R2.right.0";
  crossing.angle_rad = kPi / 2;
  crossing.point = Vec2(6, 1.5);
  view.relations = {parallel, crossing};
  const Json j = toJson(view);
  EXPECT_EQ(j["footprint"].dump(), "[[1.0,-2.0],[10.0,-5.0],[10.0,5.0],[1.0,2.0]]");
  EXPECT_EQ(j["segments"][0]["owner"], "R1");
  EXPECT_EQ(j["segments"][0]["image"].dump(), "[[100.56,200.0],[300.0,100.0]]");
  EXPECT_EQ(j["relations"][0].dump(), R"({"type":"parallel","a":"R1.left.0","b":"R1.right.0","separation_m":3.0})");
  EXPECT_EQ(j["relations"][1].dump(),
            R"({"type":"crossing","a":"R1.left.0","b":"R2.right.0","angle_deg":90.0,"point":[6.0,1.5]})");
  EXPECT_EQ(j["regions"][0].dump(), R"({"id":"R1","kind":"straight road","surface":"asphalt","segments":["R1.left.0"]})");
}

}  // namespace
}  // namespace mapnav
