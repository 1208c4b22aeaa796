// The GNSS receiver model (logs/gnss.h) against the statistics of its definition: white noise of
// sigma_m, a first-order Gauss-Markov bias of steady sigma bias_sigma_m whose correlation over dt is
// exp(-dt / bias_time_s), the stated sigma, the same bytes for the same seed, bad options named.
#include "mapnav/logs/gnss.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

constexpr int kFixes = 20000;

// The fixes' errors (fix - truth) of one axis at 1 s intervals.
std::vector<double> xErrors(const GnssReceiverOptions& options, double dt = 1.0) {
  GnssReceiver receiver(options);
  std::vector<double> e;
  const Vec2 truth(10, -5);
  for (int k = 0; k < kFixes; ++k) e.push_back(receiver.measure(truth, k * dt).position.x() - truth.x());
  return e;
}

double meanOf(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

double sdOf(const std::vector<double>& v) {
  const double m = meanOf(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

// The lag-1 autocorrelation.
double lagOne(const std::vector<double>& v) {
  const double m = meanOf(v);
  double num = 0, den = 0;
  for (std::size_t k = 0; k + 1 < v.size(); ++k) num += (v[k] - m) * (v[k + 1] - m);
  for (double x : v) den += (x - m) * (x - m);
  return num / den;
}

TEST(GnssReceiver, WhiteNoiseAloneHasItsSigmaAndNoMemory) {
  const std::vector<double> e = xErrors({.seed = 3, .sigma_m = 2.0, .bias_sigma_m = 0.0});
  // 20000 samples: the sd's standard error is 2 / sqrt(40000) = 0.01 m, the mean's 0.014 m.
  EXPECT_NEAR(sdOf(e), 2.0, 0.05);
  EXPECT_NEAR(meanOf(e), 0.0, 0.07);
  EXPECT_NEAR(lagOne(e), 0.0, 0.03);
}

TEST(GnssReceiver, TheBiasIsGaussMarkovWithItsSteadySigmaAndCorrelation) {
  // T = 10 s at 1 s fixes: lag-one correlation exp(-0.1) = 0.905; 2000 correlation times.
  const std::vector<double> e = xErrors({.seed = 5, .sigma_m = 0.0, .bias_sigma_m = 1.5, .bias_time_s = 10.0});
  EXPECT_NEAR(lagOne(e), std::exp(-0.1), 0.02);
  EXPECT_NEAR(sdOf(e), 1.5, 0.1);
  // Both together: the stated sigma is their root sum of squares, and the spread matches it.
  const GnssReceiverOptions both{.seed = 7, .sigma_m = 1.0, .bias_sigma_m = 1.5, .bias_time_s = 10.0};
  EXPECT_DOUBLE_EQ(both.statedSigma(), std::sqrt(1.0 + 2.25));
  EXPECT_NEAR(sdOf(xErrors(both)), both.statedSigma(), 0.1);
  GnssReceiver receiver(both);
  EXPECT_DOUBLE_EQ(receiver.measure(Vec2(0, 0), 0).sigma_m, both.statedSigma());
}

TEST(GnssReceiver, TheSameSeedGivesTheSameFixesAndAnotherSeedOthers) {
  const GnssReceiverOptions options;  // the defaults: a consumer receiver
  EXPECT_EQ(xErrors(options), xErrors(options));
  GnssReceiverOptions other = options;
  other.seed = 2;
  EXPECT_NE(xErrors(options), xErrors(other));
}

TEST(GnssReceiverOptions, DefaultsAreValidAndBadFieldsAreNamed) {
  EXPECT_NO_THROW(GnssReceiverOptions{}.validate());
  EXPECT_GE(GnssReceiverOptions{}.statedSigma(), 1.5);  // a consumer receiver's 1.5-3 m
  EXPECT_LE(GnssReceiverOptions{}.statedSigma(), 3.0);
  EXPECT_TRUE(testing::throwsInvalidInputNaming([] { GnssReceiver r({.bias_time_s = 0}); },
                                                "GnssReceiverOptions::bias_time_s = 0"));
  EXPECT_TRUE(testing::throwsInvalidInputNaming([] { GnssReceiver r({.sigma_m = -1}); },
                                                "GnssReceiverOptions::sigma_m = -1"));
  GnssReceiver receiver;
  receiver.measure(Vec2(0, 0), 5.0);
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { receiver.measure(Vec2(0, 0), 4.0); }, "time went back"));
}

}  // namespace
}  // namespace mapnav
