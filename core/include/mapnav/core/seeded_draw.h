#pragma once
// Seeded random draws that are the same on every platform: a 64-bit Mersenne twister (whose output
// the standard fixes) and formulas of this header, no std:: distribution (whose algorithms the
// standard leaves to the library). Header-only.
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

namespace mapnav {

class SeededDraw {
 public:
  explicit SeededDraw(std::uint64_t seed) : rng_(seed) {}
  /// In [lo, hi): 53 random bits.
  double uniform(double lo, double hi) { return lo + (hi - lo) * static_cast<double>(rng_() >> 11) * 0x1.0p-53; }
  /// In (0, 1), never either end (a logarithm's argument).
  double open01() { return (static_cast<double>(rng_() >> 11) + 0.5) * 0x1.0p-53; }
  /// In {0, ..., n - 1} (n >= 1).
  int index(int n) { return static_cast<int>(uniform(0, n)) % n; }
  /// -1 or +1.
  double sign() { return index(2) == 0 ? -1.0 : 1.0; }
  /// A standard normal draw (Box-Muller, one of the pair: two uniform draws each).
  double normal() { return std::sqrt(-2.0 * std::log(open01())) * std::cos(2.0 * std::numbers::pi * open01()); }

 private:
  std::mt19937_64 rng_;
};

}  // namespace mapnav
