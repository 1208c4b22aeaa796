#include "mapnav/geometry/pose2.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "mapnav/testing/support.h"

namespace mapnav {
namespace {


constexpr double kTol = 1e-12;

TEST(Pose2, NormalizeAngleWrapsIntoHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(normalizeAngle(0.0), 0.0);
  EXPECT_DOUBLE_EQ(normalizeAngle(0.5 + 2 * kPi), 0.5);
  EXPECT_NEAR(normalizeAngle(0.5 - 6 * kPi), 0.5, 1e-14);
  EXPECT_DOUBLE_EQ(normalizeAngle(kPi), kPi);
  EXPECT_DOUBLE_EQ(normalizeAngle(-kPi), kPi);  // -pi is excluded
  EXPECT_NEAR(normalizeAngle(3 * kPi), kPi, 1e-14);
  EXPECT_NEAR(normalizeAngle(-1.5 * kPi), 0.5 * kPi, 1e-14);
  EXPECT_NEAR(normalizeAngle(7.0), 7.0 - 2 * kPi, 1e-14);
  EXPECT_NEAR(normalizeAngle(-4.0), -4.0 + 2 * kPi, 1e-14);
}

TEST(Pose2, ConstructorNormalizesHeading) {
  EXPECT_NEAR(Pose2(1, 2, 1.5 * kPi).heading(), -0.5 * kPi, 1e-14);
  EXPECT_DOUBLE_EQ(Pose2(0, 0, -kPi).heading(), kPi);
  EXPECT_DOUBLE_EQ(Pose2(Vec2(3, 4), kPi).heading(), kPi);
  EXPECT_EQ(Pose2(Vec2(3, 4), 0.25).translation(), Vec2(3, 4));
  EXPECT_EQ(Pose2().translation(), Vec2::Zero());
  EXPECT_EQ(Pose2::identity().heading(), 0.0);
}

TEST(Pose2, ComposeKnownPoses) {
  const Pose2 a(1, 2, kPi / 2), b(3, 0, 0);
  // a * b: t = (1, 2) + R(90°)(3, 0) = (1, 5)
  EXPECT_POSE_NEAR(a * b, Pose2(1, 5, kPi / 2), kTol);
  // b * a: t = (3, 0) + (1, 2) = (4, 2)
  EXPECT_POSE_NEAR(b * a, Pose2(4, 2, kPi / 2), kTol);
  // Two quarter turns: (1, 0) + R(90°)(1, 0) = (1, 1), heading pi.
  const Pose2 q(1, 0, kPi / 2);
  const Pose2 qq = q * q;
  EXPECT_POSE_NEAR(qq, Pose2(1, 1, kPi), kTol);
  EXPECT_GT(qq.heading(), 0.0);  // pi, never -pi
  // Headings wrap: 3 * 120° = 360° = 0.
  const Pose2 r(0, 0, degToRad(120));
  EXPECT_NEAR((r * r * r).heading(), 0.0, 1e-12);
}

TEST(Pose2, InverseOfKnownPose) {
  // R(-90°)(1, 2) = (2, -1), so the inverse translation is (-2, 1).
  EXPECT_POSE_NEAR(Pose2(1, 2, kPi / 2).inverse(), Pose2(-2, 1, -kPi / 2), kTol);
  EXPECT_POSE_NEAR(Pose2(5, -3, 0).inverse(), Pose2(-5, 3, 0), kTol);
  EXPECT_DOUBLE_EQ(Pose2(0, 0, kPi).inverse().heading(), kPi);
}

TEST(Pose2, TransformOfSpecificPoints) {
  const Pose2 p(2, 1, kPi / 2);
  EXPECT_VEC2_NEAR(p.transform(Vec2(1, 0)), Vec2(2, 2), kTol);
  EXPECT_VEC2_NEAR(p.transform(Vec2(0, 1)), Vec2(1, 1), kTol);
  EXPECT_VEC2_NEAR(p.transform(Vec2(0, 0)), Vec2(2, 1), kTol);
  EXPECT_VEC2_NEAR(p.inverseTransform(Vec2(2, 2)), Vec2(1, 0), kTol);
  EXPECT_VEC2_NEAR(p.inverseTransform(Vec2(2, 1)), Vec2(0, 0), kTol);
  EXPECT_VEC2_NEAR(p.rotate(Vec2(1, 0)), Vec2(0, 1), kTol);  // no translation
  const Segment2 s = p.transform(Segment2{Vec2(1, 0), Vec2(0, 1)});
  EXPECT_VEC2_NEAR(s.a, Vec2(2, 2), kTol);
  EXPECT_VEC2_NEAR(s.b, Vec2(1, 1), kTol);
  // 30°: (1, 0) goes to (cos 30°, sin 30°).
  EXPECT_VEC2_NEAR(Pose2(0, 0, degToRad(30)).transform(Vec2(2, 0)), Vec2(std::sqrt(3.0), 1.0), kTol);
}

TEST(Pose2, RotationAndMatrix) {
  const Pose2 p(3, -1, kPi / 2);
  Mat2 r;
  r << 0, -1, 1, 0;
  EXPECT_TRUE(p.rotation().isApprox(r, 1e-15)) << p.rotation();
  Mat3 m;
  m << 0, -1, 3, 1, 0, -1, 0, 0, 1;
  EXPECT_LT((p.matrix() - m).norm(), 1e-15) << p.matrix();
}

TEST(Pose2, ExpOfKnownTwists) {
  // Quarter circle of radius 2/pi (v = 1, omega = pi/2): ends at (r, r) facing +y.
  const double r = 2 / kPi;
  EXPECT_POSE_NEAR(Pose2::exp(Pose2::Tangent(1, 0, kPi / 2)), Pose2(r, r, kPi / 2), kTol);
  // Half circle with v = pi: radius 1, ends at (0, 2) facing -x.
  EXPECT_POSE_NEAR(Pose2::exp(Pose2::Tangent(kPi, 0, kPi)), Pose2(0, 2, kPi), kTol);
  // Pure translation.
  EXPECT_POSE_NEAR(Pose2::exp(Pose2::Tangent(3, -1, 0)), Pose2(3, -1, 0), kTol);
  // Tiny rotation takes the series branch: y ≈ v·omega/2.
  const Pose2 small = Pose2::exp(Pose2::Tangent(1, 0, 1e-9));
  EXPECT_NEAR(small.x(), 1.0, 1e-15);
  EXPECT_NEAR(small.y(), 5e-10, 1e-20);
  EXPECT_NEAR(small.heading(), 1e-9, 1e-24);
}

TEST(Pose2, LogOfKnownPoses) {
  const double r = 2 / kPi;
  EXPECT_LT((Pose2(r, r, kPi / 2).log() - Pose2::Tangent(1, 0, kPi / 2)).norm(), 1e-12);
  EXPECT_LT((Pose2(0, 2, kPi).log() - Pose2::Tangent(kPi, 0, kPi)).norm(), 1e-12);
  EXPECT_LT((Pose2(3, -1, 0).log() - Pose2::Tangent(3, -1, 0)).norm(), 1e-15);
  const Pose2::Tangent tiny = Pose2(1, 5e-10, 1e-9).log();
  EXPECT_NEAR(tiny.x(), 1.0, 1e-15);
  EXPECT_NEAR(tiny.y(), 0.0, 1e-18);
  EXPECT_NEAR(tiny.z(), 1e-9, 1e-24);
}

class Pose2Random : public ::testing::Test {
 protected:
  std::mt19937 rng{20240611};
  Pose2 randomPose() {
    std::uniform_real_distribution<double> xy(-100, 100), h(-kPi, kPi);
    return {xy(rng), xy(rng), h(rng)};
  }
  Vec2 randomPoint() {
    std::uniform_real_distribution<double> xy(-50, 50);
    return {xy(rng), xy(rng)};
  }
};

TEST_F(Pose2Random, ComposeThenInverseIsIdentity) {
  for (int k = 0; k < 1000; ++k) {
    const Pose2 p = randomPose();
    EXPECT_POSE_NEAR(p * p.inverse(), Pose2::identity(), 1e-12);
    EXPECT_POSE_NEAR(p.inverse() * p, Pose2::identity(), 1e-12);
    EXPECT_POSE_NEAR(p.inverse().inverse(), p, 1e-12);
  }
}

TEST_F(Pose2Random, CompositionIsAssociativeAndActsOnPoints) {
  for (int k = 0; k < 1000; ++k) {
    const Pose2 a = randomPose(), b = randomPose(), c = randomPose();
    EXPECT_POSE_NEAR((a * b) * c, a * (b * c), 1e-10);
    const Vec2 x = randomPoint();
    EXPECT_VEC2_NEAR((a * b).transform(x), a.transform(b.transform(x)), 1e-10);
    const Vec3 h = a.matrix() * Vec3(x.x(), x.y(), 1.0);
    EXPECT_VEC2_NEAR(a.transform(x), Vec2(h.x(), h.y()), 1e-10);
    EXPECT_TRUE((a * b).matrix().isApprox(a.matrix() * b.matrix(), 1e-12));
  }
}

TEST_F(Pose2Random, TransformAndInverseTransformRoundTrip) {
  for (int k = 0; k < 1000; ++k) {
    const Pose2 p = randomPose();
    const Vec2 x = randomPoint();
    EXPECT_VEC2_NEAR(p.inverseTransform(p.transform(x)), x, 1e-11);
    EXPECT_VEC2_NEAR(p.transform(p.inverseTransform(x)), x, 1e-11);
    EXPECT_VEC2_NEAR(p.inverseTransform(x), p.inverse().transform(x), 1e-11);
    EXPECT_NEAR(p.rotate(x).norm(), x.norm(), 1e-11);
  }
}

TEST_F(Pose2Random, ExpOfLogIsIdentity) {
  for (int k = 0; k < 1000; ++k) {
    const Pose2 p = randomPose();
    EXPECT_POSE_NEAR(Pose2::exp(p.log()), p, 1e-10);
  }
  // Headings at and next to the ends of the range, and tiny ones (series branches).
  for (double h : {kPi, -kPi + 1e-12, 1e-7, -1e-7, 1e-5, 0.0}) {
    const Pose2 p(7, -3, h);
    EXPECT_POSE_NEAR(Pose2::exp(p.log()), p, 1e-12) << "heading " << h;
  }
}

TEST_F(Pose2Random, LogOfExpIsIdentity) {
  std::uniform_real_distribution<double> v(-10, 10), w(-kPi + 1e-6, kPi - 1e-6);
  for (int k = 0; k < 1000; ++k) {
    const Pose2::Tangent xi(v(rng), v(rng), w(rng));
    const Pose2::Tangent back = Pose2::exp(xi).log();
    EXPECT_LT((back - xi).norm(), 1e-10) << xi.transpose() << " -> " << back.transpose();
  }
}

TEST_F(Pose2Random, InterpolateHitsEndpoints) {
  for (int k = 0; k < 1000; ++k) {
    const Pose2 a = randomPose(), b = randomPose();
    EXPECT_POSE_NEAR(Pose2::interpolate(a, b, 0.0), a, 1e-10);
    EXPECT_POSE_NEAR(Pose2::interpolate(a, b, 1.0), b, 1e-10);
  }
}

TEST(Pose2, InterpolateMidpoints) {
  // Pure rotation about a fixed point.
  EXPECT_POSE_NEAR(Pose2::interpolate(Pose2(1, 1, 0), Pose2(1, 1, kPi / 2), 0.5), Pose2(1, 1, kPi / 4), kTol);
  // Pure translation.
  EXPECT_POSE_NEAR(Pose2::interpolate(Pose2(0, 0, kPi / 2), Pose2(0, 4, kPi / 2), 0.5), Pose2(0, 2, kPi / 2), kTol);
  EXPECT_POSE_NEAR(Pose2::interpolate(Pose2(0, 0, kPi / 2), Pose2(0, 4, kPi / 2), 0.25), Pose2(0, 1, kPi / 2),
                   kTol);
  // Along the quarter circle of radius 2/pi: 45° of it is (r sin 45°, r (1 - cos 45°)).
  const double r = 2 / kPi, s45 = std::sqrt(0.5);
  EXPECT_POSE_NEAR(Pose2::interpolate(Pose2(), Pose2(r, r, kPi / 2), 0.5), Pose2(r * s45, r * (1 - s45), kPi / 4),
                   kTol);
  // Across the ±pi seam the short way round: 170° and -170° meet at 180°.
  EXPECT_POSE_NEAR(Pose2::interpolate(Pose2(0, 0, degToRad(170)), Pose2(0, 0, degToRad(-170)), 0.5),
                   Pose2(0, 0, kPi), 1e-12);
}

}  // namespace
}  // namespace mapnav
