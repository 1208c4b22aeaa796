// The pose filter: odometry prediction, the gate, the iterated EKF update and its re-association.
#include "mapnav/localization/pose_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <utility>

#include <boost/math/distributions/chi_squared.hpp>

#include "line_scene.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

using namespace line_scene;

// ---------------------------------------------------------------------------------------------
// PoseFilter

TEST(MatchingFilter, OdometryOnlyDriftGrowsTheCovariance) {
  PoseFilter filter(Pose2(0, 0, 0), diagonalCovariance(0.01, 0.5), twoPercentOdometry());
  const MotionNoiseOptions& m = filter.options().motion;
  double trace = filter.covariance().trace();
  for (int i = 0; i < 20; ++i) {
    filter.predict({0.5, 0.0});
    EXPECT_GT(filter.covariance().trace(), trace);
    trace = filter.covariance().trace();
  }
  EXPECT_POSE_NEAR(filter.pose(), Pose2(10, 0, 0), 1e-12);
  // Straight along x: the along variance adds (sigma per metre * step)^2 and the base every step,
  // and the scale error's sigma_e^2 (10 m)^2 (a systematic error grows with the distance).
  const double along = 1e-4 + 20 * std::pow(m.distance_sigma_per_m * 0.5, 2) + 20 * std::pow(m.base_sigma_m, 2) +
                       std::pow(m.scale_sigma * 10, 2);
  EXPECT_NEAR(filter.covariance()(0, 0), along, 1e-12);
  // The heading adds (sigma per metre * step)^2 + base^2 every step ...
  const double heading = std::pow(degToRad(0.5), 2) + 20 * std::pow(m.heading_sigma_per_m * 0.5, 2) +
                         20 * std::pow(m.base_heading_sigma_rad, 2);
  EXPECT_NEAR(filter.covariance()(2, 2), heading, 1e-15);
  // ... and its uncertainty makes the lateral one grow faster than the base noise alone.
  EXPECT_GT(filter.covariance()(1, 1), 1e-4 + 20 * std::pow(m.base_sigma_m, 2) + 1e-4);
  std::printf("after 10 m of odometry: sigma along %.4f m, lateral %.4f m, heading %.3f deg\n",
              std::sqrt(filter.covariance()(0, 0)), std::sqrt(filter.covariance()(1, 1)),
              radToDeg(std::sqrt(filter.covariance()(2, 2))));
}

// Standing still for T = 100 s in 1 s steps, from a pose covariance with no correlation to the gyro
// bias: the heading is h - b t, so its variance grows by sigma_b^2 T^2 (the bias, systematic) plus
// q T (the angle random walk, q = gyro_noise^2) plus the per-step base; x and y get only the base.
// The bias' variance stays sigma_b^2 and its covariance with the heading is -sigma_b^2 T.
TEST(MatchingFilter, StandingStillGrowsTheHeadingVarianceWithTime) {
  FilterOptions o;
  o.motion.gyro_bias_sigma_deg_s = 0.1;
  o.motion.gyro_noise_deg_per_sqrt_s = 0.1;
  PoseFilter filter(Pose2(3, 4, 0.5), diagonalCovariance(0.05, 1.0), o);
  for (int i = 0; i < 100; ++i) filter.predict({0.0, 0.0}, 1.0);
  const double sb = degToRad(0.1), q = std::pow(degToRad(0.1), 2), base_h = std::pow(o.motion.base_heading_sigma_rad, 2);
  const double heading = std::pow(degToRad(1.0), 2) + sb * sb * 100 * 100 + q * 100 + 100 * base_h;
  EXPECT_NEAR(filter.covariance()(2, 2), heading, 1e-12);
  // sqrt(1 + 100 + 1 deg^2 + base): 1 deg at the start, 10.1 deg after 100 s (the bias' 10 deg dominates).
  EXPECT_NEAR(radToDeg(std::sqrt(filter.covariance()(2, 2))), 10.1002, 1e-3);
  EXPECT_NEAR(filter.fullCovariance()(2, 4), -sb * sb * 100, 1e-15);
  EXPECT_NEAR(filter.fullCovariance()(4, 4), sb * sb, 1e-18);
  EXPECT_NEAR(filter.covariance()(0, 0), 0.05 * 0.05 + 100 * std::pow(o.motion.base_sigma_m, 2), 1e-15);
  EXPECT_NEAR(filter.covariance()(0, 2), 0.0, 1e-15);
  EXPECT_POSE_NEAR(filter.pose(), Pose2(3, 4, 0.5), 1e-15);  // no bias estimated yet: no motion
}

// Driving D = 40 m straight along x in 0.5 m steps with no time elapsing: the along variance grows by
// sigma_e^2 D^2 (the scale error: one e for the whole distance) plus the random per-step terms;
// its covariance with e is sigma_e^2 D. A known scale error is applied to the reading.
TEST(MatchingFilter, DrivingGrowsTheAlongVarianceWithTheScaleUncertainty) {
  FilterOptions o;
  o.motion.scale_sigma = 0.02;
  o.motion.distance_sigma_per_m = 0.02;
  PoseFilter filter(Pose2(0, 0, 0), diagonalCovariance(0.1, 1.0), o);
  for (int i = 0; i < 80; ++i) filter.predict({0.5, 0.0});
  const double along = 0.01 + 0.02 * 0.02 * 40 * 40 + 80 * std::pow(0.02 * 0.5, 2) + 80 * std::pow(o.motion.base_sigma_m, 2);
  EXPECT_NEAR(filter.covariance()(0, 0), along, 1e-12);
  EXPECT_NEAR(std::sqrt(filter.covariance()(0, 0)), 0.81122, 1e-4);  // sqrt(0.01 + 0.64 + 0.008 + 8e-5): 0.80 m the scale's
  EXPECT_NEAR(filter.fullCovariance()(0, 3), 0.02 * 0.02 * 40, 1e-15);
  EXPECT_NEAR(filter.fullCovariance()(1, 3), 0.0, 1e-15);  // the scale moves nothing across the road
  EXPECT_POSE_NEAR(filter.pose(), Pose2(40, 0, 0), 1e-12);
  // With the scale off, the random terms alone: sqrt(0.01 + 0.008 + 8e-5) = 0.1345 m.
  o.motion.scale_sigma = 0;
  PoseFilter unscaled(Pose2(0, 0, 0), diagonalCovariance(0.1, 1.0), o);
  for (int i = 0; i < 80; ++i) unscaled.predict({0.5, 0.0});
  EXPECT_NEAR(std::sqrt(unscaled.covariance()(0, 0)), 0.13446, 1e-4);
}

// On a map that states its error sigma (setMapSigma), the map's stretch: two points of its roads d
// apart are off by a difference of variance 2 sigma^2 (1 - exp(-d^2 / (2 L^2))) along the way (the
// squared-exponential field's, sim/map_error.h), so driving d metres from the last fix of the
// along-road position adds that to the along variance (across the road the map's direction error
// adds its own, as before); a fix restarts it.
TEST(MatchingFilter, OnAMapThatStatesItsErrorTheAlongVarianceGrowsWithItsStretch) {
  FilterOptions o;
  o.motion.scale_sigma = 0;
  const double sigma = 0.5, l = o.map_correlation_m;
  auto drive = [&](PoseFilter& f, int steps) {
    for (int i = 0; i < steps; ++i) f.predict({0.5, 0.0});
  };
  PoseFilter exact(Pose2(0, 0, 0), diagonalCovariance(0.1, 1.0), o), mapped = exact;
  mapped.setMapSigma(sigma);
  drive(exact, 60);
  drive(mapped, 60);  // 30 m = L: 2 sigma^2 (1 - e^-1/2) = 0.1967 m^2
  const double stretch = 2 * sigma * sigma * (1 - std::exp(-30.0 * 30.0 / (2 * l * l)));
  EXPECT_NEAR(stretch, 0.19673, 1e-5);
  EXPECT_NEAR(mapped.covariance()(0, 0) - exact.covariance()(0, 0), stretch, 1e-12);
  EXPECT_NEAR(mapped.fullCovariance()(0, 3), exact.fullCovariance()(0, 3), 1e-15);  // not the scale's
  // Far beyond L it is bounded by 2 sigma^2: 600 m more add 2 sigma^2 e^-1/2 = 0.3033 m^2.
  drive(exact, 1200);
  drive(mapped, 1200);
  EXPECT_NEAR(mapped.covariance()(0, 0) - exact.covariance()(0, 0), 2 * sigma * sigma, 1e-9);
  // A crossing line and the road's edges fix the along-road position: the stretch restarts from 0,
  // so 5 m later it has added 2 sigma^2 (1 - exp(-25 / 1800)) = 0.0069 m^2 (not the 0.5 of the way).
  const Pose2 truth = mapped.pose();
  std::vector<LineCorrespondence> lines;
  auto add = [&](Vec2 a, Vec2 b) {
    LineCorrespondence c;
    c.id = std::to_string(lines.size());
    c.map_world = {truth.transform(a), truth.transform(b)};
    c.detected_vehicle = {a, b};
    c.sigma_m = 0.02;
    lines.push_back(c);
  };
  add({5, -2}, {5, 2});
  add({1, 1.5}, {10, 1.5});
  add({1, -1.5}, {10, -1.5});
  ASSERT_TRUE(mapped.update(lines).observed_along);
  const double after_fix = mapped.covariance()(0, 0);
  PoseFilter copy = mapped;
  copy.setMapSigma(0);
  drive(mapped, 10);
  drive(copy, 10);
  EXPECT_NEAR(mapped.covariance()(0, 0) - copy.covariance()(0, 0), 2 * sigma * sigma * (1 - std::exp(-25.0 / (2 * l * l))),
              1e-12);
  EXPECT_LT(after_fix, 0.01);
}

// The scale and the bias are learnt from the lines: after 20 m read as 20.4 m (2 % long) and a fix
// that puts the vehicle at the true 20 m, the along correction goes mostly into e (its share of the
// along variance: 0.166 of about 0.18), and its variance falls to a fraction of the prior's.
TEST(MatchingFilter, AnAlongFixCorrectsTheScaleEstimate) {
  FilterOptions o;
  o.motion.scale_sigma = 0.02;
  PoseFilter filter(Pose2(0, 0, 0), diagonalCovariance(0.1, 0.5), o);
  for (int i = 0; i < 40; ++i) filter.predict({0.51, 0.0});
  const StateMatrix p = filter.fullCovariance();
  // Lines across and along the road seen from the true pose (20, 0, 0).
  const Pose2 truth(20, 0, 0);
  std::vector<LineCorrespondence> lines;
  auto add = [&](Vec2 a, Vec2 b) {
    LineCorrespondence c;
    c.id = std::to_string(lines.size());
    c.map_world = {a, b};
    c.detected_vehicle = {truth.inverseTransform(a), truth.inverseTransform(b)};
    c.sigma_m = 0.02;
    lines.push_back(c);
  };
  add({25, -2}, {25, 2});   // across the road, 5 m ahead
  add({21, 1.5}, {30, 1.5});  // the road's left edge
  add({21, -1.5}, {30, -1.5});
  const CurrentPosition out = filter.update(lines, 1.0);
  ASSERT_EQ(out.status, PositionStatus::Corrected) << out.reason;
  EXPECT_NEAR(filter.pose().x(), 20.0, 0.02);
  // The linear update's gain for e: cov(x, e) / (var(x) + the lines' along variance) applied to -0.4 m.
  EXPECT_NEAR(filter.scaleError(), -0.4 * p(0, 3) / p(0, 0), 0.0015);
  EXPECT_LT(filter.scaleError(), -0.017);
  EXPECT_LT(filter.fullCovariance()(3, 3), 0.25 * p(3, 3));
}

// The ground's step: a measured distance observes the scale error as a scalar Kalman
// filter with the step's random distance variance added to the measurement's, so that steps
// fused one after another give the batch (closed-form) posterior of e.
TEST(GroundStepUpdate, SequentialStepsGiveTheBatchPosteriorOfTheScaleError) {
  FilterOptions o;
  const double sigma_e = o.motion.scale_sigma, r = 0.01 * 0.01;
  PoseFilter filter(Pose2(0, 0, 0), diagonalCovariance(0.01, 0.5), o);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> reading(0.4, 1.2);
  std::normal_distribution<double> noise(0, 0.01);
  double information = 1 / (sigma_e * sigma_e), weighted = 0;  // the batch posterior's terms
  for (int k = 0; k < 25; ++k) {
    const double d = reading(rng), z = 1.015 * d + noise(rng);
    filter.predict({d, 0.0});
    const double var = std::pow(o.motion.distance_sigma_per_m * (1 + filter.scaleError()) * d, 2) + r;
    // Each step's variance uses the e the prediction was made with: the batch is over the same
    // (known) variances.
    ASSERT_TRUE(filter.updateStep(z, r));
    information += d * d / var;
    weighted += d * (z - d) / var;
  }
  EXPECT_NEAR(filter.scaleError(), weighted / information, 2e-4);
  EXPECT_NEAR(filter.scaleError(), 0.015, 0.004);
  EXPECT_NEAR(filter.fullCovariance()(3, 3), 1 / information, 0.05 / information);
}

// One step from a known position: with a near-exact measurement the position lands where the
// measured step puts it (the step's own random error, not just the scale, is observed), and the
// scale moves by the share of the innovation its variance claims.
TEST(GroundStepUpdate, AnExactStepMovesThePositionToTheMeasuredDistance) {
  FilterOptions o;
  PoseFilter filter(Pose2(3, 4, degToRad(30)), diagonalCovariance(1e-6, 1e-6), o);
  filter.predict({0.8, 0.0});
  const StateMatrix p = filter.fullCovariance();
  const double var_d = std::pow(o.motion.distance_sigma_per_m * 0.8, 2);
  ASSERT_TRUE(filter.updateStep(0.83, 1e-10));
  const Vec2 moved = filter.pose().translation() - Vec2(3, 4);
  EXPECT_NEAR(moved.norm(), 0.83, 1e-4);
  EXPECT_NEAR(std::atan2(moved.y(), moved.x()), degToRad(30), 1e-3);
  const double s = 0.8 * 0.8 * p(3, 3) + var_d + 1e-10;
  EXPECT_NEAR(filter.scaleError(), 0.8 * p(3, 3) / s * 0.03, 1e-9);
  // Only right after a predict; a gross step is beyond the gate; NaN is refused.
  EXPECT_FALSE(filter.updateStep(0.83, 1e-4));
  filter.predict({0.8, 0.0});
  EXPECT_FALSE(filter.updateStep(1.6, 1e-4));
  filter.predict({0.8, 0.0});
  EXPECT_THROW(filter.updateStep(std::nan(""), 1e-4), InvalidInput);
  EXPECT_THROW(filter.updateStep(0.8, 0.0), InvalidInput);
}

FilterOptions independentFixes() {
  FilterOptions o;
  o.gnss_bias_sigma_m = 0;
  return o;
}

// A position fix on a prior without cross terms, the fixes independent (no receiver bias): per axis
// the scalar Kalman update, by hand. Prior sigma 2 m in x and 1 m in y, fix sigma 1 m, 1 m off in
// each: x moves 4/5 of the way and its variance becomes 4/5, y moves 1/2 and its variance 1/2;
// heading, scale and bias stay.
TEST(PositionFixUpdate, OnAnUncorrelatedPriorIsTheScalarKalmanUpdatePerAxis) {
  Mat3 prior = Mat3::Zero();
  prior.diagonal() << 4.0, 1.0, 0.01;
  PoseFilter filter(Pose2(10, 20, 0.3), prior, independentFixes());
  ASSERT_TRUE(filter.updatePosition(Vec2(11, 21), 1.0));
  EXPECT_NEAR(filter.pose().x(), 10.8, 1e-12);
  EXPECT_NEAR(filter.pose().y(), 20.5, 1e-12);
  EXPECT_NEAR(filter.pose().heading(), 0.3, 1e-12);
  EXPECT_NEAR(filter.covariance()(0, 0), 0.8, 1e-12);
  EXPECT_NEAR(filter.covariance()(1, 1), 0.5, 1e-12);
  EXPECT_NEAR(filter.covariance()(2, 2), 0.01, 1e-12);
  EXPECT_EQ(filter.scaleError(), 0.0);
  EXPECT_EQ(filter.gyroBias(), 0.0);
}

// With the receiver's bias a state (gnss_bias_sigma_m B, the default 1.5 m), a fix stating sigma
// s has white noise sqrt(s² - B²): the innovation is shared between the pose, the bias and the
// noise in proportion to their variances. Prior 1 m² per axis, B = 1 m, s² = 2 m²: a fix 3 m off in
// x moves the pose 1 m and the bias 1 m; both variances become 1 - 1/3, their covariance -1/3.
// Then the bias forgets itself over its correlation time: after predict over one time constant its
// estimate is 1/e of itself and its variance B² e^-2 (2/3) + B² (1 - e^-2).
TEST(PositionFixUpdate, TheReceiversBiasTakesItsShareOfTheInnovationAndForgetsItself) {
  FilterOptions o;
  o.gnss_bias_sigma_m = 1.0;
  o.gnss_bias_time_s = 60.0;
  Mat3 prior = Mat3::Zero();
  prior.diagonal() << 1.0, 1.0, 0.01;
  PoseFilter filter(Pose2(10, 20, 0.3), prior, o);
  ASSERT_TRUE(filter.updatePosition(Vec2(13, 20), std::sqrt(2.0)));
  EXPECT_NEAR(filter.pose().x(), 11.0, 1e-12);
  EXPECT_NEAR(filter.pose().y(), 20.0, 1e-12);
  EXPECT_NEAR(filter.gnssBias().x(), 1.0, 1e-12);
  EXPECT_NEAR(filter.gnssBias().y(), 0.0, 1e-12);
  EXPECT_NEAR(filter.fullCovariance()(0, 0), 2.0 / 3, 1e-12);
  EXPECT_NEAR(filter.fullCovariance()(5, 5), 2.0 / 3, 1e-12);
  EXPECT_NEAR(filter.fullCovariance()(0, 5), -1.0 / 3, 1e-12);
  EXPECT_NEAR(filter.fullCovariance()(1, 1), 2.0 / 3, 1e-12);  // y: the same share of a zero innovation
  filter.predict({0.0, 0.0}, 60.0);
  const double phi = std::exp(-1.0);
  EXPECT_NEAR(filter.gnssBias().x(), phi, 1e-12);
  EXPECT_NEAR(filter.fullCovariance()(5, 5), phi * phi * 2.0 / 3 + (1 - phi * phi), 1e-12);
  EXPECT_NEAR(filter.fullCovariance()(0, 5), -phi / 3, 1e-12);
}

// Fixes a second apart share their bias: driving 10 m/s along x for 30 s (the odometry exact, the
// start known to 0.1 m), a fix each second 2 m ahead of the truth. Taken as independent
// (gnss_bias_sigma_m 0) the fixes pull the along-road position, which the scale's uncertainty
// widens, all the way to them (and the scale with it); with the bias a state, which takes the 2 m
// while the pose is still well known, the estimate ends less than half as far off.
TEST(PositionFixUpdate, BiasedFixesDoNotDragThePositionAlongTheRoad) {
  const auto error = [](const FilterOptions& o) {
    PoseFilter filter(Pose2(0, 0, 0), Mat3::Identity() * 0.01, o);
    for (int t = 1; t <= 30; ++t) {
      filter.predict({10.0, 0.0}, 1.0);
      filter.updatePosition(Vec2(10.0 * t + 2.0, 0), 1.8);
    }
    return filter.pose().x() - 300.0;
  };
  const double independent = error(independentFixes());
  EXPECT_GT(independent, 2.0);
  EXPECT_LT(std::abs(error(FilterOptions{})), 0.5 * independent);
}

// Beyond the 2-dof gate (0.999 by default: chi-squared 13.8) the fix is refused and nothing moves;
// a fix that is not finite, or a sigma that is not > 0, is named.
TEST(PositionFixUpdate, AFixBeyondTheGateIsRefusedAndBadOnesAreNamed) {
  PoseFilter filter(Pose2(0, 0, 0), Mat3::Identity() * 0.01);
  const double limit = boost::math::quantile(boost::math::chi_squared_distribution<double>(2),
                                             FilterOptions{}.gate_probability);
  // S = 0.01 + 1.5² (the bias) + max(1 - 1.5², 1/4) (the white noise: a quarter of the stated
  // variance at least) per axis: a fix d m off in x has Mahalanobis d² / 2.51.
  const double edge = std::sqrt(limit * 2.51);
  EXPECT_FALSE(filter.updatePosition(Vec2(edge * 1.01, 0), 1.0));
  EXPECT_EQ(filter.pose().x(), 0.0);
  EXPECT_NEAR(filter.covariance()(0, 0), 0.01, 1e-15);
  EXPECT_TRUE(filter.updatePosition(Vec2(edge * 0.99, 0), 1.0));
  EXPECT_GT(filter.pose().x(), 0.0);
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { filter.updatePosition(Vec2(NAN, 0), 1.0); }, "updatePosition"));
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { filter.updatePosition(Vec2(0, 0), 0.0); }, "the sigma > 0"));
}

TEST(MatchingFilter, AGatedOutlierMeasurementIsRejectedAndReported) {
  // The filter is at the truth with a 5 cm / 1 degree covariance; the lines say the vehicle is 1 m
  // to the left.
  PoseFilter filter(kTruth, diagonalCovariance(0.05, 1.0));
  const Pose2 elsewhere(kTruth.x(), kTruth.y() + 1.0, kTruth.heading());
  const CurrentPosition out = filter.update(allEdges(elsewhere, 0.05), 3.5);
  std::printf("outlier: %s (%s)\n", std::string(toString(out.status)).c_str(), out.reason.c_str());
  EXPECT_EQ(out.status, PositionStatus::Rejected);
  EXPECT_NE(out.reason.find("rejected"), std::string::npos);
  EXPECT_GT(out.mahalanobis_d2, boost::math::quantile(boost::math::chi_squared_distribution<double>(3), 0.999));
  EXPECT_DOUBLE_EQ(out.timestamp, 3.5);
  EXPECT_POSE_NEAR(out.pose, kTruth, 0.0);  // never jumps
  EXPECT_POSE_NEAR(filter.pose(), kTruth, 0.0);
  EXPECT_FALSE(out.observed_lateral || out.observed_along || out.observed_heading);

  // Lines that agree are fused.
  const CurrentPosition ok = filter.update(allEdges(kTruth, 0.05), 3.6);
  EXPECT_EQ(ok.status, PositionStatus::Corrected) << ok.reason;
  EXPECT_EQ(ok.lines_used, 5);
  EXPECT_LT(ok.covariance.trace(), diagonalCovariance(0.05, 1.0).trace());
}

// Truth drawn from the prior (20 cm, 3 degrees), lines with 5 cm noise each and, when `shared_error`,
// all lines of the trial seen from a pose off the truth by c ~ N(0, R) (R the frame error of the
// default FilterOptions: 1 cm, 0.3 degrees): the posterior's mean NEES over 500 trials, and the
// trials the gate refused.
std::pair<double, int> meanNees(const FilterOptions& options, bool shared_error) {
  constexpr int kTrials = 500;
  const Mat3 p0 = diagonalCovariance(0.2, 3.0);
  const Eigen::LLT<Mat3> chol(p0);
  const FilterOptions defaults;
  const Mat3 r = diagonalCovariance(defaults.frame_sigma_m, defaults.frame_heading_sigma_deg);
  const Eigen::LLT<Mat3> chol_r(r);
  std::mt19937_64 rng(99);
  std::normal_distribution<double> unit(0.0, 1.0);
  double nees = 0;
  int rejected = 0;
  for (int t = 0; t < kTrials; ++t) {
    const Vec3 offset = chol.matrixL() * Vec3(unit(rng), unit(rng), unit(rng));
    const Pose2 truth(kTruth.x() + offset.x(), kTruth.y() + offset.y(), kTruth.heading() + offset.z());
    const Vec3 c = chol_r.matrixL() * Vec3(unit(rng), unit(rng), unit(rng));
    const Pose2 seen_from = shared_error ? Pose2(truth.x() + c.x(), truth.y() + c.y(), truth.heading() + c.z()) : truth;
    PoseFilter filter(kTruth, p0, options);
    const CurrentPosition out = filter.update(allEdges(seen_from, 0.05, &rng));
    if (out.status == PositionStatus::Rejected) ++rejected;
    const Vec3 e = poseError(out.pose, truth);
    nees += e.dot(out.covariance.inverse() * e);
  }
  return {nees / kTrials, rejected};
}

TEST(MatchingFilter, UpdatedErrorsAreWithinTheReportedCovariance) {
  const auto [lo, hi] = meanChiSquareInterval(3, 500, 0.99);
  FilterOptions independent;  // the lines' errors independent, and modelled so
  independent.frame_sigma_m = 0;
  independent.frame_heading_sigma_deg = 0;
  const auto [nees, rejected] = meanNees(independent, false);
  std::printf("EKF update, independent lines: mean NEES %.3f (99%% interval [%.3f, %.3f]), %d gated out\n", nees, lo,
              hi, rejected);
  EXPECT_GT(nees, lo);
  EXPECT_LT(nees, hi);
  EXPECT_LE(rejected, 5);  // 0.5 expected at the 0.999 gate
  // A frame's lines sharing a pose error: with it modelled (the defaults) the NEES is 3 ...
  const auto [shared, shared_rejected] = meanNees(FilterOptions{}, true);
  std::printf("EKF update, a shared frame error, modelled: mean NEES %.3f, %d gated out\n", shared, shared_rejected);
  EXPECT_GT(shared, lo);
  EXPECT_LT(shared, hi);
  EXPECT_LE(shared_rejected, 5);
  // ... and with the lines taken as independent the filter is overconfident.
  const auto [ignored, ignored_rejected] = meanNees(independent, true);
  std::printf("EKF update, a shared frame error, not modelled: mean NEES %.3f, %d gated out\n", ignored,
              ignored_rejected);
  EXPECT_GT(ignored, 1.5 * hi);  // measured 5.8
}

TEST(MatchingFilter, ALineAFewDegreesOffTheRoadDoesNotMoveTheAlongRoadPosition) {
  // Both road edges, exact, and a 1.5 m corner line 3.8 degrees off the road's direction whose
  // painted boundary runs straight along the road (5 cm off the map's line at its ends): its slant
  // carries along-road information of about 2 sin^2(3.8 deg) / 0.05^2 = 3.5 /m^2 (1 sigma 0.5 m),
  // which a few centimetres of map error turn into decimetres along the road.
  const Pose2 truth(10.0, 0.0, 0.0);
  std::vector<LineCorrespondence> lines = roadEdges(truth, 0.05);
  lines.push_back(detect("I1.corner.0", truth, {{20, 1.55}, {21.5, 1.55}}, Segment2{{20, 1.5}, {21.5, 1.6}}, 0.05));
  const Mat3 p = diagonalCovariance(1.0, 1.0);  // 1 m along: e.g. 40 m after the last fix

  FilterOptions loose;  // min_information 1: the corner's along information counts
  PoseFilter moved(truth, p, loose);
  ASSERT_EQ(moved.update(lines).status, PositionStatus::Corrected);
  const double loose_move = std::abs(moved.pose().x() - truth.x());
  EXPECT_GT(loose_move, 0.05);  // measured 0.078 m

  // min_information 100: along is not observed, so (up to the along component the corner gives the
  // observed lateral / heading directions) not corrected.
  FilterOptions strict;
  strict.match.min_information = 100;
  PoseFilter kept(truth, p, strict);
  const CurrentPosition out = kept.update(lines);
  ASSERT_EQ(out.status, PositionStatus::Corrected);
  EXPECT_FALSE(out.observed_along);
  // Measured 0.015 m: the projection removes the unobserved eigen-direction, but the observed
  // ones (heading, in mixed units with the corner 20 m ahead) keep a small along component.
  EXPECT_LT(std::abs(kept.pose().x() - truth.x()), 0.25 * loose_move);
  EXPECT_GT(kept.covariance()(0, 0), 0.85 * p(0, 0));  // little along information fused
}

// A prior whose along-road and lateral errors are correlated (0.8: what driving a bend with an
// uncertain scale leaves) and 0.2 m off across the road; the road edges observe the lateral
// position and the heading, not the position along. On an exact map the correlation carries the
// lateral correction along the road (-0.2 m x 8 = -1.6 m, less the lines' noise); on a map known
// to 0.5 m the along-road position is only considered: it stays, with its variance, while the
// lateral error is corrected as on the exact map.
TEST(MatchingFilter, OnAMapThatIsNotExactEdgesAloneDoNotMoveTheAlongRoadPosition) {
  const Pose2 truth(10.0, 0.0, 0.0), prior(10.0, 0.2, 0.0);
  Mat3 p = Mat3::Zero();
  p << 1.0, 0.08, 0.0,  //
      0.08, 0.01, 0.0,  //
      0.0, 0.0, std::pow(degToRad(1.0), 2);
  const std::vector<LineCorrespondence> lines = roadEdges(truth, 0.01);

  PoseFilter exact(prior, p);
  const CurrentPosition on_exact = exact.update(lines);
  ASSERT_EQ(on_exact.status, PositionStatus::Corrected) << on_exact.reason;
  EXPECT_FALSE(on_exact.observed_along);
  EXPECT_NEAR(exact.pose().y(), 0.0, 0.01);
  EXPECT_LT(exact.pose().x(), 10.0 - 1.0);

  PoseFilter uncertain(prior, p);
  uncertain.setMapSigma(0.5);
  ASSERT_EQ(uncertain.update(lines).status, PositionStatus::Corrected);
  EXPECT_NEAR(uncertain.pose().y(), exact.pose().y(), 1e-9);
  EXPECT_NEAR(uncertain.pose().x(), 10.0, 1e-9);
  EXPECT_NEAR(uncertain.covariance()(0, 0), 1.0, 1e-9);
  EXPECT_LT(std::abs(uncertain.covariance()(0, 1)), 0.1 * 0.08);
}

TEST(LineMatchingReassociation, TheFilterUpdateReassociatesToo) {
  const Mat3 p = diagonalCovariance(1.0, 2.0);
  FilterOptions independent;  // noise-free lines: no frame error either
  independent.frame_sigma_m = 0;
  independent.frame_heading_sigma_deg = 0;
  PoseFilter filter(kNotchPrior, p, independent);
  const CurrentPosition out = filter.update(notchScene(kNotchTruth, kNotchPrior));
  ASSERT_EQ(out.status, PositionStatus::Corrected) << out.reason;
  EXPECT_EQ(out.lines_used, 7);
  EXPECT_TRUE(out.outliers.empty());
  // Noise-free lines of 5 cm sigma against a 1 m prior: the prior pulls by a few millimetres.
  const Vec3 e = poseError(filter.pose(), kNotchTruth);
  EXPECT_LT(e.head<2>().norm(), 5e-3);
  EXPECT_LT(std::abs(radToDeg(e.z())), 0.02);
  // The same as the update given the right association from the start, without candidates.
  std::vector<LineCorrespondence> right = notchScene(kNotchTruth, kNotchPrior);
  right[1].map_world = Segment2{{10, 1.3}, {12, 1.3}};
  for (LineCorrespondence& c : right) c.candidates.clear();
  PoseFilter reference(kNotchPrior, p, independent);
  ASSERT_EQ(reference.update(right).status, PositionStatus::Corrected);
  EXPECT_LT(poseError(filter.pose(), reference.pose()).norm(), 1e-9);
  EXPECT_LT((filter.covariance() - reference.covariance()).cwiseAbs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace mapnav
