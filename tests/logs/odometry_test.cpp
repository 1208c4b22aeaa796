#include "mapnav/logs/odometry.h"

#include <gtest/gtest.h>

#include <cmath>

#include "mapnav/core/error.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

TEST(OdometrySensor, WithoutNoiseReportsTheTrueMotion) {
  OdometrySensor sensor(OdometryNoiseOptions{});
  const MotionIncrement o = sensor.measure(0.75, 0.1, 0.5);
  EXPECT_EQ(o.distance_m, 0.75);
  EXPECT_EQ(o.dheading_rad, 0.1);
}

TEST(OdometrySensor, ScaleErrorAndGyroBiasAreSystematic) {
  OdometryNoiseOptions options;
  options.scale_error = 0.02;
  options.gyro_bias_deg_s = 0.5;
  OdometrySensor sensor(options);
  const MotionIncrement o = sensor.measure(10.0, 0.0, 4.0);
  EXPECT_NEAR(o.distance_m, 10.2, 1e-12);
  EXPECT_NEAR(o.dheading_rad, degToRad(2.0), 1e-12);  // 0.5 deg/s for 4 s
}

TEST(OdometrySensor, NoiseHasTheStatedSpreadAndTheSameSeedRepeatsIt) {
  OdometryNoiseOptions options;
  options.seed = 42;
  options.distance_sigma_m = 0.01;
  options.heading_sigma_deg = 0.2;
  OdometrySensor a(options), b(options);
  double sum = 0, sum2 = 0, hsum2 = 0;
  constexpr int n = 20000;
  for (int i = 0; i < n; ++i) {
    const MotionIncrement x = a.measure(1.0, 0.0, 0.1), y = b.measure(1.0, 0.0, 0.1);
    ASSERT_EQ(x, y);
    sum += x.distance_m - 1.0;
    sum2 += (x.distance_m - 1.0) * (x.distance_m - 1.0);
    hsum2 += x.dheading_rad * x.dheading_rad;
  }
  EXPECT_NEAR(sum / n, 0.0, 3 * 0.01 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.01, 0.0005);
  EXPECT_NEAR(std::sqrt(hsum2 / n), degToRad(0.2), degToRad(0.01));
  options.seed = 43;
  OdometrySensor c(options);
  OdometryNoiseOptions same = options;
  same.seed = 42;
  OdometrySensor d(same);
  EXPECT_NE(c.measure(1.0, 0.0, 0.1), d.measure(1.0, 0.0, 0.1));
}

TEST(OdometryNoiseOptions, DefaultsAreValidAndTheMissionBlockIsChecked) {
  EXPECT_NO_THROW(OdometryNoiseOptions{}.validate());
  Issues issues;
  const auto o = parseOdometryNoise(R"({"seed": 7, "scale_error": 0.01, "gyro_bias": 1})", "/odometry", issues);
  EXPECT_EQ(o.seed, 7u);
  EXPECT_EQ(o.scale_error, 0.01);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].check, "schema.unknown_field");
  EXPECT_EQ(issues[0].where, "/odometry/gyro_bias");
}

TEST(OdometryNoiseOptions, TheMissionBlockAndValidateHaveOneRuleSet) {
  Issues issues;
  parseOdometryNoise(R"({"scale_error": 0.495, "gyro_bias_deg_s": 20, "x-why": "a note"})", "/odometry", issues);
  ASSERT_EQ(issues.size(), 2u);  // in the block's order
  EXPECT_EQ(issues[0], (Issue{Severity::Error, "schema.range", "/odometry/scale_error",
                              "option scale_error = 0.495: must be in [-0.49, 0.49]"}));
  EXPECT_EQ(issues[1], (Issue{Severity::Error, "schema.range", "/odometry/gyro_bias_deg_s",
                              "option gyro_bias_deg_s = 20: must be in [-10, 10]"}));
  OdometryNoiseOptions o;
  o.gyro_bias_deg_s = 20;  // validate() took any finite bias
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { o.validate(); },
                                                "OdometryNoiseOptions::gyro_bias_deg_s = 20: must be in [-10, 10]"));
  o = {};
  o.scale_error = -0.495;  // ... and any |scale_error| < 0.5
  EXPECT_THROW(OdometrySensor{o}, InvalidInput);
}

}  // namespace
}  // namespace mapnav
