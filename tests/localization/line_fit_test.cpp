// The robust line fit (fitPoseToLines), its re-association, and the options of the localization module.
#include "mapnav/localization/line_fit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "line_scene.h"
#include "mapnav/core/error.h"
#include "mapnav/localization/localize.h"
#include "mapnav/localization/pose_filter.h"
#include "mapnav/tokens/current_position.h"

namespace mapnav {
namespace {

using namespace line_scene;

// ---------------------------------------------------------------------------------------------

TEST(MatchingOptions, DefaultsAreValid) {
  EXPECT_NO_THROW(LineMatchOptions{}.validate());
  EXPECT_NO_THROW(MotionNoiseOptions{}.validate());
  EXPECT_NO_THROW(FilterOptions{}.validate());
  EXPECT_NO_THROW(LocalizeOptions{}.validate());
}

TEST(MatchingOptions, ValidateNamesTheBadField) {
  LineMatchOptions m;
  m.loss_scale = 0;
  try {
    m.validate();
    FAIL() << "no throw";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("LineMatchOptions::loss_scale = 0"), std::string::npos) << e.what();
  }
  FilterOptions f;
  f.gate_probability = 1.0;
  EXPECT_THROW(f.validate(), InvalidInput);
  f = {};
  f.motion.distance_sigma_per_m = -1;
  EXPECT_THROW(f.validate(), InvalidInput);
  // The odometry error model's fields, each named with its value.
  const std::vector<std::pair<double MotionNoiseOptions::*, std::string>> fields = {
      {&MotionNoiseOptions::scale_sigma, "MotionNoiseOptions::scale_sigma = -1"},
      {&MotionNoiseOptions::gyro_bias_sigma_deg_s, "MotionNoiseOptions::gyro_bias_sigma_deg_s = -1"},
      {&MotionNoiseOptions::gyro_noise_deg_per_sqrt_s, "MotionNoiseOptions::gyro_noise_deg_per_sqrt_s = -1"}};
  for (const auto& [field, message] : fields) {
    f = {};
    f.motion.*field = -1;
    try {
      f.validate();
      FAIL() << message;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
  f = {};
  f.frame_sigma_m = -0.1;
  try {
    f.validate();
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("FilterOptions::frame_sigma_m = -0.1"), std::string::npos) << e.what();
  }
  f = {};
  f.frame_heading_sigma_deg = std::numeric_limits<double>::infinity();
  EXPECT_THROW(f.validate(), InvalidInput);
  // A negative or non-finite time step.
  PoseFilter filter(Pose2(), Mat3::Identity());
  EXPECT_THROW(filter.predict({}, -1.0), InvalidInput);
  EXPECT_THROW(filter.predict({}, std::nan("")), InvalidInput);
  LocalizeOptions l;
  l.edge_sigma_m = 0;
  EXPECT_THROW(l.validate(), InvalidInput);
  l = {};
  l.edge_sigma_px = -1;
  EXPECT_THROW(l.validate(), InvalidInput);
  // A covariance that is not positive definite.
  EXPECT_THROW(PoseFilter(Pose2(), Mat3::Zero()), InvalidInput);
}

TEST(MatchingOptions, EnumsRoundTripThroughStrings) {
  for (RobustLoss l : {RobustLoss::None, RobustLoss::Huber, RobustLoss::Cauchy}) {
    EXPECT_EQ(robustLossFromString(toString(l)), l);
  }
  for (PositionStatus s :
       {PositionStatus::Corrected, PositionStatus::OdometryOnly, PositionStatus::Rejected, PositionStatus::Lost}) {
    EXPECT_EQ(positionStatusFromString(toString(s)), s);
  }
  EXPECT_FALSE(robustLossFromString("tukey"));
}

// ---------------------------------------------------------------------------------------------
// fitPoseToLines

TEST(LineMatchingAtCrossing, NoiseFreeLinesRecoverAKnownOffset) {
  const std::optional<LineFit> fit = fitPoseToLines(kPrior, allEdges(kTruth, 0.05));
  ASSERT_TRUE(fit);
  const Vec3 e = poseError(fit->pose, kTruth);
  std::printf("noise-free: error %.2e m, %.2e m, %.2e deg after %d iterations, rms %.1e m\n", e.x(), e.y(),
              radToDeg(e.z()), fit->iterations, fit->rms_m);
  EXPECT_LT(e.head<2>().norm(), 1e-3);
  EXPECT_LT(std::abs(radToDeg(e.z())), 0.01);
  EXPECT_TRUE(fit->converged);
  EXPECT_EQ(fit->inliers, 5);
  EXPECT_TRUE(fit->outliers.empty());
  EXPECT_TRUE(fit->observed.along && fit->observed.lateral && fit->observed.heading);
  EXPECT_TRUE(fit->observed.unobserved.empty());
}

TEST(LineMatchingAtCrossing, NoisyErrorsAreWithinTheReportedCovariance) {
  // 500 seeded trials with 5 cm noise on every detected end point: the normalised estimation error
  // squared, e^T I e, is chi-square with 3 degrees of freedom when the information I is right.
  constexpr int kTrials = 500;
  constexpr double kSigma = 0.05;
  std::mt19937_64 rng(2024);
  double nees = 0;
  int dropped = 0;
  Vec3 squared = Vec3::Zero(), reported = Vec3::Zero();
  for (int t = 0; t < kTrials; ++t) {
    const std::optional<LineFit> fit = fitPoseToLines(kPrior, allEdges(kTruth, kSigma, &rng));
    ASSERT_TRUE(fit);
    dropped += 5 - fit->inliers;  // a good line with a point beyond 4 sigma: about 1 trial in 1500
    const Vec3 e = poseError(fit->pose, kTruth);
    nees += e.dot(fit->information * e);
    squared += e.cwiseProduct(e);
    reported += fit->information.inverse().diagonal();
  }
  nees /= kTrials;
  const auto [lo, hi] = meanChiSquareInterval(3, kTrials, 0.99);
  const Vec3 actual = (squared / kTrials).cwiseSqrt(), claimed = (reported / kTrials).cwiseSqrt();
  std::printf("mean NEES over %d trials: %.3f (99%% interval for chi2(3): [%.3f, %.3f]); good lines dropped: %d\n",
              kTrials, nees, lo, hi, dropped);
  std::printf("RMS error x %.4f m, y %.4f m, heading %.4f deg; reported sigma %.4f m, %.4f m, %.4f deg\n", actual.x(),
              actual.y(), radToDeg(actual.z()), claimed.x(), claimed.y(), radToDeg(claimed.z()));
  EXPECT_LE(dropped, 3);
  EXPECT_GT(nees, lo);
  EXPECT_LT(nees, hi);
}

TEST(LineMatchingOnStraightRoad, ParallelLinesLeaveTheAlongRoadPositionUnchanged) {
  const std::optional<LineFit> fit = fitPoseToLines(kPrior, roadEdges(kTruth, 0.05));
  ASSERT_TRUE(fit);
  const Vec3 e = poseError(fit->pose, kTruth);
  std::printf("parallel only: x stays at the prior's %+.4f m off; y error %.2e m, heading error %.2e deg\n", e.x(),
              e.y(), radToDeg(e.z()));
  EXPECT_DOUBLE_EQ(fit->pose.x(), kPrior.x());  // along the road: the prior's value
  EXPECT_LT(std::abs(e.y()), 1e-3);              // across: corrected
  EXPECT_LT(std::abs(radToDeg(e.z())), 0.01);
  EXPECT_FALSE(fit->observed.along);
  EXPECT_TRUE(fit->observed.lateral);
  EXPECT_TRUE(fit->observed.heading);
  ASSERT_EQ(fit->observed.unobserved.size(), 1u);
  EXPECT_NEAR(std::abs(fit->observed.unobserved[0].x()), 1.0, 1e-9);  // the road's direction
  EXPECT_NEAR(fit->information(0, 0), 0.0, 1e-9);
}

TEST(LineMatchingOnStraightRoad, ACrossingPairFixesTheAlongRoadPosition) {
  std::vector<LineCorrespondence> lines = roadEdges(kTruth, 0.05);
  lines.push_back(detect("R2.near.0", kTruth, {{19, 1.5}, {19, 5}}, kCrossNear, 0.05));
  lines.push_back(detect("R2.far.0", kTruth, {{21, 1.5}, {21, 5}}, kCrossFar, 0.05));
  const std::optional<LineFit> fit = fitPoseToLines(kPrior, lines);
  ASSERT_TRUE(fit);
  const Vec3 e = poseError(fit->pose, kTruth);
  EXPECT_LT(e.head<2>().norm(), 1e-3);
  EXPECT_LT(std::abs(radToDeg(e.z())), 0.01);
  EXPECT_TRUE(fit->observed.along);
  EXPECT_TRUE(fit->observed.unobserved.empty());
}

TEST(LineMatchingAtCrossing, OneWrongLabelAmongFiveDoesNotMoveTheResult) {
  // The crossing's near edge at y < 0 labelled as its far edge (a line 2 m away), with 5 cm noise
  // on all points: the robust fit rejects it, and the pose is the one the four good lines give.
  constexpr int kTrials = 100;
  constexpr double kSigma = 0.05;
  std::mt19937_64 rng(7);
  double nees = 0, plain_shift = 0;
  int rejected = 0, same = 0;
  for (int t = 0; t < kTrials; ++t) {
    std::vector<LineCorrespondence> lines = allEdges(kTruth, kSigma, &rng);
    std::vector<LineCorrespondence> good(lines.begin(), lines.end() - 1);
    lines.back().id = "R3.far.0";
    lines.back().map_world = Segment2{{21, -10}, {21, 10}};
    const std::optional<LineFit> fit = fitPoseToLines(kPrior, lines);
    const std::optional<LineFit> reference = fitPoseToLines(kPrior, good);
    ASSERT_TRUE(fit && reference);
    const auto& out = fit->outliers;
    if (std::find(out.begin(), out.end(), "R3.far.0") != out.end()) ++rejected;
    // The shift from the good lines' pose, in the good lines' standard deviations (Mahalanobis):
    // none when the same lines are used.
    const Vec3 shift = poseError(fit->pose, reference->pose);
    if (std::sqrt(shift.dot(reference->information * shift)) < 1e-6) ++same;
    const Vec3 e = poseError(fit->pose, kTruth);
    nees += e.dot(reference->information * e) / kTrials;
    // Least squares without a robust loss nor rejection, for comparison.
    LineMatchOptions plain;
    plain.loss = RobustLoss::None;
    plain.inlier_threshold = 1e9;
    const Vec3 p = poseError(fitPoseToLines(kPrior, lines, plain)->pose, kTruth);
    plain_shift = std::max(plain_shift, p.head<2>().norm());
  }
  const auto [lo, hi] = meanChiSquareInterval(3, kTrials, 0.99);
  std::printf("wrong label: rejected in %d/%d trials; the good lines' pose exactly in %d; mean NEES %.2f "
              "(99%% interval [%.2f, %.2f]); plain least squares is off by up to %.3f m\n",
              rejected, kTrials, same, nees, lo, hi, plain_shift);
  EXPECT_EQ(rejected, kTrials);
  EXPECT_GE(same, kTrials - 2);  // a good line may be dropped too, as without the wrong label
  EXPECT_GT(nees, lo);           // errors as the noise alone gives
  EXPECT_LT(nees, hi);
  EXPECT_GT(plain_shift, 0.1);  // without the robust loss the wrong label does move it
}

TEST(LineMatching, NoLinesGiveNothing) { EXPECT_FALSE(fitPoseToLines(kPrior, {})); }

// ---------------------------------------------------------------------------------------------
// Re-association

TEST(LineMatchingReassociation, APieceOnTheWrongSegmentOfANotchedEdgeMovesToTheRightOne) {
  const std::vector<LineCorrespondence> lines = notchScene(kNotchTruth, kNotchPrior);
  // The prior's association is wrong: the notch piece is matched against the edge after it.
  ASSERT_EQ(lines[1].map_world.a, Vec2(12, 1));

  const std::optional<LineFit> fit = fitPoseToLines(kNotchPrior, lines);
  ASSERT_TRUE(fit);
  const Vec3 e = poseError(fit->pose, kNotchTruth);
  EXPECT_LT(e.head<2>().norm(), 1e-6);
  EXPECT_LT(std::abs(e.z()), 1e-8);
  EXPECT_TRUE(fit->outliers.empty());
  EXPECT_EQ(fit->map_lines[1].a, Vec2(10, 1.3));  // the notch
  EXPECT_EQ(fit->map_lines[1].b, Vec2(12, 1.3));
  EXPECT_LT(fit->rms_m, 1e-6);

  // Without candidates the prior's association stays: the notch piece, 0.3 m off its line at the
  // true pose, is rejected as an outlier (or, kept, would bend the pose).
  std::vector<LineCorrespondence> fixed = lines;
  for (LineCorrespondence& c : fixed) c.candidates.clear();
  const std::optional<LineFit> plain = fitPoseToLines(kNotchPrior, fixed);
  ASSERT_TRUE(plain);
  EXPECT_EQ(plain->outliers, std::vector<std::string>{"R1.left.1"});
}

}  // namespace
}  // namespace mapnav
