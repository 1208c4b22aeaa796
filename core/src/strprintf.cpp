#include "mapnav/core/strprintf.h"

#include <array>
#include <charconv>
#include <cstdarg>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace mapnav {

std::string strprintf(const char* pattern, ...) {
  std::va_list args, again;
  va_start(args, pattern);
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, pattern, args);
  va_end(args);
  std::string out(n > 0 ? static_cast<std::size_t>(n) : 0, '\0');
  if (n > 0) std::vsnprintf(out.data(), out.size() + 1, pattern, again);
  va_end(again);
  return out;
}

std::string numberText(double value) {
  std::array<char, 64> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

std::pair<std::string, std::string> comparedText(double a, double b, int decimals) {
  if (!std::isfinite(a) || !std::isfinite(b)) return {numberText(a), numberText(b)};
  auto order = [](double x, double y) { return (x > y) - (x < y); };
  for (int d = decimals < 0 ? 0 : decimals; d <= 17; ++d) {
    std::string ta = strprintf("%.*f", d, a), tb = strprintf("%.*f", d, b);
    if (order(std::strtod(ta.c_str(), nullptr), std::strtod(tb.c_str(), nullptr)) == order(a, b)) return {ta, tb};
  }
  return {numberText(a), numberText(b)};  // shortest round-trip texts: they read back as a and b
}

}  // namespace mapnav
