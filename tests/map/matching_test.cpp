#include "mapnav/map/matching.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include <boost/math/distributions/chi_squared.hpp>

#include "map_fixtures.h"
#include "mapnav/core/error.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/map/map.h"
#include "mapnav/map/map_io.h"
#include "mapnav/map/predict.h"
#include "mapnav/testing/support.h"
#include "mapnav/vision_iface/detected_object.h"

namespace mapnav {
namespace {

// The scene of most tests: a road along +x, edges y = +1 (left) and y = -1 (right), and a crossing
// road whose edges x = 19 and x = 21 run along y. The vehicle drives along the first road.
const Segment2 kLeft{{-5, 1}, {40, 1}}, kRight{{-5, -1}, {40, -1}};
const Segment2 kCrossNear{{19, -10}, {19, 10}}, kCrossFar{{21, -10}, {21, 10}};

// The error of `estimate` against `truth` as (x, y, heading), the heading wrapped.
Vec3 poseError(const Pose2& estimate, const Pose2& truth) {
  return {estimate.x() - truth.x(), estimate.y() - truth.y(), normalizeAngle(estimate.heading() - truth.heading())};
}

// What a detector at `truth` reports of the world piece `seen` of map line `line`: its end points in
// the vehicle frame, each coordinate with Gaussian noise of `sigma` (none when rng is null).
LineCorrespondence detect(const std::string& id, const Pose2& truth, const Segment2& seen, const Segment2& line,
                          double sigma, std::mt19937_64* rng = nullptr) {
  Segment2 v = truth.inverse().transform(seen);
  if (rng != nullptr) {
    std::normal_distribution<double> noise(0.0, sigma);
    v.a += Vec2(noise(*rng), noise(*rng));
    v.b += Vec2(noise(*rng), noise(*rng));
  }
  return {id, v, line, sigma, {}};
}

// Both road edges seen from 2 to 8 m ahead of the vehicle (x along the road).
std::vector<LineCorrespondence> roadEdges(const Pose2& truth, double sigma, std::mt19937_64* rng = nullptr) {
  const double x = truth.x();
  return {detect("R1.left.0", truth, {{x + 2, 1}, {x + 8, 1}}, kLeft, sigma, rng),
          detect("R1.right.0", truth, {{x + 2, -1}, {x + 8, -1}}, kRight, sigma, rng)};
}

// The crossing road's edges beside the first road, left and right of it.
std::vector<LineCorrespondence> crossingEdges(const Pose2& truth, double sigma, std::mt19937_64* rng = nullptr) {
  return {detect("R2.near.0", truth, {{19, 1.5}, {19, 5}}, kCrossNear, sigma, rng),
          detect("R2.far.0", truth, {{21, 1.5}, {21, 5}}, kCrossFar, sigma, rng),
          detect("R3.near.0", truth, {{19, -5}, {19, -1.5}}, kCrossNear, sigma, rng)};
}

std::vector<LineCorrespondence> allEdges(const Pose2& truth, double sigma, std::mt19937_64* rng = nullptr) {
  std::vector<LineCorrespondence> out = roadEdges(truth, sigma, rng);
  for (const LineCorrespondence& c : crossingEdges(truth, sigma, rng)) out.push_back(c);
  return out;
}

const Pose2 kTruth(14.0, 0.2, degToRad(3.0));
// The prior of the issue: 0.3 m, -0.2 m, 2 degrees off.
const Pose2 kPrior(kTruth.x() + 0.3, kTruth.y() - 0.2, kTruth.heading() + degToRad(2.0));

// The two-sided interval holding the mean of `trials` chi-square(dof) draws with probability p.
std::pair<double, double> meanChiSquareInterval(int dof, int trials, double p) {
  boost::math::chi_squared_distribution<double> sum(dof * trials);
  return {boost::math::quantile(sum, (1 - p) / 2) / trials, boost::math::quantile(sum, (1 + p) / 2) / trials};
}

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
  for (PositionStatus s : {PositionStatus::Corrected, PositionStatus::OdometryOnly, PositionStatus::Rejected}) {
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

// The Terregator camera (1.5 m up, 22 deg down, f = 904 px). A line across the road 10 m ahead
// on the optical axis's plane lies on one image row v0 = cy + f tan(theta - tilt), theta =
// atan(h / 10): a pixel across it is the next row, whose ground distance is h / tan(tilt +
// atan((v0 -+ 1 - cy) / f)) (about (d^2 + h^2) cos^2(theta - tilt) / (h f) = 7.1 cm from the
// 10 m). A line along the road there is a column: a pixel across it is Z / f to the side, Z the
// point's depth on the optical axis, sqrt(d^2 + h^2) cos(theta - tilt) (1.1 cm).
TEST(MatchingNoise, GroundMetresPerPixelIsTheCameraResolutionAcrossTheLine) {
  CameraIntrinsics in;
  in.fx = in.fy = 904;
  CameraMount mount;
  mount.height_m = 1.5;
  mount.tilt_rad = degToRad(22.0);
  const auto camera = createCamera(LensModel::Pinhole, in, mount);
  const double h = 1.5, d = 10.0, tilt = mount.tilt_rad, theta = std::atan(h / d);
  const double v0 = in.cy + in.fx * std::tan(theta - tilt);
  auto rowDistance = [&](double v) { return h / std::tan(tilt + std::atan((v - in.cy) / in.fy)); };
  const double up = rowDistance(v0 - 1) - d, down = d - rowDistance(v0 + 1);

  const auto across = groundMetresPerPixel(*camera, Segment2{{d, -0.5}, {d, 0.5}});
  ASSERT_TRUE(across);
  EXPECT_GE(*across, std::min(up, down) - 1e-9);
  EXPECT_LE(*across, std::max(up, down) + 1e-9);
  EXPECT_NEAR(*across, 0.071, 0.001);

  const auto along = groundMetresPerPixel(*camera, Segment2{{d - 0.5, 0.0}, {d + 0.5, 0.0}});
  ASSERT_TRUE(along);
  EXPECT_NEAR(*along, std::hypot(d, h) * std::cos(theta - tilt) / in.fx, 1e-9);

  // Behind the camera: not seen.
  EXPECT_FALSE(groundMetresPerPixel(*camera, Segment2{{-3.0, -0.5}, {-3.0, 0.5}}));
}

TEST(LineMatching, NoLinesGiveNothing) { EXPECT_FALSE(fitPoseToLines(kPrior, {})); }

// ---------------------------------------------------------------------------------------------
// PoseFilter

Mat3 diagonalCovariance(double sigma_m, double sigma_deg) {
  return Vec3(sigma_m * sigma_m, sigma_m * sigma_m, std::pow(degToRad(sigma_deg), 2)).asDiagonal();
}

TEST(MatchingFilter, OdometryOnlyDriftGrowsTheCovariance) {
  PoseFilter filter(Pose2(0, 0, 0), diagonalCovariance(0.01, 0.5));
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

// ---------------------------------------------------------------------------------------------
// localize: the Map module's step

// A Prediction holding the scene's interest segments (what predictView would give near the
// crossing), and the DetectedObject a detector at `truth` would report of `lines`.
Prediction scenePrediction() {
  Prediction p;
  const std::pair<const char*, Segment2> segments[] = {{"R1.left.0", kLeft},      {"R1.right.0", kRight},
                                                       {"R2.near.0", kCrossNear}, {"R2.far.0", kCrossFar},
                                                       {"R3.near.0", kCrossNear}};
  for (const auto& [id, world] : segments) {
    InterestSegment s;
    s.id = id;
    p.view.segments.push_back(s);
    p.segments_world.push_back(world);
  }
  return p;
}

DetectedObject detectedFrom(const std::vector<LineCorrespondence>& lines, double timestamp) {
  DetectedObject d;
  d.timestamp = timestamp;
  d.confidence = 1;
  for (const LineCorrespondence& c : lines) {
    DetectedLine l;
    l.label = c.id;
    l.score = 1;
    l.vehicle = c.detected_vehicle;
    d.lines.push_back(l);
  }
  return d;
}

TEST(MatchingLocalize, EdgesCorrectLateralAndHeadingAndTheCrossingCorrectsAlong) {
  // Driving along the road at y = 0.3 from x = 0, 0.5 m a frame, odometry 2 % long (a bias the noise model
  // covers only as random error). The road edges
  // are seen every frame (2 cm noise); the crossing at x = 19..21 once within 9 m of it.
  const Prediction prediction = scenePrediction();
  const Pose2 start(0, 0.3, 0);
  PoseFilter filter(Pose2(0, 0.2, degToRad(1.0)), diagonalCovariance(0.1, 2.0));
  std::mt19937_64 rng(5);
  double worst_lateral = 0, along_before = 0, along_after = 0, sigma_along_before = 0, sigma_along_after = 0;
  for (int k = 1; k <= 24; ++k) {
    const Pose2 truth(start.x() + 0.5 * k, start.y(), 0);
    std::vector<LineCorrespondence> seen = roadEdges(truth, 0.02, &rng);
    const bool crossing_in_view = 19 - truth.x() < 9;
    if (crossing_in_view) {
      for (const LineCorrespondence& c : crossingEdges(truth, 0.02, &rng)) seen.push_back(c);
    }
    const CurrentPosition out = localize(filter, {0.5 * 1.02, 0.0}, prediction, detectedFrom(seen, 0.1 * k));
    ASSERT_EQ(out.status, PositionStatus::Corrected) << "frame " << k << ": " << out.reason;
    const Vec3 e = poseError(out.pose, truth);
    EXPECT_TRUE(out.observed_lateral && out.observed_heading);
    EXPECT_EQ(out.observed_along, crossing_in_view) << "frame " << k;
    // Every frame's lateral and heading errors within 4 reported sigmas.
    EXPECT_LT(std::abs(e.y()), 4 * std::sqrt(out.covariance(1, 1))) << "frame " << k;
    EXPECT_LT(std::abs(e.z()), 4 * std::sqrt(out.covariance(2, 2))) << "frame " << k;
    if (!crossing_in_view) {
      if (k >= 10) worst_lateral = std::max(worst_lateral, std::abs(e.y()));  // once settled
      along_before = e.x();
      sigma_along_before = std::sqrt(out.covariance(0, 0));
      EXPECT_NE(out.reason.find("along-road position from odometry"), std::string::npos) << out.reason;
    } else {
      along_after = e.x();
      sigma_along_after = std::sqrt(out.covariance(0, 0));
    }
  }
  std::printf("edges only: lateral error <= %.4f m (from frame 10), along error grew to %.3f m (sigma %.3f m); "
              "after the crossing came into view: %.4f m (sigma %.4f m)\n",
              worst_lateral, along_before, sigma_along_before, along_after, sigma_along_after);
  EXPECT_LT(worst_lateral, 0.03);  // 1 cm sigma by then
  EXPECT_GT(along_before, 0.15);  // 2 % of 10 m, carried by odometry
  EXPECT_LT(std::abs(along_before), 3 * sigma_along_before);  // and covered by the covariance
  EXPECT_LT(std::abs(along_after), 0.05);
  EXPECT_LT(std::abs(along_after), 4 * sigma_along_after);
}

TEST(MatchingLocalize, NoUsableLinesLeaveThePoseToOdometry) {
  const Prediction prediction = scenePrediction();
  PoseFilter filter(kTruth, diagonalCovariance(0.05, 1.0));
  const CurrentPosition failed =
      localize(filter, {1.0, 0.0}, prediction, DetectedObject::failed("frame over-exposed"));
  EXPECT_EQ(failed.status, PositionStatus::OdometryOnly);
  EXPECT_NE(failed.reason.find("vision failed (frame over-exposed)"), std::string::npos) << failed.reason;
  const double h = kTruth.heading();
  EXPECT_POSE_NEAR(failed.pose, Pose2(kTruth.x() + std::cos(h), kTruth.y() + std::sin(h), h), 1e-12);

  DetectedObject unknown = detectedFrom(roadEdges(filter.pose(), 0.05), 2.0);
  for (DetectedLine& l : unknown.lines) l.label = "R9.left.0";  // not in the prediction
  const CurrentPosition none = localize(filter, {0.0, 0.0}, prediction, unknown);
  EXPECT_EQ(none.status, PositionStatus::OdometryOnly);
  EXPECT_NE(none.reason.find("no usable lines"), std::string::npos) << none.reason;
  EXPECT_EQ(none.lines_used, 0);
  EXPECT_DOUBLE_EQ(none.timestamp, 2.0);
}

TEST(MatchingLocalize, ParkModeCentreLineCorrectsLateralAndHeadingNotAlong) {
  // The cross of four roads: R1 runs from (0, 0) east. The vehicle is at (8, 0.3) heading 3 degrees
  // left; the filter thinks (8.5, 0), heading 0, with 0.5 m / 5 degree sigmas. Vision finds the
  // centre line 2 to 8 m ahead and no labelled edge.
  const Map map(testing::crossOfFourRoads());
  const Pose2 truth(8.0, 0.3, degToRad(3.0));
  const Pose2 prior(8.5, 0.0, 0.0);
  PoseFilter filter(prior, diagonalCovariance(0.5, 5.0));
  DetectedObject d;
  d.timestamp = 1.0;
  d.centerline_vehicle = truth.inverse().transform(Segment2{{10, 0}, {16, 0}});
  const CurrentPosition out = localize(filter, {0.0, 0.0}, Prediction{}, d, {}, &map);
  ASSERT_EQ(out.status, PositionStatus::Corrected) << out.reason;
  const Vec3 e = poseError(out.pose, truth);
  std::printf("park mode: %s; errors along %+.4f m, lateral %+.4f m, heading %+.4f deg\n", out.reason.c_str(), e.x(),
              e.y(), radToDeg(e.z()));
  EXPECT_NE(out.reason.find("park mode"), std::string::npos);
  EXPECT_NEAR(out.pose.x(), prior.x(), 1e-9);  // along: untouched
  EXPECT_LT(std::abs(e.y()), 0.01);            // lateral: from 0.3 m to under 1 cm
  EXPECT_LT(std::abs(radToDeg(e.z())), 0.1);   // heading: from 3 degrees to under 0.1
  EXPECT_TRUE(out.observed_lateral);
  EXPECT_TRUE(out.observed_heading);
  EXPECT_FALSE(out.observed_along);
  EXPECT_EQ(out.lines_used, 1);

  // Without the map (or far from every road) there is nothing to match.
  PoseFilter lost(Pose2(8.5, 9.0, 0.0), diagonalCovariance(0.5, 5.0));
  EXPECT_EQ(localize(lost, {0.0, 0.0}, Prediction{}, d, {}, &map).status, PositionStatus::OdometryOnly);
  EXPECT_EQ(localize(filter, {0.0, 0.0}, Prediction{}, d).status, PositionStatus::OdometryOnly);
}

TEST(MatchingOnCurve, PiecewiseEdgesFollowTheCurveWhereThePredictedChordsDoNot) {
  // On the campus' R5, a 35 m radius curve, the vehicle 20 m from I4 facing along the road. Vision's
  // lines are short chords of the edges (2.4 m: 2 cm from the curve, as the image polygon's 3 px
  // tolerance gives), breaking at other places than the prediction's 5 m chords (0.1 m tolerance).
  const Map campus = loadMap(testing::mapPath("cmu_campus.json"));
  const Road& r5 = campus.road("R5");
  const Pose2 truth(r5.centerline.pointAt(20.0), r5.centerline.headingAt(20.0));
  const auto camera = testing::terregatorPinhole();
  const Prediction prediction = predictView(campus, truth, *camera);
  DetectedObject detected;
  for (std::size_t i = 0; i < prediction.view.segments.size(); ++i) {
    const InterestSegment& s = prediction.view.segments[i];
    if (s.owner != "R5" || s.side == "corner") continue;
    const Polyline2& edge = s.side == "left" ? campus.leftEdge(r5) : campus.rightEdge(r5);
    const double sa = edge.project(prediction.segments_world[i].a).arc_length;
    const double sb = edge.project(prediction.segments_world[i].b).arc_length;
    for (double s0 = std::min(sa, sb) + 0.7; s0 + 2.4 <= std::max(sa, sb); s0 += 2.4) {
      DetectedLine line;
      line.label = s.id;
      line.vehicle = truth.inverse().transform(Segment2{edge.pointAt(s0), edge.pointAt(s0 + 2.4)});
      detected.lines.push_back(line);
    }
  }
  ASSERT_GE(detected.lines.size(), 4u);
  const auto chords = labelledCorrespondences(prediction, detected, 0.05, 0.3);
  const auto pieces = edgeCorrespondences(campus, prediction, detected, truth, 0.05, 0.3, 1.0);
  EXPECT_GT(pieces.size(), chords.size());
  auto worst = [&](const std::vector<LineCorrespondence>& lines) {  // largest end-point distance at the truth
    double d = 0;
    for (const LineCorrespondence& c : lines) {
      const Segment2 w = truth.transform(c.detected_vehicle);
      const Vec2 n = leftNormal((c.map_world.b - c.map_world.a).normalized());
      d = std::max({d, std::abs(n.dot(w.a - c.map_world.a)), std::abs(n.dot(w.b - c.map_world.a))});
    }
    return d;
  };
  std::printf("on the curve: end points up to %.3f m off the predicted chords, %.3f m off the edge pieces\n",
              worst(chords), worst(pieces));
  EXPECT_LT(worst(pieces), 0.025);
  EXPECT_GT(worst(chords), 2 * worst(pieces));
  // Fitted from the truth, the pieces stay on it; the chords pull it away.
  const auto fit_pieces = fitPoseToLines(truth, pieces);
  const auto fit_chords = fitPoseToLines(truth, chords);
  ASSERT_TRUE(fit_pieces && fit_chords);
  const Vec3 e_pieces = poseError(fit_pieces->pose, truth), e_chords = poseError(fit_chords->pose, truth);
  std::printf("fit from the truth: pieces off by %.4f m, %.3f deg; chords by %.4f m, %.3f deg\n",
              e_pieces.head<2>().norm(), radToDeg(std::abs(e_pieces.z())), e_chords.head<2>().norm(),
              radToDeg(std::abs(e_chords.z())));
  EXPECT_LT(e_pieces.head<2>().norm(), 0.02);
  EXPECT_LT(std::abs(radToDeg(e_pieces.z())), 0.1);
  EXPECT_GT(e_chords.head<2>().norm() + std::abs(e_chords.z()), e_pieces.head<2>().norm() + std::abs(e_pieces.z()));

  LocalizeOptions options;
  EXPECT_EQ(options.curve_piece_m, 0.0);  // opt-in: the chords unless asked
  options.curve_piece_m = -1;
  EXPECT_THROW(options.validate(), InvalidInput);
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

// ---------------------------------------------------------------------------------------------
// Re-association

// A left road edge with a notch (as where a road meets a narrower one): y = 1, a recess to
// y = 1.3 for 10 <= x <= 12, y = 1 again up to the crossing at x = 19.
const Polyline2 kNotchedLeft({{-5, 1}, {10, 1}, {10, 1.3}, {12, 1.3}, {12, 1}, {19, 1}});

std::vector<Segment2> segmentsOf(const Polyline2& line) {
  std::vector<Segment2> out;
  for (std::size_t i = 0; i < line.segmentCount(); ++i) out.push_back(line.segment(i));
  return out;
}

// The notched edge seen before, in and after the notch, the right edge and the crossing; the
// left pieces carry the notched edge's segments as candidates and, as their first map line, the
// segment nearest to their midpoint placed by `prior` (as edgeCorrespondences picks it).
std::vector<LineCorrespondence> notchScene(const Pose2& truth, const Pose2& prior) {
  std::vector<LineCorrespondence> lines;
  const std::vector<Segment2> candidates = segmentsOf(kNotchedLeft);
  for (const auto& [id, seen] : {std::pair<const char*, Segment2>{"R1.left.0", {{4, 1}, {9.6, 1}}},
                                 std::pair<const char*, Segment2>{"R1.left.1", {{10.3, 1.3}, {11.7, 1.3}}},
                                 std::pair<const char*, Segment2>{"R1.left.2", {{12.3, 1}, {16, 1}}}}) {
    LineCorrespondence c = detect(id, truth, seen, Segment2{}, 0.05);
    const Vec2 mid = prior.transform(c.detected_vehicle.pointAt(0.5));
    c.map_world = kNotchedLeft.segment(kNotchedLeft.project(mid).segment);
    c.candidates = candidates;
    lines.push_back(c);
  }
  lines.push_back(detect("R1.right.0", truth, {{4, -1}, {16, -1}}, kRight, 0.05));
  for (const LineCorrespondence& c : crossingEdges(truth, 0.05)) lines.push_back(c);
  return lines;
}

const Pose2 kNotchTruth(3.0, 0.1, degToRad(2.0));
// 2 m along, 0.1 m across and 1 degree off: the notch piece (midpoint at x = 11 in truth) lands at
// x = 13, 0.34 m from the edge after the notch and 1 m from the notch.
const Pose2 kNotchPrior(5.0, 0.0, degToRad(3.0));

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
