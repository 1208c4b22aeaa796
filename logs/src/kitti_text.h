#pragma once
// What the KITTI importers (kitti_import.cpp, kitti_raw_import.cpp) share: a bad line of a text
// file as a ValidationError naming the file, line and check.
#include <charconv>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>

#include "mapnav/core/error.h"

namespace mapnav::kitti {

[[noreturn]] inline void badLine(const std::filesystem::path& file, int line, const std::string& check,
                                 const std::string& message) {
  Issue issue;
  issue.check = check;
  issue.message = message;
  issue.line = line;
  issue.column = 1;
  throw ValidationError(file.string(), {issue});
}

/// A whole token as a finite number; nothing when it is not one.
inline std::optional<double> finiteNumber(const std::string& token) {
  double v = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || end != token.data() + token.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace mapnav::kitti
