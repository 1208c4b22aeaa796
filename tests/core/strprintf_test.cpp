#include "mapnav/core/strprintf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

namespace mapnav {
namespace {

TEST(Strprintf, FormatsAsPrintfWouldAtAnyLength) {
  EXPECT_EQ(strprintf("%.2f m", 1.234), "1.23 m");
  EXPECT_EQ(strprintf("%s", std::string(1000, 'x').c_str()).size(), 1000u);
  EXPECT_EQ(strprintf("no arguments"), "no arguments");
}

// The shortest text that reads back as the same double: hand-picked values and a round trip of
// values with many digits.
TEST(NumberText, ShortestTextThatReadsBackExactly) {
  EXPECT_EQ(numberText(0.1), "0.1");
  EXPECT_EQ(numberText(3.0), "3");
  EXPECT_EQ(numberText(-2.5), "-2.5");
  EXPECT_EQ(numberText(1e300), "1e+300");
  EXPECT_EQ(numberText(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(numberText(-std::numeric_limits<double>::infinity()), "-inf");
  for (double v = 1e-7; v < 1e9; v *= 3.3719) {
    const std::string text = numberText(v);
    EXPECT_EQ(std::strtod(text.c_str(), nullptr), v) << text;
    EXPECT_LE(text.size(), 24u);
  }
}

// Numbers a message compares: 2 decimals when they tell the two apart the right way, more when
// rounding would make them equal or swap them, the same text for equal numbers.
TEST(ComparedText, NeverContradictsTheComparison) {
  EXPECT_EQ(comparedText(0.879, 0.878061), std::make_pair(std::string("0.879"), std::string("0.878")));
  EXPECT_EQ(comparedText(3.5, 3.0), std::make_pair(std::string("3.50"), std::string("3.00")));
  EXPECT_EQ(comparedText(0.4999, 0.5), std::make_pair(std::string("0.4999"), std::string("0.5000")));
  EXPECT_EQ(comparedText(2.0, 2.0), std::make_pair(std::string("2.00"), std::string("2.00")));
  EXPECT_EQ(comparedText(12.34, 5.0, 0), std::make_pair(std::string("12"), std::string("5")));
  // Neighbouring doubles differ only in their 17th significant digit.
  const double x = 0.1, y = std::nextafter(0.1, 1.0);
  const auto [tx, ty] = comparedText(y, x);
  EXPECT_GT(std::strtod(tx.c_str(), nullptr), std::strtod(ty.c_str(), nullptr)) << tx << " " << ty;
  EXPECT_EQ(comparedText(1.0, std::numeric_limits<double>::infinity()).second, "inf");
  // Random pairs close together: the texts always read back in the numbers' order.
  double a = 0.3;
  for (int i = 0; i < 1000; ++i) {
    a = std::fmod(a * 7.31 + 0.123, 10.0);
    const double b = a + (i % 3 - 1) * std::pow(10.0, -(i % 15));
    const auto [ta, tb] = comparedText(a, b);
    const double ra = std::strtod(ta.c_str(), nullptr), rb = std::strtod(tb.c_str(), nullptr);
    EXPECT_EQ((ra > rb) - (ra < rb), (a > b) - (a < b)) << a << " " << b << ": " << ta << " " << tb;
  }
}

}  // namespace
}  // namespace mapnav
