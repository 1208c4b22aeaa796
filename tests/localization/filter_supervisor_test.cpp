// The filter's supervisor (filter_supervisor.h) on hand-made sequences of match outcomes: fits that
// agree and widen the covariance on the Nth frame, fits that disagree, an outlier, a poor fit or an
// accepted frame ending the run, and the run starting again after a reset.
#include "mapnav/localization/filter_supervisor.h"

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/types.h"

namespace mapnav {
namespace {

/// A frame whose lines the gate rejected: the estimate, and the pose the lines alone give as
/// `forward`, `left` (m) and `turn_deg` from it in its own frame.
CurrentPosition rejected(const Pose2& estimate, double forward, double left, double turn_deg, double rms_m = 0,
                         std::vector<std::string> outliers = {}) {
  CurrentPosition p;
  p.status = PositionStatus::Rejected;
  p.pose = estimate;
  p.rejected_fit = estimate * Pose2(forward, left, degToRad(turn_deg));
  p.rejected_fit_rms_m = rms_m;
  p.outliers = std::move(outliers);
  return p;
}

CurrentPosition rejected(double forward, double left, double turn_deg, double rms_m = 0,
                         std::vector<std::string> outliers = {}) {
  return rejected(Pose2(), forward, left, turn_deg, rms_m, std::move(outliers));
}

/// The rule as it was made: three rejected frames in a row (the options' default is 0, off).
constexpr FilterSupervisorOptions kThree{.after_rejections = 3};

/// Whether a fresh supervisor with N = 3 widens on the third of these rejected fits.
bool widensOnTheThird(const CurrentPosition& first, const CurrentPosition& second, const CurrentPosition& third) {
  FilterSupervisor supervisor(kThree);
  supervisor.observe(first);
  supervisor.observe(second);
  return supervisor.observe(third).widen;
}

CurrentPosition accepted() {
  CurrentPosition p;
  p.status = PositionStatus::Corrected;
  return p;
}

// 3 frames, widened to the defaults 0.5 m and 10 degrees: diag(0.25, 0.25, (10 pi / 180)^2).
TEST(FilterSupervisor, ThreeAgreeingRejectedFitsWidenTheCovarianceOnTheThird) {
  FilterSupervisor supervisor(kThree);
  EXPECT_FALSE(supervisor.observe(rejected(0, -0.8, 4)).widen);
  EXPECT_EQ(supervisor.rejections(), 1u);
  EXPECT_FALSE(supervisor.observe(rejected(0.4, -0.7, 5)).widen);  // N - 1: not yet
  EXPECT_EQ(supervisor.rejections(), 2u);
  const SupervisorDecision d = supervisor.observe(rejected(-0.3, -0.9, 3.5));
  ASSERT_TRUE(d.widen);
  EXPECT_EQ(d.rejections, 3u);
  const double h = 10 * kPi / 180;
  EXPECT_DOUBLE_EQ(d.covariance(0, 0), 0.25);
  EXPECT_DOUBLE_EQ(d.covariance(1, 1), 0.25);
  EXPECT_DOUBLE_EQ(d.covariance(2, 2), h * h);
  EXPECT_DOUBLE_EQ(d.covariance(0, 1), 0);
  EXPECT_DOUBLE_EQ(d.covariance(1, 2), 0);
  EXPECT_EQ(supervisor.rejections(), 0u);  // the run starts again
}

// Agreement is judged from the estimate, in its own frame: the vehicle drives 2 m a frame heading
// north, and each fit is 0.8 m to its right (east) and 4 degrees clockwise, whatever the world
// coordinates; the along-road offsets (0, 1, 2 m) are not compared.
TEST(FilterSupervisor, JudgesAgreementInTheEstimatesFrameAsTheVehicleDrives) {
  FilterSupervisor supervisor(kThree);
  for (int frame = 0; frame < 3; ++frame) {
    const Pose2 estimate(10, 5 + 2.0 * frame, kPi / 2);
    const SupervisorDecision d = supervisor.observe(rejected(estimate, frame, -0.8, -4));
    EXPECT_EQ(d.widen, frame == 2) << frame;
  }
}

// A pipeline misreading a curve: 1.5 m left, 1.5 m right, ... (park_loop's R4): never.
TEST(FilterSupervisor, KeepsTheCovarianceWhenTheFitsDisagreeAcrossTheRoad) {
  FilterSupervisor supervisor(kThree);
  for (int frame = 0; frame < 6; ++frame) {
    EXPECT_FALSE(supervisor.observe(rejected(0, frame % 2 == 0 ? 1.5 : -1.5, 0)).widen) << frame;
  }
  // 0.25 m apart agree, 0.35 m do not (agreement_m 0.3).
  EXPECT_TRUE(widensOnTheThird(rejected(0, 1.0, 0), rejected(0, 1.25, 0), rejected(0, 1.1, 0)));
  EXPECT_FALSE(widensOnTheThird(rejected(0, 1.0, 0), rejected(0, 1.35, 0), rejected(0, 1.1, 0)));
}

// 2.5 degrees apart agree, 3.5 do not (agreement_deg 3).
TEST(FilterSupervisor, KeepsTheCovarianceWhenTheFitsDisagreeInHeading) {
  EXPECT_TRUE(widensOnTheThird(rejected(0, 0.5, 4), rejected(0, 0.5, 6.5), rejected(0, 0.5, 5)));
  EXPECT_FALSE(widensOnTheThird(rejected(0, 0.5, 4), rejected(0, 0.5, 7.5), rejected(0, 0.5, 5)));
}

// The window is the last N fits: a stray first fit does not stop three agreeing ones after it.
TEST(FilterSupervisor, JudgesTheLastNFits) {
  FilterSupervisor supervisor(kThree);
  EXPECT_FALSE(supervisor.observe(rejected(0, 1.5, 0)).widen);
  EXPECT_FALSE(supervisor.observe(rejected(0, -0.8, 0)).widen);
  EXPECT_FALSE(supervisor.observe(rejected(0, -0.8, 0)).widen);  // 1.5, -0.8, -0.8: 2.3 m apart
  EXPECT_EQ(supervisor.rejections(), 3u);
  EXPECT_TRUE(supervisor.observe(rejected(0, -0.8, 0)).widen);   // -0.8 three times
}

// One frame with an outlier among its lines ends the run: three good ones after it are needed.
TEST(FilterSupervisor, AnOutlierEndsTheRun) {
  FilterSupervisor supervisor(kThree);
  EXPECT_FALSE(supervisor.observe(rejected(0, -0.8, 4)).widen);
  EXPECT_FALSE(supervisor.observe(rejected(0, -0.8, 4)).widen);
  EXPECT_FALSE(supervisor.observe(rejected(0, -0.8, 4, 0, {"R1.left.0"})).widen);
  EXPECT_EQ(supervisor.rejections(), 0u);
  EXPECT_FALSE(supervisor.observe(rejected(0, -0.8, 4)).widen);
  EXPECT_FALSE(supervisor.observe(rejected(0, -0.8, 4)).widen);
  EXPECT_TRUE(supervisor.observe(rejected(0, -0.8, 4)).widen);
}

// Lines that do not fit together (random campus 15's shadow edge, 0.09-0.13 m): max_rms_m 0.05,
// inclusive.
TEST(FilterSupervisor, APoorFitEndsTheRun) {
  FilterSupervisor supervisor(kThree);
  for (int frame = 0; frame < 5; ++frame) EXPECT_FALSE(supervisor.observe(rejected(0, -0.8, 4, 0.09)).widen) << frame;
  EXPECT_EQ(supervisor.rejections(), 0u);
  supervisor.observe(rejected(0, -0.8, 4, 0.05));
  supervisor.observe(rejected(0, -0.8, 4, 0.05));
  EXPECT_FALSE(supervisor.observe(rejected(0, -0.8, 4, 0.06)).widen);
  EXPECT_EQ(supervisor.rejections(), 0u);
}

// An accepted frame, an odometry-only one or a rejection without a fit end the run too.
TEST(FilterSupervisor, AFrameThatIsNotARejectedFitEndsTheRun) {
  CurrentPosition odometry;
  odometry.status = PositionStatus::OdometryOnly;
  CurrentPosition no_fit;
  no_fit.status = PositionStatus::Rejected;
  for (const CurrentPosition& breaker : {accepted(), odometry, no_fit}) {
    FilterSupervisor supervisor(kThree);
    supervisor.observe(rejected(0, -0.8, 4));
    supervisor.observe(rejected(0, -0.8, 4));
    EXPECT_FALSE(supervisor.observe(breaker).widen);
    EXPECT_EQ(supervisor.rejections(), 0u);
    EXPECT_FALSE(supervisor.observe(rejected(0, -0.8, 4)).widen);
  }
}

// After a reset the counters start from nothing: N more agreeing fits before the next one.
TEST(FilterSupervisor, AfterAResetItTakesNMoreFrames) {
  FilterSupervisor supervisor(kThree);
  for (int frame = 1; frame <= 9; ++frame) {
    EXPECT_EQ(supervisor.observe(rejected(0, -0.8, 4)).widen, frame % 3 == 0) << frame;
    EXPECT_EQ(supervisor.rejections(), static_cast<std::size_t>(frame % 3)) << frame;
  }
  supervisor.observe(rejected(0, -0.8, 4));
  supervisor.clear();
  EXPECT_EQ(supervisor.rejections(), 0u);
}

TEST(FilterSupervisor, NeverWidensAtZeroAndAtOnceAtOne) {
  FilterSupervisor never({.after_rejections = 0});
  for (int frame = 0; frame < 5; ++frame) EXPECT_FALSE(never.observe(rejected(0, -0.8, 4)).widen);
  EXPECT_EQ(never.rejections(), 0u);
  FilterSupervisor once({.after_rejections = 1, .sigma_m = 2, .heading_sigma_deg = 90});
  const SupervisorDecision d = once.observe(rejected(0, -0.8, 4));
  ASSERT_TRUE(d.widen);
  EXPECT_DOUBLE_EQ(d.covariance(0, 0), 4);
  EXPECT_DOUBLE_EQ(d.covariance(2, 2), kPi * kPi / 4);
}

TEST(FilterSupervisorOptions, DefaultsAreValidAndOffAndABadFieldIsNamed) {
  EXPECT_NO_THROW(FilterSupervisorOptions{}.validate());
  FilterSupervisor by_default;
  for (int frame = 0; frame < 5; ++frame) EXPECT_FALSE(by_default.observe(rejected(0, -0.8, 4)).widen);
  try {
    FilterSupervisor bad({.sigma_m = 0});
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "FilterSupervisorOptions::sigma_m = 0: must be finite and > 0");
  }
  EXPECT_THROW(FilterSupervisorOptions{.after_rejections = -1}.validate(), InvalidInput);
}

}  // namespace
}  // namespace mapnav
