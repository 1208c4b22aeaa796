#pragma once
// Shared by the fuzz targets: the input as text, the fixed files the targets read (data/), and the
// check that stops the run when a property that must hold does not.
//
// The rule every target enforces: bad input may make a parser return nothing with issues, or throw
// a mapnav::Error (the library's documented way to say "this input is wrong"); anything else — a
// crash, a sanitizer report, another exception type escaping, a broken round trip — is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

namespace mapnav::fuzz {

inline std::string_view asText(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// A file of tests/fuzz/data/.
inline std::filesystem::path dataPath(std::string_view name) {
  return std::filesystem::path(MAPNAV_FUZZ_DATA_DIR) / name;
}

/// Aborts (libFuzzer then saves the input) with `what` when `ok` is false.
inline void require(bool ok, const char* what, const std::string& detail = {}) {
  if (ok) return;
  std::fprintf(stderr, "fuzz property violated: %s\n%s\n", what, detail.c_str());
  std::abort();
}

}  // namespace mapnav::fuzz
