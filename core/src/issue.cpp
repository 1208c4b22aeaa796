#include "mapnav/core/issue.h"

#include "mapnav/core/error.h"

namespace mapnav {

std::string_view toString(Severity severity) {
  return severity == Severity::Error ? "error" : "warning";
}

std::optional<Severity> severityFromString(std::string_view text) {
  if (text == "error") return Severity::Error;
  if (text == "warning") return Severity::Warning;
  return std::nullopt;
}

std::string formatIssue(const Issue& issue, std::string_view file) {
  std::string out(file);
  out += ':';
  if (issue.line > 0) {
    out += std::to_string(issue.line) + ':' + std::to_string(issue.column) + ':';
  } else {
    out += issue.where;
    if (!issue.where.empty()) out += ':';
  }
  out += ' ';
  out += toString(issue.severity);
  out += ": ";
  out += issue.check;
  out += ": ";
  out += issue.message;
  return out;
}

bool hasErrors(const Issues& issues) { return countSeverity(issues, Severity::Error) > 0; }

std::size_t countSeverity(const Issues& issues, Severity severity) {
  std::size_t n = 0;
  for (const Issue& issue : issues) n += issue.severity == severity ? 1 : 0;
  return n;
}

void addIssue(Issues& issues, Severity severity, std::string check, std::string where, std::string message) {
  issues.push_back(Issue{severity, std::move(check), std::move(where), std::move(message)});
}

namespace {
std::string summary(const std::string& file, const std::vector<Issue>& issues) {
  const Issue* first = nullptr;
  for (const Issue& issue : issues) {
    if (issue.severity == Severity::Error) {
      first = &issue;
      break;
    }
  }
  if (first == nullptr) return file + ": invalid";
  std::string text = formatIssue(*first, file);
  const std::size_t errors = countSeverity(issues, Severity::Error);
  if (errors > 1) text += " (and " + std::to_string(errors - 1) + " more errors)";
  return text;
}
}  // namespace

ValidationError::ValidationError(std::string file, std::vector<Issue> issues)
    : InvalidInput(summary(file, issues)), file_(std::move(file)), issues_(std::move(issues)) {}

}  // namespace mapnav
