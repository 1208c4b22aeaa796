#include "mapnav/navigator/road_position.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>
#include <system_error>

#include "mapnav/core/error.h"
#include "mapnav/core/strprintf.h"

namespace mapnav {

namespace {

bool isIdChar(char c, bool first) {
  const bool letter = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
  return letter || (!first && ((c >= '0' && c <= '9') || c == '_' || c == '-'));
}

/// `[A-Za-z][A-Za-z0-9_-]*`
bool isId(std::string_view s) {
  if (s.empty() || !isIdChar(s[0], true)) return false;
  return std::all_of(s.begin() + 1, s.end(), [](char c) { return isIdChar(c, false); });
}

constexpr std::string_view kExpected = "expected ROAD@NODE+METERS[/LATERAL], e.g. R1@I1+3 or R1@I1+3/-0.4";

/// `[0-9]+(\.[0-9]*)?`
bool isDecimal(std::string_view s) {
  const std::size_t digits = s.find_first_not_of("0123456789");
  if (digits == 0 || s.empty()) return false;
  return digits == std::string_view::npos ||
         (s[digits] == '.' && s.find_first_not_of("0123456789", digits + 1) == std::string_view::npos);
}

/// A decimal (isDecimal) as a finite double; nothing when it is beyond the range of one.
std::optional<double> decimal(std::string_view s) {
  if (s.back() == '.') s.remove_suffix(1);
  double value = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value, std::chars_format::fixed);
  if (ec != std::errc{} || end != s.data() + s.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

/// The shortest fixed-point text that reads back to the same double ("3", "0.4", "1000000").
std::string decimalText(double value) {
  std::array<char, 400> buffer{};  // the longest finite double in fixed notation is 309 + 1 + 17 digits
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value, std::chars_format::fixed);
  return std::string(buffer.data(), result.ptr);
}

}  // namespace

RoadPosition parseRoadPosition(std::string_view text) {
  // By hand rather than with std::regex, which recurses once per character (a long id overflowed
  // the stack) — and std::stod threw std::out_of_range for numbers beyond a double.
  const auto fail = [&](std::string_view why) {
    return InvalidInput("road position \"" + std::string(text) + "\": " + std::string(why));
  };
  const std::size_t at = text.find('@');
  const std::size_t plus = text.find('+', at == std::string_view::npos ? 0 : at);
  const std::size_t slash = text.find('/', plus == std::string_view::npos ? 0 : plus);
  if (at == std::string_view::npos || plus == std::string_view::npos) throw fail(kExpected);
  RoadPosition p;
  p.road = text.substr(0, at);
  p.node = text.substr(at + 1, plus - at - 1);
  const std::string_view meters = text.substr(plus + 1, slash == std::string_view::npos ? slash : slash - plus - 1);
  std::string_view lateral = slash == std::string_view::npos ? std::string_view() : text.substr(slash + 1);
  const bool negative = !lateral.empty() && lateral[0] == '-';
  if (!lateral.empty() && (lateral[0] == '-' || lateral[0] == '+')) lateral.remove_prefix(1);
  if (!isId(p.road) || !isId(p.node) || !isDecimal(meters) ||
      (slash != std::string_view::npos && !isDecimal(lateral))) {
    throw fail(kExpected);
  }
  const auto m = decimal(meters);
  const auto l = slash == std::string_view::npos ? std::optional(0.0) : decimal(lateral);
  if (!m || !l) throw fail("a number is out of range");
  p.meters = *m;
  p.lateral = negative ? -*l : *l;
  return p;
}

std::string toString(const RoadPosition& p) {
  std::string text = p.road + "@" + p.node + "+" + decimalText(p.meters);
  if (p.lateral != 0) text += (p.lateral < 0 ? "/-" : "/+") + decimalText(std::abs(p.lateral));
  return text;
}

double arcFromStart(const Road& road, const RoadPosition& p) {
  if (p.node != road.from && p.node != road.to) {
    throw InvalidInput("road position " + toString(p) + ": " + p.node + " is not an end of " + road.id + " (it runs " +
                       road.from + " to " + road.to + ")");
  }
  const double length = road.centerline.length();
  if (!(p.meters >= 0) || p.meters > length) {
    const auto [meters, len] = comparedText(p.meters, length);
    throw InvalidInput("road position " + toString(p) + ": " + meters + " m is " +
                       (p.meters > length ? "beyond" : "outside") + " the road's " + len + " m");
  }
  return p.node == road.from ? p.meters : length - p.meters;
}

Pose2 toPose(const Map& map, const RoadPosition& p) {
  const Road& road = map.road(p.road);
  const double s = arcFromStart(road, p);
  const bool forward = p.node == road.from;
  const double heading = normalizeAngle(road.centerline.headingAt(s) + (forward ? 0.0 : kPi));
  const Vec2 at = road.centerline.pointAt(s) + p.lateral * leftNormal(unitVector(heading));
  return Pose2(at, heading);
}

RoadPosition clampedTo(const Map& map, RoadPosition p) {
  p.meters = std::clamp(p.meters, 0.0, map.road(p.road).centerline.length());
  return p;
}

}  // namespace mapnav
