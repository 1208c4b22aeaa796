// Measuring the step between two frames from the ground on the simulator's frames: the
// landmark avenue's concrete between lawns with tree shadows, pairs of frames a step of 0.5-1.2 m
// and up to 3 degrees apart, the predicted motion off the truth by up to 3 % (twice the odometry's
// scale error) and 0.3 degrees; the measured distance against the true one.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/sim/world.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"
#include "sim_frame.h"
#include "mapnav/vision/ground_step.h"

namespace mapnav {
namespace {

using testing::visionFrame;

// The current vehicle's pose in the previous one's frame for a step of `d` m turning `dh` rad, as
// measureGroundStep reads a MotionIncrement: along the mid-step heading.
Pose2 stepPose(double d, double dh) { return Pose2(d * std::cos(0.5 * dh), d * std::sin(0.5 * dh), dh); }

TEST(GroundStep, DefaultOptionsAreValidAndABadFieldIsNamed) {
  EXPECT_NO_THROW(GroundStepOptions{}.validate());
  GroundStepOptions o;
  o.far_m = o.near_m;
  EXPECT_THROW(
      {
        try {
          o.validate();
        } catch (const InvalidInput& e) {
          EXPECT_NE(std::string(e.what()).find("far_m"), std::string::npos) << e.what();
          throw;
        }
      },
      InvalidInput);
  o = GroundStepOptions{};
  o.cell_m = 0.001;  // 4000 cells along
  EXPECT_THROW(o.validate(), InvalidInput);
}

class GroundStepOnTheAvenue : public ::testing::Test {
 protected:
  void SetUp() override {
    camera_ = loadCamera(testing::mapPath("cameras/terregator_pinhole.json"));
    WorldOptions o;
    o.seed = 7;
    o.shadow_density = 0.3;
    world_ = std::make_unique<World>(map_, o);
  }
  const Map map_{testing::landmarkAvenue(true)};
  std::unique_ptr<Camera> camera_;
  std::unique_ptr<World> world_;
};

TEST_F(GroundStepOnTheAvenue, MeasuredStepsAreWithinThreeSigmaOfTheTruth) {
  std::mt19937_64 rng(28);
  std::uniform_real_distribution<double> along(5, 200), across(-0.4, 0.4), heading(-degToRad(4), degToRad(4)),
      step(0.5, 1.2), turn(-degToRad(3), degToRad(3)), scale(-0.03, 0.03), gyro(-degToRad(0.3), degToRad(0.3));
  const int pairs = testing::kUnderSanitizers ? 40 : 100;  // the sanitizer stage: the same code on fewer frames
  int found = 0, within_3_sigma = 0;
  std::vector<double> errors, predicted_errors, peaks;
  for (int k = 0; k < pairs; ++k) {
    const Pose2 before(along(rng), across(rng), heading(rng));
    const double d = step(rng), dh = turn(rng);
    const Pose2 after = before * stepPose(d, dh);
    const Frame a = world_->render(*camera_, before, 2.0 * k), b = world_->render(*camera_, after, 2.0 * k + 1);
    const MotionIncrement predicted{d * (1 + scale(rng)), dh + gyro(rng)};
    const MeasuredStep m = measureGroundStep(visionFrame(a, *camera_), visionFrame(b, *camera_), predicted);
    predicted_errors.push_back(std::abs(predicted.distance_m - d));
    peaks.push_back(m.peak);
    if (!m.found) {
      std::printf("pair %d not found: %s\n", k, m.reason.c_str());
      continue;
    }
    ++found;
    errors.push_back(std::abs(m.distance_m - d));
    within_3_sigma += std::abs(m.distance_m - d) <= 3 * m.sigma_m ? 1 : 0;
  }
  std::sort(errors.begin(), errors.end());
  std::sort(predicted_errors.begin(), predicted_errors.end());
  std::sort(peaks.begin(), peaks.end());
  const double median = errors.empty() ? 1e9 : errors[errors.size() / 2];
  std::printf("%d of %d steps measured; error median %.4f m, 95th percentile %.4f m, max %.4f m (the prediction's: "
              "median %.4f m); %d within 3 sigma; peaks %.3f-%.3f, median %.3f\n",
              found, pairs, median, errors.empty() ? 1e9 : errors[errors.size() * 95 / 100],
              errors.empty() ? 1e9 : errors.back(), predicted_errors[predicted_errors.size() / 2], within_3_sigma, peaks.front(), peaks.back(),
              peaks[peaks.size() / 2]);
  EXPECT_GE(found, pairs * 9 / 10);
  EXPECT_GE(within_3_sigma, found * 95 / 100);
  EXPECT_LE(median, 0.25 * predicted_errors[predicted_errors.size() / 2]);
}

TEST_F(GroundStepOnTheAvenue, AUniformGroundDoesNotRegisterAndAWrongPredictionIsBeyondTheResidual) {
  const Pose2 before(50, 0, 0);
  const Pose2 after = before * stepPose(0.8, 0);
  const Frame a = world_->render(*camera_, before, 0), b = world_->render(*camera_, after, 1);
  // The predicted motion 0.5 m short: the ground registers 0.5 m further, beyond 0.25 m.
  const MeasuredStep short_by_half = measureGroundStep(visionFrame(a, *camera_), visionFrame(b, *camera_), {0.3, 0});
  EXPECT_FALSE(short_by_half.found);
  EXPECT_NE(short_by_half.reason.find("beyond"), std::string::npos) << short_by_half.reason;
  // Grey frames: nothing to register.
  Frame grey = a;
  std::fill(grey.rgb.data.begin(), grey.rgb.data.end(), std::uint8_t{128});
  const MeasuredStep flat = measureGroundStep(visionFrame(grey, *camera_), visionFrame(grey, *camera_), {0.8, 0});
  EXPECT_FALSE(flat.found);
  EXPECT_NE(flat.reason.find("no texture"), std::string::npos) << flat.reason;
  // Stripes along the road (a kerb's, a lawn edge's) and sensor noise: they fix the step across the
  // road but not along it, a ridge in the correlation, not a peak.
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0, 2.0);
  auto stripes = [&](const Pose2& pose) {
    Frame f = a;
    for (int v = 0; v < f.rgb.height; ++v) {
      for (int u = 0; u < f.rgb.width; ++u) {
        const auto g = camera_->backproject(Vec2(u, v));
        const double y = g ? pose.transform(*g).y() : 0.0;
        const double level = 128 + 40 * std::sin(2 * M_PI * y / 0.7) + 20 * std::sin(2 * M_PI * y / 0.23);
        for (int c = 0; c < 3; ++c) {
          f.rgb.data[(static_cast<std::size_t>(v) * f.rgb.width + u) * 3 + c] =
              static_cast<std::uint8_t>(std::clamp(level + noise(rng), 0.0, 255.0));
        }
      }
    }
    return f;
  };
  const Frame sa = stripes(before), sb = stripes(after);
  const MeasuredStep ridge = measureGroundStep(visionFrame(sa, *camera_), visionFrame(sb, *camera_), {0.8, 0});
  EXPECT_FALSE(ridge.found) << ridge.distance_m;
  EXPECT_NE(ridge.reason.find("did not register"), std::string::npos) << ridge.reason;
  // A car's camera (KITTI's, 1.66 m up, looking ahead) sees the ground from 7 m on, too shallow.
  const auto car = loadCamera(testing::mapPath("cameras/kitti_raw_2011_09_26_cam02.json"));
  Frame car_frame;
  car_frame.rgb = Image(car->width(), car->height(), 3);
  const MeasuredStep shallow = measureGroundStep(visionFrame(car_frame, *car), visionFrame(car_frame, *car), {1.2, 0});
  EXPECT_FALSE(shallow.found);
  EXPECT_NE(shallow.reason.find("too shallow"), std::string::npos) << shallow.reason;
  // A frame without its camera is the caller's error.
  VisionFrame no_camera = visionFrame(a, *camera_);
  no_camera.camera = nullptr;
  EXPECT_THROW(measureGroundStep(no_camera, visionFrame(b, *camera_), {0.8, 0}), InvalidInput);
}

}  // namespace
}  // namespace mapnav
