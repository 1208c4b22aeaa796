// The four modules, each step on its own: Map predicts for the predicted pose and falls back to
// odometry; Vision sees only the prediction and halts on failure; the Navigator plans from the
// estimate, replans off the route and stops while halted; Motion Control executes the newest plan,
// stops when it expires and arrives at the goal.
#include "mapnav/mission/modules.h"

#include <gtest/gtest.h>

#include "mapnav/core/error.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

const Map& campus() { return testing::campusMap(); }

// A pipeline that says what it is told and counts its calls.
class ScriptedPipeline : public VisionPipeline {
 public:
  explicit ScriptedPipeline(DetectedObject answer, int* calls) : answer_(std::move(answer)), calls_(calls) {}
  std::string name() const override { return "scripted"; }
  void configure(const std::string&) override {}
  DetectedObject detect(const VisionFrame&, const PredictedObject&) override {
    ++*calls_;
    return answer_;
  }
  void reset() override {}

 private:
  DetectedObject answer_;
  int* calls_;
};

std::vector<TokenType> types(const std::vector<Posting>& postings) {
  std::vector<TokenType> out;
  for (const Posting& p : postings) out.push_back(tokenType(p.token));
  return out;
}

TEST(MissionModules, MapModuleDefaultsAreValid) { EXPECT_NO_THROW(MapModuleOptions{}.validate()); }

TEST(MissionModules, MapPredictsForThePredictedPoseAndFallsBackToOdometryWithoutADetection) {
  const auto camera = testing::terregatorPinhole();
  MapModule map(campus(), *camera, Pose2(53, 40, kPi));  // on R1 facing I1, as the dialogue starts
  Blackboard board;
  std::vector<Posting> posted;
  board.onPost([&](const Posting& p) { posted.push_back(p); });
  map.predict(board, 0.5, MotionIncrement{1.0, 0.0});
  ASSERT_EQ(posted.size(), 1u);
  const auto& prediction = std::get<PredictionToken>(posted[0].token);
  EXPECT_POSE_NEAR(prediction.made_for, Pose2(52, 40, kPi), 1e-9);
  EXPECT_DOUBLE_EQ(prediction.view.timestamp, 0.5);
  EXPECT_FALSE(prediction.view.empty());
  const CurrentPosition& position = map.localize(board, 0.5);
  EXPECT_EQ(position.status, PositionStatus::OdometryOnly);
  EXPECT_NE(position.reason.find("no DetectedObject"), std::string::npos) << position.reason;
  EXPECT_POSE_NEAR(position.pose, Pose2(52, 40, kPi), 1e-9);
  EXPECT_EQ(tokenType(posted.back().token), TokenType::CurrentPosition);
}

// The odometry scale, estimated by the pose filter (MotionNoiseOptions::scale_sigma). On the campus'
// R1 (straight along x from I1 at x = 50), the truth drives west from x = 80, 1 m a frame, the
// encoders reading 1.02 m. Frames 1 to 20 see nothing (odometry only); frames 21 and 22 (10 and 9 m
// before I1) see every predicted line where the truth sees it, I1's crossing lines among them: an
// along-road fix. The estimate is then 0.42-0.44 m behind the truth's progress, and the fix moves the
// scale error e by that error times cov(along, e) / var(along): with sigma_e = 0.02 the scale's
// sigma_e^2 D^2 (D = 21.4 m: 0.18 m^2) is most of the along variance (the random 2 %/m adds 0.009
// m^2, the start 0.0001 m^2), so e goes to about -0.44 / 21.4 * 0.95 = -0.019: scale 0.981 against
// the true 1 / 1.02 = 0.9804. With the scale not estimated (sigma 0) the random model alone cannot
// cover the 0.44 m: the gate refuses the fix.
double scaleAfterADrive(bool fix_at_the_end, double prior_sigma) {
  const auto camera = testing::terregatorPinhole();
  MapModuleOptions options;
  options.initial_sigma_m = 0.01;
  options.filter.motion.scale_sigma = prior_sigma;
  MapModule map(campus(), *camera, Pose2(80, 40, kPi), options);
  Blackboard board;
  for (int frame = 1; frame <= 22; ++frame) {
    const double t = frame;
    const Pose2 truth(80 - frame, 40, kPi);
    map.predict(board, t, MotionIncrement{1.02, 0.0});
    if (frame > 20 && fix_at_the_end) {
      const Prediction& prediction = map.prediction();
      DetectedObject seen;
      for (std::size_t i = 0; i < prediction.view.segments.size(); ++i) {
        DetectedLine l;
        l.label = prediction.view.segments[i].id;
        l.vehicle = {truth.inverseTransform(prediction.segments_world[i].a),
                     truth.inverseTransform(prediction.segments_world[i].b)};
        seen.lines.push_back(l);
      }
      seen.timestamp = t;
      board.post(Module::Vision, seen);
    }
    const CurrentPosition& p = map.localize(board, t);
    if (frame == 22 && fix_at_the_end && prior_sigma > 0) {
      EXPECT_EQ(p.status, PositionStatus::Corrected) << p.reason;
      EXPECT_TRUE(p.observed_along) << p.reason;
      EXPECT_NEAR(p.pose.x(), truth.x(), 0.01);
    }
    if (frame <= 20) {
      EXPECT_DOUBLE_EQ(map.odometryScale(), 1.0);  // nothing has observed along yet
    }
  }
  return map.odometryScale();
}

TEST(MissionModules, MapEstimatesTheOdometryScaleAtAnAlongRoadFix) {
  EXPECT_NEAR(scaleAfterADrive(true, 0.02), 0.9813, 0.0005);
  EXPECT_DOUBLE_EQ(scaleAfterADrive(false, 0.02), 1.0);  // no fix: the odometry as read
  EXPECT_DOUBLE_EQ(scaleAfterADrive(true, 0.0), 1.0);    // the scale not estimated
  MapModuleOptions bad;
  bad.filter.motion.scale_sigma = -0.01;
  try {
    bad.validate();
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("scale_sigma"), std::string::npos);
  }
}

TEST(MissionModules, VisionFailureHaltsMotionAndPassesControlToTheOperator) {
  int calls = 0;
  HaltPolicy policy;
  policy.resume_after_frames = 3;
  VisionModule vision(std::make_unique<ScriptedPipeline>(DetectedObject::failed("frame too dark"), &calls), policy);
  Blackboard board;
  std::vector<Posting> posted;
  board.onPost([&](const Posting& p) { posted.push_back(p); });
  PredictionToken p;
  p.view.timestamp = 2;
  p.view.regions.push_back(PredictedRegion{"R1", "straight road", "concrete", Vec3::Zero(), {}, {}});
  board.post(Module::Map, p);
  posted.clear();
  const std::uint8_t black[3] = {0, 0, 0};
  const DetectedObject& d = vision.see(board, VisionFrame{1, 1, black, nullptr, 2});
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(d.status, DetectedObject::Status::Failed);
  EXPECT_EQ(types(posted), (std::vector<TokenType>{TokenType::DetectedObject, TokenType::VisionFailure, TokenType::Halt}));
  const Halt* halt = board.halt(Module::Navigator);
  ASSERT_NE(halt, nullptr);
  EXPECT_EQ(halt->reason, "vision failed: frame too dark");
  EXPECT_EQ(halt->control_to, "operator");
  EXPECT_EQ(halt->resume_after_frames, std::optional<std::size_t>(3));
}

TEST(MissionModules, VisionIsNotAskedToFindAnEmptyPredictionNorAStaleOne) {
  int calls = 0;
  VisionModule vision(std::make_unique<ScriptedPipeline>(DetectedObject{}, &calls));
  Blackboard board;
  PredictionToken empty;
  empty.view.timestamp = 1;
  board.post(Module::Map, empty);
  const std::uint8_t pixel[3] = {0, 0, 0};
  EXPECT_EQ(vision.see(board, VisionFrame{1, 1, pixel, nullptr, 1}).status, DetectedObject::Status::Ok);
  EXPECT_EQ(calls, 0);
  EXPECT_EQ(board.halt(Module::Vision), nullptr);
  // A frame the Map predicted nothing for: a failure.
  EXPECT_EQ(vision.see(board, VisionFrame{1, 1, pixel, nullptr, 1.5}).status, DetectedObject::Status::Failed);
  EXPECT_NE(board.halt(Module::Vision), nullptr);
}

CurrentPosition at(const Pose2& pose, double t) {
  CurrentPosition p;
  p.pose = pose;
  p.timestamp = t;
  return p;
}

TEST(MissionModules, TheNavigatorPlansFromTheEstimateAndSpeaksTheDialogue) {
  NavigatorModule navigator(campus(), parseRoadPosition("R2@I1+30"), {parseRoadPosition("R4@I2+6")});
  EXPECT_NEAR(navigator.route().length_m, 16.0, 1e-6);
  Blackboard board;
  // The estimate is 0.3 m right of R2 (heading north, right is east): steer left, back to the route.
  board.post(Module::Map, at(Pose2(50.3, 70, kPi / 2), 0));
  const MotionCommand& c = navigator.plan(board, 0);
  EXPECT_EQ(c.kind, CommandKind::Drive);
  EXPECT_EQ(c.road, "R2");
  EXPECT_NEAR(c.drive_m, 10.0, 0.05);
  ASSERT_TRUE(c.next_turn);
  EXPECT_EQ(c.next_turn->at, "I2");
  EXPECT_EQ(turnDirection(c.next_turn->angle), "straight");
  EXPECT_GT(c.setpoint.turn_rate_rad_s, 0.05);
  EXPECT_TRUE(c.path_ends_at_goal);  // 16 m of route, 20 m of plan
  EXPECT_VEC2_NEAR(c.path.back(), Vec2(50, 86), 1e-6);
  EXPECT_FALSE(c.same_road);
  board.post(Module::Map, at(Pose2(50.0, 71, kPi / 2), 0.5));
  EXPECT_TRUE(navigator.plan(board, 0.5).same_road);  // "Drive on it ..."
  EXPECT_EQ(navigator.replans(), 0u);
}

TEST(MissionModules, TheNavigatorReplansOffTheRouteAndStopsWhileHalted) {
  NavigatorModule navigator(campus(), parseRoadPosition("R2@I1+30"), {parseRoadPosition("R4@I2+6")});
  Blackboard board;
  board.post(Module::Map, at(Pose2(50, 70, kPi / 2), 0));
  navigator.plan(board, 0);
  board.post(Module::Map, at(Pose2(53, 71, kPi / 2), 0.5));  // 3 m off the route: beyond its 2 m tolerance
  EXPECT_EQ(navigator.plan(board, 0.5).kind, CommandKind::Drive);
  EXPECT_EQ(navigator.replans(), 1u);
  Halt halt;
  halt.timestamp = 1;
  halt.reason = "vision failed: frame too dark";
  board.post(Module::Vision, halt);
  board.post(Module::Map, at(Pose2(50, 72, kPi / 2), 1));
  const MotionCommand& stop = navigator.plan(board, 1);
  EXPECT_EQ(stop.kind, CommandKind::Stop);
  EXPECT_NE(stop.reason.find("halted"), std::string::npos) << stop.reason;
  // No position (none posted for a long time): stop too.
  board.post(Module::User, Resume{2, 1});
  EXPECT_EQ(navigator.plan(board, 9).kind, CommandKind::Stop);
}

TEST(MissionModules, MotionControlDrivesThePlanToTheGoalAndStopsWhenItExpires) {
  VehicleLimits limits;
  BlackboardOptions options;
  options.command_validity_s = 30;
  Blackboard board(options);
  MotionCommand c;
  c.sequence = 1;
  c.path = {Vec2(0, 0), Vec2(1.5, 0)};
  c.path_ends_at_goal = true;
  c.speed_mps = 0.5;
  board.post(Module::Navigator, c);
  board.post(Module::Map, at(Pose2(0, 0.05, 0), 0));
  MotionControlModule motion(true, limits);
  ASSERT_NE(motion.receive(board, 0), nullptr);
  SkidSteerVehicle vehicle(Pose2(0, 0.05, 0), limits);
  double t = 0;
  for (int i = 0; i < 400 && !motion.arrived(); ++i, t += 0.05) vehicle.step(motion.control(board, t, 0.05), 0.05);
  EXPECT_TRUE(motion.arrived());
  EXPECT_VEC2_NEAR(vehicle.pose().translation(), Vec2(1.5, 0), 0.12);
  EXPECT_POSE_NEAR(motion.pose(), vehicle.pose(), 1e-9);  // the model is the vehicle's encoders

  // In replay Motion Control only records; a plan that is not renewed expires and stops it.
  BlackboardOptions short_lived;
  short_lived.command_validity_s = 0.5;
  Blackboard board2(short_lived);
  std::vector<Drop> dropped;
  board2.onDrop([&](const Drop& d) { dropped.push_back(d); });
  c.path_ends_at_goal = false;
  c.path = {Vec2(0, 0), Vec2(20, 0)};
  board2.post(Module::Navigator, c);
  board2.post(Module::Map, at(Pose2(), 0));
  MotionControlModule recorder(false, limits);
  EXPECT_FALSE(recorder.executing());
  MotionControlModule driver(true, limits);
  driver.receive(board2, 0);
  EXPECT_GT(driver.control(board2, 0.25, 0.05).speed_mps, 0.0);
  EXPECT_EQ(driver.control(board2, 0.75, 0.05).speed_mps, 0.0);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0].type, TokenType::MotionCommand);
}

}  // namespace
}  // namespace mapnav
