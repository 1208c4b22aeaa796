#pragma once
// What every command shares: reading a map through both passes, and turning exceptions into the
// messages and exit codes the CLI promises.
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/core/issue.h"
#include "mapnav/map/map.h"

namespace mapnav::cli {

/// The non-empty names of a comma-separated list ("R1,,I5" -> R1, I5; "" -> none).
std::vector<std::string> splitNames(const std::string& text);

/// The numbers of a comma-separated option value ("40.44,-79.94"), between `min_count` and
/// `max_count` of them. Throws InvalidInput naming the option and what it expects.
std::vector<double> parseNumbers(const std::string& option, const std::string& text, std::size_t min_count,
                                 std::size_t max_count, const std::string& expected);

/// A file shipped with mapnav, by its path in the source tree ("maps/park_path.json"): the
/// installed copy next to the program (../share/mapnav/...) when there is one, else the source
/// tree's.
std::string dataPath(const std::string& relative);

/// `v` with `digits` decimals, or `missing` ("-", "null") when there is none.
std::string fixedOr(const std::optional<double>& v, int digits, const std::string& missing);

/// `FILE:/pointer: severity: check: message`, one per line.
void printIssues(const Issues& issues, const std::string& file, std::ostream& out);

/// Runs a command body, turning every exception into a message on `err` and an exit code:
/// invalid input 1, I/O and anything unexpected 2.
int guarded(std::ostream& err, const std::function<int()>& body);

/// Loads a valid map and runs `body` on it, or explains on `err` why the map is not valid (exit 1).
int withMap(const std::string& file, std::ostream& err, const std::function<int(const Map&)>& body);

}  // namespace mapnav::cli
