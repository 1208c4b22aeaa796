#pragma once
// printf's formatting into a std::string, for the numbers of reports, traces and tables.
#include <string>

namespace mapnav {

/// What std::printf(pattern, args...) would print: strprintf("%.2f m", 1.234) is "1.23 m". Any
/// length; the compiler checks the arguments against a literal pattern (-Wformat).
[[gnu::format(printf, 1, 2)]] std::string strprintf(const char* pattern, ...);

}  // namespace mapnav
