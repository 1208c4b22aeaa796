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

}  // namespace
}  // namespace mapnav
