#pragma once
// Numbers in geometry's error messages (internal to geometry/src): the shortest text that reads
// back as the same double.
#include <array>
#include <charconv>
#include <string>

namespace mapnav::detail {

inline std::string numberText(double value) {
  std::array<char, 64> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

}  // namespace mapnav::detail
