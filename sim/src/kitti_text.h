#pragma once
// What the KITTI importers (kitti_import.cpp, kitti_raw_import.cpp) share: a bad line of a text
// file as a ValidationError naming the file, line and check.
#include <filesystem>
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

}  // namespace mapnav::kitti
