#pragma once
// Numbers into text: printf's formatting into a std::string, for reports, traces and tables; and the
// shortest text of a double, for error messages that quote a value exactly.
#include <string>
#include <utility>

namespace mapnav {

/// What std::printf(pattern, args...) would print: strprintf("%.2f m", 1.234) is "1.23 m". Any
/// length; the compiler checks the arguments against a literal pattern (-Wformat).
[[gnu::format(printf, 1, 2)]] std::string strprintf(const char* pattern, ...);

/// The shortest text that reads back as the same double (std::to_chars): 0.1 is "0.1", 1e300 is
/// "1e+300", NaN "nan".
std::string numberText(double value);

/// Two numbers that a message compares ("0.879 m is beyond the road's 0.8781 m"), as fixed-point
/// texts that never contradict the comparison: `decimals` decimals (trailing zeros kept), or as
/// many more as it takes for the two texts to read back in the same order as the numbers (equal
/// numbers print alike; unequal ones never do). Non-finite numbers print as numberText does.
std::pair<std::string, std::string> comparedText(double a, double b, int decimals = 2);

}  // namespace mapnav
