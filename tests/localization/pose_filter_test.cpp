// The pose filter: odometry prediction, the gate, the iterated EKF update and its re-association.
#include "mapnav/localization/pose_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

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
  // Straight along x: the along variance adds (sigma per metre * step)^2 and the base every step.
  const double along = 1e-4 + 20 * std::pow(m.distance_sigma_per_m * 0.5, 2) + 20 * std::pow(m.base_sigma_m, 2);
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

TEST(MatchingFilter, UpdatedErrorsAreWithinTheReportedCovariance) {
  // Truth drawn from the prior (20 cm, 3 degrees), lines with 5 cm noise: the posterior's NEES.
  constexpr int kTrials = 500;
  const Mat3 p0 = diagonalCovariance(0.2, 3.0);
  const Eigen::LLT<Mat3> chol(p0);
  std::mt19937_64 rng(99);
  std::normal_distribution<double> unit(0.0, 1.0);
  double nees = 0;
  int rejected = 0;
  for (int t = 0; t < kTrials; ++t) {
    const Vec3 offset = chol.matrixL() * Vec3(unit(rng), unit(rng), unit(rng));
    const Pose2 truth(kTruth.x() + offset.x(), kTruth.y() + offset.y(), kTruth.heading() + offset.z());
    PoseFilter filter(kTruth, p0);
    const CurrentPosition out = filter.update(allEdges(truth, 0.05, &rng));
    if (out.status == PositionStatus::Rejected) ++rejected;
    const Vec3 e = poseError(out.pose, truth);
    nees += e.dot(out.covariance.inverse() * e);
  }
  nees /= kTrials;
  const auto [lo, hi] = meanChiSquareInterval(3, kTrials, 0.99);
  std::printf("EKF update: mean NEES %.3f over %d trials (99%% interval [%.3f, %.3f]), %d gated out\n", nees, kTrials,
              lo, hi, rejected);
  EXPECT_GT(nees, lo);
  EXPECT_LT(nees, hi);
  EXPECT_LE(rejected, 5);  // 0.5 expected at the 0.999 gate
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

TEST(LineMatchingReassociation, TheFilterUpdateReassociatesToo) {
  const Mat3 p = diagonalCovariance(1.0, 2.0);
  PoseFilter filter(kNotchPrior, p);
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
  PoseFilter reference(kNotchPrior, p);
  ASSERT_EQ(reference.update(right).status, PositionStatus::Corrected);
  EXPECT_LT(poseError(filter.pose(), reference.pose()).norm(), 1e-9);
  EXPECT_LT((filter.covariance() - reference.covariance()).cwiseAbs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace mapnav
