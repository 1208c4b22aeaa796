#pragma once
// What several benchmarks measure beside time: the process's resident memory (Linux
// /proc/self/status) and wall-clock seconds.
#include <chrono>
#include <fstream>
#include <string>

namespace mapnav::bench {

/// A field of /proc/self/status in kB ("VmRSS", "VmHWM"); 0 where there is none.
inline double statusKb(const std::string& field) {
  std::ifstream status("/proc/self/status");
  std::string key;
  double kb = 0;
  while (status >> key) {
    if (key == field + ":") {
      status >> kb;
      return kb;
    }
    status.ignore(1 << 12, '\n');
  }
  return 0;
}

/// Resets the process's peak resident memory (VmHWM) to its current value (Linux).
inline void resetPeakMemory() { std::ofstream("/proc/self/clear_refs") << "5"; }

inline double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace mapnav::bench
