#pragma once
// Validation results as data (as Lanelet2's lanelet2_validation/Issue.h): every check has a dotted
// name (`roads.unknown_intersection`), every problem a JSON Pointer into the file it came from.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mapnav {

enum class Severity { Warning, Error };

std::string_view toString(Severity severity);
std::optional<Severity> severityFromString(std::string_view text);

struct Issue {
  Severity severity = Severity::Error;
  std::string check;    ///< dotted check name, e.g. "roads.unknown_intersection"
  std::string where;    ///< JSON Pointer (RFC 6901) into the input; "" is the whole document
  std::string message;  ///< what is wrong, for a person
  int line = 0;         ///< 1-based line for syntax errors, 0 when `where` locates the problem
  int column = 0;       ///< 1-based column for syntax errors

  bool operator==(const Issue&) const = default;
};

using Issues = std::vector<Issue>;

/// One line, as the CLI prints it: `FILE:/pointer: error: check: message`, or `FILE:LINE:COL: ...`
/// for a syntax error. An empty pointer (the whole document) prints as `FILE:`.
std::string formatIssue(const Issue& issue, std::string_view file);

bool hasErrors(const Issues& issues);
std::size_t countSeverity(const Issues& issues, Severity severity);

/// Adds an issue; a one-liner for the many checks.
void addIssue(Issues& issues, Severity severity, std::string check, std::string where, std::string message);

}  // namespace mapnav
