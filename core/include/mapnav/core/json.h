#pragma once
// Reading JSON documents with precise errors: syntax errors with line and column, every semantic
// problem with the JSON Pointer of the value. Readers collect issues and go on, so that one pass
// reports every problem (as mold does). Include only in .cpp files that parse or write JSON.
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "mapnav/core/issue.h"

namespace mapnav {

/// Keys keep the author's order, so that written files read like the input.
using Json = nlohmann::ordered_json;

/// Parses `text`. On a syntax error adds a `json.syntax` issue with line and column and returns
/// nothing. Non-finite numbers (1e999) are reported as `json.not_finite` with their pointer, nesting
/// deeper than 512 arrays / objects (mapnav's formats need 6) as `json.too_deep` with the line and column where it goes too deep.
std::optional<Json> parseJson(std::string_view text, Issues& issues);

/// RFC 6901: `pointerJoin("/roads", "a/b")` is `/roads/a~1b`.
std::string pointerJoin(std::string_view base, std::string_view key);
std::string pointerJoin(std::string_view base, std::size_t index);

/// "object", "array", "string", "number", "boolean", "null".
std::string_view jsonTypeName(const Json& value);

/// `x` rounded to a multiple of 1 / `scale` (scale 1e4: 4 decimals), -0 turned into 0: a figure
/// for a JSON output, its bytes independent of a computation's last bits.
inline double roundTo(double x, double scale) { return std::round(x * scale) / scale + 0.0; }

/// Writes `value` indented by 2 with a final newline; points and other short arrays of numbers on
/// one line. Doubles round-trip exactly.
std::string dumpJson(const Json& value);

/// A cursor over one JSON object that records what is wrong with it as issues (check names
/// `schema.type`, `schema.required`, `schema.unknown_field`, `schema.range`) and lets the reader go
/// on. Keys beginning with "x-" (extensions) and "$schema" are always allowed.
class JsonObject {
 public:
  /// Records `schema.type` if `value` is not an object; then every accessor returns nothing.
  JsonObject(const Json& value, std::string pointer, Issues& issues);

  bool isObject() const { return object_ != nullptr; }
  const std::string& pointer() const { return pointer_; }
  std::string pointer(std::string_view key) const { return pointerJoin(pointer_, key); }
  bool has(std::string_view key) const;

  /// The member, or nothing; records `schema.required` when it is required and missing.
  const Json* member(std::string_view key, bool required);

  std::optional<std::string> string(std::string_view key, bool required = true);
  /// A finite number within [min, max]; records `schema.type` or `schema.range` otherwise.
  std::optional<double> number(std::string_view key, bool required = true, double min = -1e300,
                               double max = 1e300);
  std::optional<bool> boolean(std::string_view key, bool required = true);

  /// Records `schema.unknown_field` for every member that no accessor asked for.
  void rejectUnknownMembers();

  Issues& issues() { return issues_; }

 private:
  const Json* object_ = nullptr;
  std::string pointer_;
  Issues& issues_;
  std::vector<std::string> known_;
};

/// Checks a finite number in [min, max] at `pointer`; records an issue and returns nothing otherwise.
std::optional<double> readNumber(const Json& value, const std::string& pointer, Issues& issues,
                                 double min = -1e300, double max = 1e300);

}  // namespace mapnav
