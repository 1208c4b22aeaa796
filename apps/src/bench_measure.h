#pragma once
// `mapnav bench`'s timer: a call run in batches until a minimum time has passed, the median batch
// taken (internal to apps/).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "mapnav/core/strprintf.h"

namespace mapnav::cli {

using Clock = std::chrono::steady_clock;

inline double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Keeps the compiler from dropping work whose result is otherwise unused.
template <class T>
inline void keep(const T& value) {
  asm volatile("" : : "g"(&value) : "memory");
}

struct Measured {
  double s_per_frame = 0;  // the median batch's time per call, seconds
  int batches = 0;
};

// Runs `once` in batches until `min_time_s` has passed and there are at least 5 batches (3 when one
// call alone takes a third of the time), and takes the median batch: the machine's noise (other
// processes, frequency changes) lands in the outer batches. A warm-up call and a calibration that
// sizes a batch to about a tenth of `min_time_s` come first and are not counted.
template <class F>
Measured measure(F&& once, double min_time_s) {
  once();
  const double batch_target = min_time_s / 10;
  long n = 1;
  double per_call = 0;
  for (;;) {
    const Clock::time_point t0 = Clock::now();
    for (long i = 0; i < n; ++i) once();
    const double dt = secondsSince(t0);
    if (dt >= batch_target / 4 || n >= (1L << 30)) {
      per_call = dt / static_cast<double>(n);
      break;
    }
    n *= 4;
  }
  const long calls = std::max(1L, static_cast<long>(std::ceil(batch_target / std::max(per_call, 1e-9))));
  const int min_batches = per_call > min_time_s / 3 ? 3 : 5;
  std::vector<double> batches;
  const Clock::time_point start = Clock::now();
  while (static_cast<int>(batches.size()) < min_batches ||
         (secondsSince(start) < min_time_s && batches.size() < 1000)) {
    const Clock::time_point t0 = Clock::now();
    for (long i = 0; i < calls; ++i) once();
    batches.push_back(secondsSince(t0) / static_cast<double>(calls));
  }
  std::sort(batches.begin(), batches.end());
  const std::size_t m = batches.size();
  const double median = m % 2 ? batches[m / 2] : 0.5 * (batches[m / 2 - 1] + batches[m / 2]);
  return {median, static_cast<int>(m)};
}

// Four significant digits, without an exponent for the values a frame time takes.
inline std::string sig(double value) {
  if (!std::isfinite(value)) return "-";
  const double a = std::fabs(value);
  if (a >= 1000) return strprintf("%.0f", value);
  if (a >= 100) return strprintf("%.1f", value);
  if (a >= 10) return strprintf("%.2f", value);
  if (a >= 1) return strprintf("%.3f", value);
  if (a >= 0.1) return strprintf("%.4f", value);
  if (a >= 0.01) return strprintf("%.5f", value);
  return strprintf("%.6f", value);
}

inline std::string pad(const std::string& text, std::size_t width) {
  return text.size() >= width ? text : std::string(width - text.size(), ' ') + text;
}

}  // namespace mapnav::cli
