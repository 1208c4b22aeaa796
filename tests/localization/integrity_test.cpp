// The integrity monitor (integrity.h) on hand-made frames: an estimate pulled across the road a
// little each frame is found departed from odometry where the chi-square bound says; the gate's
// rejections among the last frames make the position uncertain at the binomial bound; frames that
// observe nothing do too; and the map's error as the pose filter takes it (setMapSigma).
#include "mapnav/localization/integrity.h"

#include <gtest/gtest.h>

#include <cmath>

#include <boost/math/distributions/chi_squared.hpp>

#include "mapnav/core/error.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/types.h"

namespace mapnav {
namespace {

using State = IntegrityVerdict::State;

/// A filter at the origin heading +x, 0.1 m and 1 deg sigma, with only random odometry noise (no
/// scale or bias states) and none per step, so that covariances stay what the test computes.
PoseFilter quietFilter() {
  FilterOptions o;
  o.motion = MotionNoiseOptions{.scale_sigma = 0, .gyro_bias_sigma_deg_s = 0, .gyro_noise_deg_per_sqrt_s = 0,
                                .distance_sigma_per_m = 0, .heading_sigma_per_rad = 0, .heading_sigma_per_m = 0,
                                .base_sigma_m = 0, .base_heading_sigma_rad = 0};
  const double h = degToRad(1.0);
  return PoseFilter(Pose2(), Vec3(0.01, 0.01, h * h).asDiagonal(), o);
}

/// A frame whose lines observed the position across the road and the heading, accepted or rejected.
CurrentPosition measured(const PoseFilter& f, bool rejected = false) {
  CurrentPosition p = f.current(0, "");
  p.status = rejected ? PositionStatus::Rejected : PositionStatus::Corrected;
  p.observed_lateral = p.observed_heading = !rejected;
  p.gate_dof = 2;
  p.mahalanobis_d2 = rejected ? 20 : 1;
  return p;
}

TEST(Integrity, TheDefaultsAreValid) { EXPECT_NO_THROW(IntegrityOptions{}.validate()); }

TEST(Integrity, BadOptionsNameTheField) {
  IntegrityOptions o;
  o.min_observed_fraction = 1.5;
  try {
    o.validate();
    FAIL() << "no throw";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("min_observed_fraction"), std::string::npos) << e.what();
  }
}

// Standing still, the estimate pulled 0.3 m to the left each frame (wrong lines accepted a step at a
// time; the covariance as the filter's, 0.01 m² per axis): the difference from the dead reckoning
// (which stays at the origin, also 0.01 m²) has variance 0.02 m² across, so d² = y² / 0.02, beyond
// chi-square(3)'s 0.9999 quantile (21.1) once y > 0.65 m: on the third frame (0.9 m), not the second.
TEST(Integrity, AnEstimatePulledAcrossTheRoadIsFoundDepartedWhereTheBoundSays) {
  PoseFilter filter = quietFilter();
  IntegrityMonitor monitor(filter);
  const double bound = boost::math::quantile(boost::math::chi_squared_distribution<double>(3), 0.9999);
  for (int frame = 1; frame <= 3; ++frame) {
    monitor.predict(MotionIncrement{}, 0.1);
    filter.moveTo(Pose2(0, 0.3 * frame, 0));
    const IntegrityVerdict v = monitor.observe(measured(filter), filter);
    const double y = 0.3 * frame;
    EXPECT_NEAR(v.departure_d2, y * y / 0.02, 1e-9) << frame;
    EXPECT_NEAR(v.departure_bound, bound, 1e-9);
    EXPECT_EQ(v.state, frame < 3 ? State::Ok : State::Departed) << frame << ": " << v.reason;
    if (frame == 3) {
      EXPECT_NE(v.reason.find("departed from odometry by 0.90 m"), std::string::npos) << v.reason;
      EXPECT_NEAR(v.dead_reckoned.y(), 0, 1e-12);  // where the caller puts the estimate back
    }
  }
}

// Driving, the estimate and the dead reckoning move together: no departure, however far.
TEST(Integrity, AnEstimateThatMovesWithOdometryHasNotDeparted) {
  PoseFilter filter = quietFilter();
  IntegrityMonitor monitor(filter);
  for (int frame = 1; frame <= 50; ++frame) {
    const MotionIncrement step{1.0, degToRad(0.5)};
    monitor.predict(step, 0.1);
    filter.predict(step, 0.1);
    const IntegrityVerdict v = monitor.observe(measured(filter), filter);
    ASSERT_EQ(v.state, State::Ok) << frame << ": " << v.reason;
    EXPECT_NEAR(v.departure_d2, 0, 1e-9);
  }
}

// With the gate at 0.999 a consistent filter has a frame rejected with probability 0.001. Among 10
// frames, one rejection has P(>= 1) = 1 - 0.999^10 = 0.00995, above 1 - 0.999: not uncertain; two
// have P(>= 2) = 4.5e-5: uncertain.
TEST(Integrity, TwoRejectionsInTenFramesMakeThePositionUncertainOneDoesNot) {
  PoseFilter filter = quietFilter();
  IntegrityMonitor monitor(filter);
  for (int frame = 1; frame <= 10; ++frame) {
    monitor.predict(MotionIncrement{0.5, 0}, 0.1);
    filter.predict(MotionIncrement{0.5, 0}, 0.1);
    const IntegrityVerdict v = monitor.observe(measured(filter, frame == 4 || frame == 9), filter);
    EXPECT_EQ(v.state, frame < 9 ? State::Ok : State::Uncertain) << frame << ": " << v.reason;
    EXPECT_EQ(v.rejections, frame < 4 ? 0 : frame < 9 ? 1 : 2);
  }
  // Ten accepted frames later the first rejection has left the window, the second not.
  IntegrityVerdict v;
  for (int frame = 1; frame <= 5; ++frame) v = monitor.observe(measured(filter), filter);
  EXPECT_EQ(v.rejections, 1);
  EXPECT_EQ(v.state, State::Ok) << v.reason;
}

// Frames of 1 m that observe nothing: over the last 20 m fewer than half observed the position.
TEST(Integrity, FramesThatObserveNothingMakeThePositionUncertainAfterTwentyMetres) {
  PoseFilter filter = quietFilter();
  IntegrityMonitor monitor(filter);
  IntegrityVerdict v;
  for (int frame = 1; frame <= 30; ++frame) {
    monitor.predict(MotionIncrement{1.0, 0}, 0.1);
    filter.predict(MotionIncrement{1.0, 0}, 0.1);
    CurrentPosition p = filter.current(0, "odometry only");
    if (frame <= 10) p = measured(filter);
    v = monitor.observe(p, filter);
    // Frame 20: 20 frames in the window, 10 observed (half): not fewer. Frame 21: 9 of 20.
    EXPECT_EQ(v.state, frame <= 20 ? State::Ok : State::Uncertain) << frame << ": " << v.reason;
  }
  EXPECT_DOUBLE_EQ(v.observed_fraction, 0.0);
  EXPECT_NE(v.reason.find("observed in 0 of the 20 frames of the last 20 m"), std::string::npos) << v.reason;
}

// The map's error as the filter takes it: one step of d = 3 m adds 2 (sigma / L)² (1 - exp(-d / L))
// to the heading variance (sigma 0.5 m, L 30 m), and mapCovariance() is diag(sigma², sigma², (sigma / L)²).
TEST(Integrity, TheMapsErrorGrowsTheHeadingVarianceByItsFormulaAndIsStated) {
  PoseFilter exact = quietFilter();
  PoseFilter mapped = quietFilter();
  mapped.setMapSigma(0.5);
  EXPECT_THROW(mapped.setMapSigma(-1), InvalidInput);
  exact.predict(MotionIncrement{3.0, 0}, 0.1);
  mapped.predict(MotionIncrement{3.0, 0}, 0.1);
  const double slope = 0.5 / 30.0;
  EXPECT_NEAR(mapped.covariance()(2, 2) - exact.covariance()(2, 2), 2 * slope * slope * (1 - std::exp(-0.1)), 1e-15);
  const Mat3 m = mapped.mapCovariance();
  EXPECT_DOUBLE_EQ(m(0, 0), 0.25);
  EXPECT_DOUBLE_EQ(m(1, 1), 0.25);
  EXPECT_DOUBLE_EQ(m(2, 2), slope * slope);
  EXPECT_TRUE(exact.mapCovariance().isZero());
  EXPECT_TRUE(mapped.current(0, "").map_covariance.isApprox(m));
}

}  // namespace
}  // namespace mapnav
