#pragma once
// The one exception tree of mapnav (as Lanelet2's Exceptions.h). Every error the library throws
// derives from mapnav::Error, so a caller can catch one type. "No result" that is normal (a pose
// off every road, no route) is an std::optional or an empty result, never an exception.
#include <stdexcept>
#include <string>
#include <vector>

#include "mapnav/core/issue.h"

namespace mapnav {

/// Root of every exception mapnav throws.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The input was read and understood, and it is wrong (an invalid map, a bad option value).
/// The CLI exits with 1.
class InvalidInput : public Error {
 public:
  using Error::Error;
};

/// A file could not be read or written. The CLI exits with 2.
class IoError : public Error {
 public:
  using Error::Error;
};

/// An id (road, intersection, surface, pipeline, ...) that is not there.
class NotFound : public Error {
 public:
  using Error::Error;
};

/// A goal that cannot be reached from a start.
class Unreachable : public Error {
 public:
  using Error::Error;
};

/// An invalid input with every problem found in it, as data. what() is the first error, formatted,
/// and the number of further problems.
class ValidationError : public InvalidInput {
 public:
  ValidationError(std::string file, std::vector<Issue> issues);
  const std::string& file() const { return file_; }
  const std::vector<Issue>& issues() const { return issues_; }

 private:
  std::string file_;
  std::vector<Issue> issues_;
};

}  // namespace mapnav
