// The pose filter's landmark update: range and bearing to a mapped landmark.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "mapnav/core/error.h"
#include "mapnav/localization/pose_filter.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

// A covariance with sigmas along x, y (m) and heading (deg).
Mat3 covarianceOf(double sx, double sy, double s_deg) { return Vec3(sx * sx, sy * sy, std::pow(degToRad(s_deg), 2)).asDiagonal(); }

// What a camera at `origin` (vehicle frame) on a vehicle at `truth` measures of a landmark at `p`.
LandmarkObservation seen(const std::string& id, const Vec2& p, const Pose2& truth, double range_sigma, double bearing_sigma,
                         const Vec2& origin = Vec2::Zero()) {
  const Vec2 d = truth.inverseTransform(p) - origin;
  LandmarkObservation o;
  o.id = id;
  o.map_world = p;
  o.origin_vehicle = origin;
  o.range_m = d.norm();
  o.bearing_rad = std::atan2(d.y(), d.x());
  o.covariance = Vec2(range_sigma * range_sigma, bearing_sigma * bearing_sigma).asDiagonal();
  return o;
}

// The measurement (range, bearing) of landmark p from the origin of a vehicle at pose q.
Vec2 rangeBearing(const Pose2& q, const Vec2& p, const Vec2& origin = Vec2::Zero()) {
  const Vec2 d = q.inverseTransform(p) - origin;
  return Vec2(d.norm(), std::atan2(d.y(), d.x()));
}

// Its Jacobian over (x, y, heading) by central differences.
Eigen::Matrix<double, 2, 3> numericJacobian(const Pose2& q, const Vec2& p, const Vec2& origin = Vec2::Zero()) {
  const double eps = 1e-6;
  Eigen::Matrix<double, 2, 3> j;
  for (int k = 0; k < 3; ++k) {
    Vec3 dv = Vec3::Zero();
    dv(k) = eps;
    const Pose2 plus(q.x() + dv(0), q.y() + dv(1), q.heading() + dv(2));
    const Pose2 minus(q.x() - dv(0), q.y() - dv(1), q.heading() - dv(2));
    j.col(k) = (rangeBearing(plus, p, origin) - rangeBearing(minus, p, origin)) / (2 * eps);
  }
  return j;
}

FilterOptions poseOnly() {
  FilterOptions options;
  options.motion.scale_sigma = 0;
  options.motion.gyro_bias_sigma_deg_s = 0;
  return options;
}

TEST(LandmarkUpdate, ALandmarkAheadFixesTheAlongRoadErrorAsTheInformationFormSays) {
  // The estimate 0.6 m ahead of the truth, unsure along (0.5 m), sure across (0.05 m).
  const Pose2 prior(20.6, 0, 0), truth(20, 0, 0);
  const Mat3 p = covarianceOf(0.5, 0.05, 0.5);
  PoseFilter filter(prior, p, poseOnly());
  const LandmarkObservation o = seen("T1", Vec2(28, 3), truth, 0.05, degToRad(0.3));
  const auto result = filter.updateLandmarks({o});
  ASSERT_EQ(result.used.size(), 1u);
  EXPECT_TRUE(result.rejected.empty());
  // One EKF step in information form, independently: P+ = (P^-1 + H^T R^-1 H)^-1 and
  // x+ = x + P+ H^T R^-1 (z - h(x)), H by numerical differences at the prior.
  const Eigen::Matrix<double, 2, 3> h = numericJacobian(prior, o.map_world);
  const Mat2 r_inv = o.covariance.inverse();
  const Mat3 posterior = (p.inverse() + h.transpose() * r_inv * h).inverse();
  const Vec2 innovation = Vec2(o.range_m, o.bearing_rad) - rangeBearing(prior, o.map_world);
  const Vec3 expected = Vec3(prior.x(), prior.y(), prior.heading()) + posterior * h.transpose() * r_inv * innovation;
  EXPECT_NEAR(filter.pose().x(), expected(0), 1e-6);
  EXPECT_NEAR(filter.pose().y(), expected(1), 1e-6);
  EXPECT_NEAR(filter.pose().heading(), expected(2), 1e-8);
  EXPECT_TRUE(filter.covariance().isApprox(posterior, 1e-6)) << filter.covariance() << "\n" << posterior;
  // And what that means: most of the 0.6 m along error is gone, the along sigma from 0.5 m to 6 cm.
  EXPECT_LT(std::abs(filter.pose().x() - truth.x()), 0.1);
  EXPECT_LT(std::sqrt(filter.covariance()(0, 0)), 0.06);
  EXPECT_TRUE(result.information.isApprox(h.transpose() * r_inv * h, 1e-5));
}

TEST(LandmarkUpdate, TheJacobianMatchesNumericalDifferencesWithTheCameraOffTheVehiclesOrigin) {
  // With a prior P = sigma^2 I far tighter than R = I, a measurement offset dz moves the state by
  // about sigma^2 H^T dz: H read off the update, compared with numerical differences.
  const Vec2 p(7, -4), origin(0.4, 0.1);
  const Pose2 pose(1, 2, 0.3);
  const Eigen::Matrix<double, 2, 3> numeric = numericJacobian(pose, p, origin);
  const double sigma = 1e-3, dz = 0.01;
  for (int row = 0; row < 2; ++row) {
    PoseFilter filter(pose, Mat3::Identity() * sigma * sigma, poseOnly());
    LandmarkObservation o = seen("L", p, pose, 1.0, 1.0, origin);
    (row == 0 ? o.range_m : o.bearing_rad) += dz;
    ASSERT_EQ(filter.updateLandmarks({o}).used.size(), 1u);
    const Vec3 step(filter.pose().x() - pose.x(), filter.pose().y() - pose.y(), filter.pose().heading() - pose.heading());
    const Vec3 expected = sigma * sigma * numeric.row(row).transpose() * dz;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(step(k), expected(k), 1e-3 * expected.norm()) << row << " " << k;
  }
}

TEST(LandmarkUpdate, AnObservationBeyondTheGateIsRejectedAndLeavesTheFilterAsItWas) {
  PoseFilter filter(Pose2(20, 0, 0), covarianceOf(0.1, 0.05, 0.5), FilterOptions{});
  const Pose2 before = filter.pose();
  const StateMatrix covariance = filter.fullCovariance();
  // Seen as if the vehicle were 3 m further on: 30 sigma along.
  const auto result = filter.updateLandmarks({seen("P7", Vec2(30, 2), Pose2(23, 0, 0), 0.05, degToRad(0.3))});
  EXPECT_TRUE(result.used.empty());
  ASSERT_EQ(result.rejected.size(), 1u);
  EXPECT_EQ(result.rejected[0], "P7");
  EXPECT_EQ(filter.pose().x(), before.x());
  EXPECT_EQ(filter.fullCovariance(), covariance);
  EXPECT_EQ(result.information, Mat3::Zero());
}

TEST(LandmarkUpdate, LandmarksAlongAStraightRoadEstimateTheOdometryScale) {
  // 40 steps of 0.5 m read as 0.5 / 1.03 (the encoders read 3 % short), a landmark every 10 m.
  PoseFilter filter(Pose2(0, 0, 0), covarianceOf(0.01, 0.01, 0.2), FilterOptions{});
  const double truth_step = 0.5, reading = 0.5 / 1.03;
  std::vector<Vec2> landmarks;
  for (int k = 1; k <= 6; ++k) landmarks.emplace_back(10.0 * k, k % 2 == 0 ? 2.5 : -2.5);
  for (int i = 1; i <= 100; ++i) {
    filter.predict({reading, 0.0}, 0.1);
    const Pose2 truth(truth_step * i, 0, 0);
    if (i % 10 != 0) continue;
    std::vector<LandmarkObservation> in_view;
    for (std::size_t k = 0; k < landmarks.size(); ++k) {
      const Vec2 d = truth.inverseTransform(landmarks[k]);
      if (d.x() > 2 && d.x() < 12) in_view.push_back(seen("L" + std::to_string(k), landmarks[k], truth, 0.05, degToRad(0.3)));
    }
    filter.updateLandmarks(in_view);
  }
  EXPECT_NEAR(filter.pose().x(), 50.0, 0.05);
  EXPECT_NEAR(filter.scaleError(), 0.03, 0.006);  // the true distance is 1.03 times the reading
}

TEST(LandmarkUpdate, UpdatedErrorsAreWithinTheReportedCovariance) {
  // 200 seeded trials: the normalised error squared of (x, y, heading) after one landmark update
  // has mean 3 (the chi-square with 3 dof), the filter neither over- nor under-confident.
  std::mt19937 rng(7);
  std::normal_distribution<double> n01;
  double sum = 0;
  const int trials = 200;
  const Mat3 prior = covarianceOf(0.3, 0.1, 1.0);
  for (int t = 0; t < trials; ++t) {
    const Pose2 truth(10, 5, 0.4);
    const Pose2 start(truth.x() + 0.3 * n01(rng), truth.y() + 0.1 * n01(rng), truth.heading() + degToRad(1.0) * n01(rng));
    PoseFilter filter(start, prior, poseOnly());
    std::vector<LandmarkObservation> obs;
    for (const Vec2& p : {Vec2(16, 10), Vec2(19, 6)}) {
      LandmarkObservation o = seen("L", p, truth, 0.08, degToRad(0.5));
      o.range_m += 0.08 * n01(rng);
      o.bearing_rad += degToRad(0.5) * n01(rng);
      obs.push_back(o);
    }
    filter.updateLandmarks(obs);
    Vec3 e(filter.pose().x() - truth.x(), filter.pose().y() - truth.y(), normalizeAngle(filter.pose().heading() - truth.heading()));
    sum += e.dot(filter.covariance().ldlt().solve(e));
  }
  EXPECT_NEAR(sum / trials, 3.0, 0.6);
}

TEST(LandmarkUpdate, ANonFiniteMeasurementIsRefusedNamingTheLandmark) {
  PoseFilter filter(Pose2(0, 0, 0), covarianceOf(0.1, 0.1, 0.5), FilterOptions{});
  LandmarkObservation o = seen("T3", Vec2(5, 1), Pose2(0, 0, 0), 0.05, 0.01);
  o.range_m = std::nan("");
  try {
    filter.updateLandmarks({o});
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("landmark \"T3\""), std::string::npos) << e.what();
  }
  o = seen("T3", Vec2(5, 1), Pose2(0, 0, 0), 0.05, 0.01);
  o.covariance(0, 0) = -1;
  EXPECT_THROW(filter.updateLandmarks({o}), InvalidInput);
}

}  // namespace
}  // namespace mapnav
