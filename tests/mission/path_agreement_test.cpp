// Path agreement (mapnav/mission/path_agreement.h): the future path from the truth poses, the fraction
// of it inside a road found, the angle and offset of a centre line, and the run's summary, on cases
// whose answers are worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "mapnav/core/error.h"
#include "mapnav/vision_iface/pipeline.h"
#include "mapnav/mission/path_agreement.h"
#include "mapnav/mission/track.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

/// A level pin-hole 1.5 m up at the vehicle's origin, 640 x 480, principal point at the centre:
/// ground point (x, y) → u = 319.5 − f·y/x, v = 239.5 + 1.5·f/x. With f = 100 the ground from 0.63 m
/// on is in view (every sample of a 2–15 m path); with f = 500, from 3.125 m on.
std::unique_ptr<Camera> levelCamera(double f) {
  return createCamera(LensModel::Pinhole, CameraIntrinsics{640, 480, f, f, 319.5, 239.5, {}},
                      CameraMount{Vec2::Zero(), 1.5, 0.0, 0.0, 0.0});
}

/// Frames whose truth poses are `poses`, in order.
std::vector<LogFrame> framesAt(const std::vector<Pose2>& poses) {
  std::vector<LogFrame> frames(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) frames[i].truth = poses[i];
  return frames;
}

/// `n` poses 1 m apart along the world direction `heading` from `start`, each facing that way.
std::vector<Pose2> straightDrive(const Vec2& start, double heading, std::size_t n) {
  std::vector<Pose2> poses;
  for (std::size_t i = 0; i < n; ++i) poses.emplace_back(start + static_cast<double>(i) * unitVector(heading), heading);
  return poses;
}

/// A detection whose road is the ground rectangle x in [x0, x1], y in [y0, y1], on the ground only.
DetectedObject groundRectangle(double x0, double x1, double y0, double y1) {
  DetectedObject d;
  d.region_vehicle = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  return d;
}

TEST(FuturePath, SamplesEveryQuarterMetreFrom2To15MetresInTheVehicleFrame) {
  // Driving 30° north of east from (10, 5): in each frame's vehicle frame the path runs straight ahead.
  const auto frames = framesAt(straightDrive({10, 5}, degToRad(30), 21));
  const std::vector<Vec2> path = futurePath(frames, 3);
  ASSERT_EQ(path.size(), 53u);  // (15 − 2) / 0.25 + 1
  for (std::size_t k = 0; k < path.size(); ++k) EXPECT_VEC2_NEAR(path[k], Vec2(2 + 0.25 * static_cast<double>(k), 0), 1e-9);
}

TEST(FuturePath, FollowsTheArcLengthAroundATurn) {
  // 4 m ahead, then 16 m to the left while still facing east: arc length 6 m is (4, 2).
  std::vector<Pose2> poses = {Pose2(0, 0, 0), Pose2(2, 0, 0), Pose2(4, 0, 0)};
  for (int k = 1; k <= 8; ++k) poses.emplace_back(4, 2.0 * k, 0);
  const std::vector<Vec2> path = futurePath(framesAt(poses), 0);
  ASSERT_EQ(path.size(), 53u);
  EXPECT_VEC2_NEAR(path[0], Vec2(2, 0), 1e-9);
  EXPECT_VEC2_NEAR(path[8], Vec2(4, 0), 1e-9);    // 4 m
  EXPECT_VEC2_NEAR(path[16], Vec2(4, 2), 1e-9);   // 6 m
  EXPECT_VEC2_NEAR(path[52], Vec2(4, 11), 1e-9);  // 15 m
}

TEST(FuturePath, AShortPathIsCutOrLeftOut) {
  const auto frames = framesAt(straightDrive({0, 0}, 0, 9));  // the last frame 8 m ahead of the first
  const std::vector<Vec2> to8 = futurePath(frames, 0);
  ASSERT_EQ(to8.size(), 25u);  // 2 .. 8 m
  EXPECT_VEC2_NEAR(to8.back(), Vec2(8, 0), 1e-9);
  EXPECT_EQ(futurePath(frames, 1).size(), 21u);  // 7 m left: 2 .. 7 m, the least measured
  EXPECT_TRUE(futurePath(frames, 2).empty());    // 6 m left
  EXPECT_TRUE(futurePath(frames, 8).empty());    // the last frame: no path at all
  // A frame without truth ends the path; one without truth has none.
  auto gap = frames;
  gap[5].truth.reset();
  EXPECT_TRUE(futurePath(gap, 0).empty());  // 4 m, to frame 4
  EXPECT_TRUE(futurePath(gap, 5).empty());
  const PathAgreement none = pathAgreement(gap, 5, DetectedObject{}, *levelCamera(100));
  EXPECT_EQ(none.status, PathStatus::NoTruth);
  EXPECT_FALSE(none.inside_fraction);
  EXPECT_EQ(pathAgreement(gap, 0, DetectedObject{}, *levelCamera(100)).status, PathStatus::TooShort);
}

TEST(PathAgreement, InsideFractionCountsTheSamplesInTheRoadFound) {
  const auto frames = framesAt(straightDrive({0, 0}, 0, 20));
  const auto camera = levelCamera(100);
  // The road found ends at 8.6 m: samples 2, 2.25, ..., 8.5 m are inside, 27 of 53.
  const DetectedObject ground = groundRectangle(1, 8.6, -1, 1);
  const PathAgreement a = pathAgreement(frames, 0, ground, *camera);
  EXPECT_EQ(a.status, PathStatus::Measured);
  EXPECT_EQ(a.out_of_view, 0u);
  EXPECT_EQ(a.path_image.size(), 53u);
  EXPECT_EQ(a.inside, 27u);
  ASSERT_TRUE(a.inside_fraction);
  EXPECT_DOUBLE_EQ(*a.inside_fraction, 27.0 / 53.0);
  EXPECT_TRUE(a.road_found);
  EXPECT_FALSE(a.centre_line);
  // The first sample, 2 m ahead on the axis, at (319.5, 239.5 + 150 / 2).
  EXPECT_VEC2_NEAR(a.path_image.front(), Vec2(319.5, 314.5), 1e-9);

  // The same rectangle given in pixels (its corners projected: a pin-hole images the ground's
  // straight sides as straight lines) gives the same answer.
  DetectedObject pixels;
  for (const Vec2& g : ground.region_vehicle) pixels.region_image.push_back(*camera->projectGround(g));
  EXPECT_EQ(pathAgreement(frames, 0, pixels, *camera).inside, 27u);

  // A road that covers the path's left half only (y from 0 up) holds every sample, since the
  // boundary counts as inside; one just right of the path holds none.
  EXPECT_EQ(pathAgreement(frames, 0, groundRectangle(1, 20, 0, 1), *camera).inside, 53u);
  EXPECT_EQ(pathAgreement(frames, 0, groundRectangle(1, 20, -1, -0.01), *camera).inside, 0u);

  // Drifting 0.2 m left a metre: sample s is at y = 0.2 s / √1.04, so a road from y = 1.5 m left
  // holds the samples from s = 7.65 m on: 7.75 .. 15 m, 30 of 53.
  std::vector<Pose2> drift;
  for (int k = 0; k < 20; ++k) drift.emplace_back(k, 0.2 * k, 0);
  EXPECT_EQ(pathAgreement(framesAt(drift), 0, groundRectangle(0, 30, 1.5, 10), *camera).inside, 30u);
}

TEST(PathAgreement, SamplesOutOfViewAreLeftOutAndCounted) {
  const auto frames = framesAt(straightDrive({0, 0}, 0, 20));
  // f = 500: the bottom row (v = 479.5) sees 3.125 m ahead, so 2, 2.25, ..., 3 m are below the image:
  // 5 left out, 48 in view, of which 3.25 .. 8.5 m (22) are inside.
  const PathAgreement a = pathAgreement(frames, 0, groundRectangle(1, 8.6, -1, 1), *levelCamera(500));
  EXPECT_EQ(a.out_of_view, 5u);
  EXPECT_EQ(a.path_image.size(), 48u);
  EXPECT_EQ(a.inside, 22u);
  EXPECT_DOUBLE_EQ(*a.inside_fraction, 22.0 / 48.0);
  // A camera looking 80° up sees no ground at all.
  const auto up = createCamera(LensModel::Pinhole, CameraIntrinsics{640, 480, 500, 500, 319.5, 239.5, {}},
                               CameraMount{Vec2::Zero(), 1.5, degToRad(-80), 0.0, 0.0});
  const PathAgreement blind = pathAgreement(frames, 0, groundRectangle(1, 8.6, -1, 1), *up);
  EXPECT_EQ(blind.status, PathStatus::OutOfView);
  EXPECT_EQ(blind.out_of_view, 53u);
  EXPECT_FALSE(blind.inside_fraction);
}

TEST(PathAgreement, AFailedDetectionOrNoRegionIsZeroInside) {
  const auto frames = framesAt(straightDrive({0, 0}, 0, 20));
  DetectedObject failed = DetectedObject::failed("no road-coloured pixels");
  failed.region_vehicle = groundRectangle(1, 20, -1, 1).region_vehicle;  // ignored: the pipeline failed
  const PathAgreement a = pathAgreement(frames, 0, failed, *levelCamera(100));
  EXPECT_EQ(a.status, PathStatus::Measured);
  EXPECT_FALSE(a.road_found);
  EXPECT_EQ(*a.inside_fraction, 0.0);
  EXPECT_EQ(pathAgreement(frames, 0, DetectedObject{}, *levelCamera(100)).inside_fraction, 0.0);
}

// The ground share, on the lattice of every 4th pixel of every 4th row from (2, 2): the level
// camera (cy = 239.5) sees the ground from row 242 down, 60 lattice rows of 160 points. The whole
// image holds the path and covers all of it (the trivial region); its left half (u < 319.5: 80
// columns) covers half; a failed detection 0; a region only on the ground (no region_image) none.
TEST(PathAgreement, GroundShareSaysHowMuchOfTheViewTheRoadFoundTakes) {
  const auto frames = framesAt(straightDrive({0, 0}, 0, 20));
  const auto camera = levelCamera(100);
  DetectedObject all, left;
  all.region_image = {{-0.5, -0.5}, {639.5, -0.5}, {639.5, 479.5}, {-0.5, 479.5}};
  left.region_image = {{-0.5, -0.5}, {319.5, -0.5}, {319.5, 479.5}, {-0.5, 479.5}};
  const PathAgreement a = pathAgreement(frames, 0, all, *camera);
  EXPECT_EQ(*a.inside_fraction, 1.0);
  EXPECT_EQ(*a.ground_share, 1.0);
  EXPECT_EQ(*pathAgreement(frames, 0, left, *camera).ground_share, 0.5);
  EXPECT_EQ(*pathAgreement(frames, 0, DetectedObject::failed("x"), *camera).ground_share, 0.0);
  EXPECT_FALSE(pathAgreement(frames, 0, groundRectangle(1, 8.6, -1, 1), *camera).ground_share);
  std::vector<PathAgreement> run{a, pathAgreement(frames, 0, left, *camera), pathAgreement(frames, 0, left, *camera)};
  EXPECT_EQ(*summarizePathAgreement(run).median_ground_share, 0.5);
}

TEST(PathAgreement, CentreLineAngleAndOffsetToThePath) {
  const auto camera = levelCamera(100);
  // Straight ahead; the centre line rises 0.1 m a metre, through (5, 0.5): atan(0.1) off the path,
  // and at x = 7.5 it is at y = 0.75, so the path runs 0.75 m right of it.
  const auto ahead = framesAt(straightDrive({0, 0}, 0, 20));
  DetectedObject d;
  d.centerline_vehicle = Segment2{{5, 0.5}, {10, 1.0}};
  const PathAgreement a = pathAgreement(ahead, 0, d, *camera);
  EXPECT_TRUE(a.centre_line);
  ASSERT_TRUE(a.path_direction);
  EXPECT_VEC2_NEAR(*a.path_direction, Vec2(1, 0), 1e-12);
  ASSERT_TRUE(a.angle_deg);
  EXPECT_NEAR(*a.angle_deg, radToDeg(std::atan(0.1)), 1e-9);  // 5.71°
  ASSERT_TRUE(a.offset_m);
  EXPECT_NEAR(*a.offset_m, -0.75, 1e-12);
  // The line's ends the other way round: the same angle and offset.
  d.centerline_vehicle = Segment2{{10, 1.0}, {5, 0.5}};
  EXPECT_NEAR(*pathAgreement(ahead, 0, d, *camera).angle_deg, radToDeg(std::atan(0.1)), 1e-9);
  EXPECT_NEAR(*pathAgreement(ahead, 0, d, *camera).offset_m, -0.75, 1e-12);

  // Facing east but drifting 0.2 m left a metre (the poses' positions along (1, 0.2)), against a
  // centre line straight ahead on the axis: atan(0.2) apart, and at x = 7.5 the path is 1.5 m left.
  std::vector<Pose2> drift;
  for (int k = 0; k < 20; ++k) drift.emplace_back(k, 0.2 * k, 0);
  d.centerline_vehicle = Segment2{{0, 0}, {20, 0}};
  const PathAgreement b = pathAgreement(framesAt(drift), 0, d, *camera);
  EXPECT_VEC2_NEAR(*b.path_direction, Vec2(1, 0.2).normalized(), 1e-12);
  EXPECT_NEAR(*b.angle_deg, radToDeg(std::atan(0.2)), 1e-9);  // 11.31°
  EXPECT_NEAR(*b.path_y_ahead, 1.5, 1e-12);
  EXPECT_NEAR(*b.offset_m, 1.5, 1e-12);

  // A path that ends at 8 m gives an offset (it reaches x = 7.5) but no direction over 5-10 m.
  const PathAgreement c = pathAgreement(framesAt(straightDrive({0, 0}, 0, 9)), 0, d, *camera);
  EXPECT_FALSE(c.path_direction);
  EXPECT_FALSE(c.angle_deg);
  EXPECT_NEAR(*c.offset_m, 0.0, 1e-12);
}

/// A measured frame with a path direction and an offset look-ahead; `inside` its fraction, a
/// centre line when `angle` is given.
PathAgreement measuredFrame(double inside, std::optional<double> angle, std::optional<double> offset) {
  PathAgreement f;
  f.inside_fraction = inside;
  f.road_found = inside > 0;
  f.path_direction = Vec2(1, 0);
  f.path_y_ahead = 0.0;
  f.centre_line = angle.has_value();
  f.angle_deg = angle;
  f.offset_m = offset;
  return f;
}

TEST(PathAgreementSummary, CountsFailuresAgainstTheGoalsAndSaysWhatWasNotMeasured) {
  std::vector<PathAgreement> frames = {measuredFrame(1.0, 1.0, 0.10), measuredFrame(0.96, 2.0, 0.20),
                                       measuredFrame(0.0, std::nullopt, std::nullopt),  // the pipeline failed
                                       measuredFrame(0.5, 5.0, 0.30), measuredFrame(0.99, 0.5, 0.90)};
  frames.emplace_back().status = PathStatus::TooShort;
  frames.emplace_back().status = PathStatus::NoTruth;
  EXPECT_NEAR(*offsetJump(frames, 1), 0.1, 1e-12);
  EXPECT_FALSE(offsetJump(frames, 2));
  EXPECT_NEAR(*offsetJump(frames, 4), 0.6, 1e-12);

  const PathAgreementSummary s = summarizePathAgreement(frames);
  EXPECT_EQ(s.frames, 7u);
  EXPECT_EQ(s.measured, 5u);
  EXPECT_EQ(s.no_truth, 1u);
  EXPECT_EQ(s.path_too_short, 1u);
  EXPECT_EQ(s.out_of_view, 0u);
  EXPECT_EQ(s.no_region, 1u);
  // Inside: 0, 0.5, 0.96, 0.99, 1 → median 0.96; three of five at 0.95 or more.
  EXPECT_DOUBLE_EQ(*s.median_inside, 0.96);
  EXPECT_EQ(s.inside_goal_frames, 3u);
  EXPECT_DOUBLE_EQ(*s.inside_goal_fraction, 0.6);
  // Angles 0.5, 1, 2, 5 (nearest-rank median 1) and one frame without a centre line: 3 of 5 within 3°.
  EXPECT_EQ(s.centre_line_frames, 4u);
  EXPECT_EQ(s.angle_frames, 5u);
  EXPECT_EQ(s.angle_missing, 1u);
  EXPECT_DOUBLE_EQ(*s.median_angle_deg, 1.0);
  EXPECT_EQ(s.angle_goal_frames, 3u);
  EXPECT_DOUBLE_EQ(*s.angle_goal_fraction, 0.6);
  // Pairs 0-1 (0.1 m), 1-2 and 2-3 (no offset in frame 2), 3-4 (0.6 m); 4-5 is not measured.
  EXPECT_EQ(s.offset_pairs, 4u);
  EXPECT_EQ(s.offset_missing, 2u);
  EXPECT_NEAR(*s.median_offset_jump_m, 0.1, 1e-12);
  EXPECT_EQ(s.offset_goal_pairs, 1u);
  EXPECT_DOUBLE_EQ(*s.offset_goal_fraction, 0.25);
}

TEST(PathAgreementSummary, NoCentreLineGivesNoAngleOrOffsetFigures) {
  const std::vector<PathAgreement> frames = {measuredFrame(1.0, std::nullopt, std::nullopt),
                                             measuredFrame(0.9, std::nullopt, std::nullopt)};
  const PathAgreementSummary s = summarizePathAgreement(frames);
  EXPECT_EQ(s.centre_line_frames, 0u);
  EXPECT_DOUBLE_EQ(*s.inside_goal_fraction, 0.5);
  EXPECT_EQ(s.angle_frames, 2u);
  EXPECT_FALSE(s.angle_goal_fraction);
  EXPECT_FALSE(s.median_angle_deg);
  EXPECT_FALSE(s.offset_goal_fraction);
  EXPECT_FALSE(summarizePathAgreement({}).median_inside);
}

TEST(PathAgreementOptions, DefaultsAreValidAndABadFieldIsNamed) {
  EXPECT_NO_THROW(PathAgreementOptions{}.validate());
  PathAgreementOptions o;
  o.step_m = 0;
  try {
    o.validate();
    FAIL() << "step_m = 0 passed";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("PathAgreementOptions::step_m = 0"), std::string::npos) << e.what();
  }
  o = {};
  o.direction_far_m = 20;  // beyond far_m
  EXPECT_THROW(o.validate(), InvalidInput);
}

TEST(PathAgreementOptions, TheRulesBetweenFieldsComeAfterTheFieldsOwn) {
  const auto rejection = [](const PathAgreementOptions& o) -> std::string {
    try {
      o.validate();
    } catch (const InvalidInput& e) {
      return e.what();
    }
    return "";
  };
  PathAgreementOptions o;
  o.far_m = 2;
  EXPECT_EQ(rejection(o), "PathAgreementOptions::far_m = 2: must be > near_m");
  o.step_m = -1;  // its own rule is named first
  EXPECT_EQ(rejection(o), "PathAgreementOptions::step_m = -1: must be finite and > 0");
  o = {};
  o.min_reach_m = 16;
  EXPECT_EQ(rejection(o), "PathAgreementOptions::min_reach_m = 16: must be in [near_m, far_m]");
  o = {};
  o.direction_near_m = 1;
  EXPECT_EQ(rejection(o), "PathAgreementOptions::direction_near_m = 1: must be >= near_m");
  o = {};
  o.direction_far_m = 20;
  EXPECT_EQ(rejection(o), "PathAgreementOptions::direction_far_m = 20: must be in (direction_near_m, far_m]");
  o = {};
  o.far_m = std::numeric_limits<double>::infinity();
  EXPECT_EQ(rejection(o), "PathAgreementOptions::far_m = inf: must be finite");
  o = {};
  o.angle_goal_deg = 91;
  EXPECT_EQ(rejection(o), "PathAgreementOptions::angle_goal_deg = 91: must be in [0, 90]");
}

/// A pipeline that finds the same ground rectangle in every frame.
class FixedRoad : public VisionPipeline {
 public:
  std::string name() const override { return "fixed-road"; }
  void configure(const std::string&) override {}
  DetectedObject detect(const VisionFrame& frame, const PredictedObject&) override {
    DetectedObject d = groundRectangle(1, 8.6, -1, 1);
    d.timestamp = frame.timestamp;
    return d;
  }
  void reset() override {}
};

// The lane bootstrap of `log track` on a level pin-hole 1.5 m up, 640 x 500, f = 500, principal point
// (319.5, 240): ground (x, y) → u = 319.5 − 500·y/x, v = 240 + 750/x. Row 0.98 · 500 = 490 sees the
// ground 750 / 250 = 3 m ahead; a 3 m lane's corners there are 500 · 1.5 / 3 = 250 px either side of
// the centre, at 30 m 25 px either side on row 265.
TEST(LaneOutline, ProjectsTheVehiclesLaneFromTheNearestGroundInView) {
  const auto camera = createCamera(LensModel::Pinhole, CameraIntrinsics{640, 500, 500, 500, 319.5, 240, {}},
                                   CameraMount{Vec2::Zero(), 1.5, 0.0, 0.0, 0.0});
  const Polygon2 lane = laneOutline(*camera, 3.0, 30.0);
  ASSERT_EQ(lane.size(), 4u);
  EXPECT_NEAR(lane[0].x(), 69.5, 1e-9);  // bottom left
  EXPECT_NEAR(lane[0].y(), 490, 1e-9);
  EXPECT_NEAR(lane[1].x(), 569.5, 1e-9);  // bottom right
  EXPECT_NEAR(lane[1].y(), 490, 1e-9);
  EXPECT_NEAR(lane[2].x(), 344.5, 1e-9);  // top right
  EXPECT_NEAR(lane[2].y(), 265, 1e-9);
  EXPECT_NEAR(lane[3].x(), 294.5, 1e-9);  // top left
  EXPECT_NEAR(lane[3].y(), 265, 1e-9);
  try {
    laneOutline(*camera, 3.0, 2.0);
    ADD_FAILURE() << "a lane ending before the nearest ground in view was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_STREQ(e.what(), "the lane: the far end 2 m is not beyond the nearest ground in view, 3.00 m ahead");
  }
  EXPECT_THROW(laneOutline(*camera, 0.0, 30.0), InvalidInput);
  EXPECT_THROW(laneOutline(*camera, 3.0, std::nan("")), InvalidInput);
  // A camera looking 30 degrees up does not see the ground at its bottom row.
  const auto up = createCamera(LensModel::Pinhole, CameraIntrinsics{640, 500, 500, 500, 319.5, 240, {}},
                               CameraMount{Vec2::Zero(), 1.5, degToRad(-30), 0.0, 0.0});
  EXPECT_THROW(laneOutline(*up, 3.0, 30.0), InvalidInput);
}

TEST(TrackLogPath, EachFrameIsHeldAgainstTheLogsTruthAhead) {
  // 20 frames 1 m apart straight ahead, blank images: frame i's path reaches 19 − i m.
  const std::filesystem::path dir = testing::freshTempDir() / "log";
  std::shared_ptr<const Camera> camera = levelCamera(100);
  {
    ReplayLogWriter writer(dir, LogHeader{"straight", camera, "", 10.0});
    for (int i = 0; i < 20; ++i) {
      LogFrame f;
      f.t = 0.1 * i;
      f.odometry.distance_m = i == 0 ? 0.0 : 1.0;
      f.truth = Pose2(i, 0, 0);
      writer.add(f, Image(640, 480, 1));
    }
    writer.finish();
  }
  const ReplayLog log = ReplayLog::open(dir);
  FixedRoad pipeline;
  const Polygon2 bootstrap = {{100, 470}, {540, 470}, {400, 300}, {240, 300}};
  std::vector<std::size_t> drawn;  // the path samples the observer got, per frame
  const TrackObserver observe = [&](const Image&, const PredictedObject&, const DetectedObject&, const TrackedFrame& t) {
    drawn.push_back(t.path.path.size());
  };
  // Six frames run, but the path of frame 5 still reaches 14 m into the frames not run.
  const TrackRun six = trackLog(log, pipeline, *camera, bootstrap, TrackOptions{-1, 6, {}}, observe);
  ASSERT_EQ(six.frames.size(), 6u);
  EXPECT_EQ(drawn, (std::vector<std::size_t>{53, 53, 53, 53, 53, 49}));
  EXPECT_DOUBLE_EQ(*six.frames[0].path.inside_fraction, 27.0 / 53.0);  // 2 .. 8.5 m of 2 .. 15 m
  EXPECT_DOUBLE_EQ(*six.frames[5].path.inside_fraction, 27.0 / 49.0);  // of 2 .. 14 m
  try {  // a row below the camera's image: a rule between the options and the camera
    trackLog(log, pipeline, *camera, bootstrap, TrackOptions{480, 1, {}});
    ADD_FAILURE() << "row 480 of a 480-row image was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_STREQ(e.what(), "trackLog: options.row = 480: must be at most the camera image's last row, 479");
  }
  try {  // between the sentinel -1 and the first row: the table's rule
    trackLog(log, pipeline, *camera, bootstrap, TrackOptions{-0.5, 1, {}});
    ADD_FAILURE() << "row -0.5 was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_STREQ(e.what(), "TrackOptions::row = -0.5: must be -1 or >= 0");
  }

  // The whole log: frames 13 to 19 have less than 7 m ahead.
  const TrackRun all = trackLog(log, pipeline, *camera, bootstrap);
  const PathAgreementSummary s = all.pathAgreement();
  EXPECT_EQ(s.frames, 20u);
  EXPECT_EQ(s.measured, 13u);
  EXPECT_EQ(s.path_too_short, 7u);
  EXPECT_EQ(all.frames[13].path.status, PathStatus::TooShort);
  // Only frames 11 and 12, whose paths end within the road found (at 8 and 7 m), hold 95 % of it.
  EXPECT_EQ(s.inside_goal_frames, 2u);
  EXPECT_DOUBLE_EQ(*all.frames[10].path.inside_fraction, 27.0 / 29.0);
  EXPECT_EQ(s.centre_line_frames, 0u);
  EXPECT_FALSE(s.angle_goal_fraction);
}

}  // namespace
}  // namespace mapnav
