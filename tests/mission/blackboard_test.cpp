// The blackboard: who may post and read what (information hiding), newer plans abort older ones,
// tokens older than their validity are dropped, a halt stays until the operator resumes.
#include "mapnav/mission/blackboard.h"

#include <gtest/gtest.h>

#include "mapnav/core/error.h"

namespace mapnav {
namespace {

MotionCommand command(std::uint64_t sequence, double t) {
  MotionCommand c;
  c.sequence = sequence;
  c.timestamp = t;
  c.road = "R1";
  return c;
}

CurrentPosition position(double t) {
  CurrentPosition p;
  p.timestamp = t;
  p.pose = Pose2(1, 2, 0.5);
  return p;
}

TEST(MissionBlackboard, DefaultOptionsAreValidAndABadOneIsNamed) {
  EXPECT_NO_THROW(BlackboardOptions{}.validate());
  BlackboardOptions bad;
  bad.command_validity_s = 0;
  try {
    bad.validate();
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("command_validity_s"), std::string::npos) << e.what();
  }
}

TEST(MissionBlackboard, VisionMayReadOnlyThePredictedObject) {
  Blackboard board;
  PredictionToken p;
  p.view.timestamp = 1;
  p.made_for = Pose2(10, 20, 1);
  board.post(Module::Map, p);
  board.post(Module::Map, position(1));
  board.post(Module::Navigator, command(1, 1));
  // What Vision gets carries no pose: only the view.
  const PredictedObject* view = board.prediction(Module::Vision, 1);
  ASSERT_NE(view, nullptr);
  EXPECT_EQ(view->timestamp, 1);
  EXPECT_THROW(board.position(Module::Vision, 1), Error);
  EXPECT_THROW(board.command(Module::Vision, 1), Error);
  EXPECT_THROW(board.detection(Module::Navigator, 1), Error);
  EXPECT_THROW(board.detection(Module::Vision, 1), Error);
  EXPECT_FALSE(Blackboard::mayRead(Module::Vision, TokenType::CurrentPosition));
  EXPECT_TRUE(Blackboard::mayRead(Module::Vision, TokenType::Halt));
}

TEST(MissionBlackboard, OnlyTheOwnerPostsEachToken) {
  Blackboard board;
  EXPECT_THROW(board.post(Module::Vision, position(0)), Error);
  EXPECT_THROW(board.post(Module::Map, command(1, 0)), Error);
  EXPECT_THROW(board.post(Module::Navigator, Resume{0, 1}), Error);
  EXPECT_THROW(board.post(Module::MotionControl, VisionFailure{0, "x"}), Error);
  EXPECT_TRUE(board.post(Module::User, Resume{0, 1}));
}

TEST(MissionBlackboard, ANewerSteeringPlanAbortsTheOlderOne) {
  Blackboard board;
  std::vector<Posting> posted;
  std::vector<Drop> dropped;
  board.onPost([&](const Posting& p) { posted.push_back(p); });
  board.onDrop([&](const Drop& d) { dropped.push_back(d); });
  EXPECT_TRUE(board.post(Module::Navigator, command(1, 0.0)));
  EXPECT_TRUE(board.post(Module::Navigator, command(2, 0.5)));
  ASSERT_EQ(posted.size(), 2u);
  EXPECT_EQ(posted[0].aborts, 0u);
  EXPECT_EQ(posted[1].aborts, 1u);
  EXPECT_EQ(board.command(Module::MotionControl, 0.5)->sequence, 2u);
  // An older plan arriving late does not replace the newer one.
  EXPECT_FALSE(board.post(Module::Navigator, command(3, 0.2)));
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0].type, TokenType::MotionCommand);
  EXPECT_NE(dropped[0].why.find("stale"), std::string::npos);
  EXPECT_EQ(board.command(Module::MotionControl, 0.5)->sequence, 2u);
}

TEST(MissionBlackboard, TokensOlderThanTheirValidityAreDropped) {
  BlackboardOptions options;
  options.position_validity_s = 1.0;
  options.command_validity_s = 2.0;
  Blackboard board(options);
  std::vector<Drop> dropped;
  board.onDrop([&](const Drop& d) { dropped.push_back(d); });
  board.post(Module::Map, position(10));
  board.post(Module::Navigator, command(1, 10));
  EXPECT_NE(board.position(Module::Navigator, 10.9), nullptr);
  EXPECT_NE(board.command(Module::MotionControl, 11.9), nullptr);
  EXPECT_EQ(board.position(Module::Navigator, 11.5), nullptr);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0].type, TokenType::CurrentPosition);
  EXPECT_DOUBLE_EQ(dropped[0].token_time, 10);
  EXPECT_NE(dropped[0].why.find("expired"), std::string::npos) << dropped[0].why;
  EXPECT_EQ(board.position(Module::Navigator, 11.5), nullptr);  // gone: dropped once
  EXPECT_EQ(dropped.size(), 1u);
  EXPECT_EQ(board.command(Module::MotionControl, 12.5), nullptr);
  EXPECT_EQ(dropped.size(), 2u);
}

TEST(MissionBlackboard, AHaltStaysUntilTheOperatorResumes) {
  Blackboard board;
  EXPECT_EQ(board.halt(Module::Navigator), nullptr);
  Halt halt;
  halt.timestamp = 3;
  halt.reason = "vision failed: frame too dark";
  board.post(Module::Vision, halt);
  ASSERT_NE(board.halt(Module::Navigator), nullptr);
  EXPECT_EQ(board.halt(Module::MotionControl)->reason, "vision failed: frame too dark");
  EXPECT_NE(board.halt(Module::Map), nullptr);  // halts do not expire
  board.post(Module::User, Resume{5, 2});
  EXPECT_EQ(board.halt(Module::Navigator), nullptr);
}

TEST(MissionBlackboard, NamesRoundTrip) {
  for (Module m : {Module::User, Module::Sensors, Module::Map, Module::Vision, Module::Navigator, Module::MotionControl,
                   Module::Blackboard, Module::Mission}) {
    EXPECT_EQ(moduleFromString(toString(m)), m);
  }
  for (TokenType t : {TokenType::PredictedObject, TokenType::DetectedObject, TokenType::CurrentPosition,
                      TokenType::MotionCommand, TokenType::VisionFailure, TokenType::Halt, TokenType::Resume}) {
    EXPECT_EQ(tokenTypeFromString(toString(t)), t);
  }
  EXPECT_EQ(commandKindFromString("stop"), CommandKind::Stop);
  EXPECT_FALSE(moduleFromString("Planner"));
}

}  // namespace
}  // namespace mapnav
