#pragma once
// What every command shares: reading a map through both passes, and turning exceptions into the
// messages and exit codes the CLI promises.
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/core/issue.h"
#include "mapnav/image/image.h"
#include "mapnav/map/map.h"

namespace mapnav {
struct MapModuleOptions;
}

namespace mapnav::cli {

/// The non-empty names of a comma-separated list ("R1,,I5" -> R1, I5; "" -> none).
std::vector<std::string> splitNames(const std::string& text);

/// The numbers of a comma-separated option value ("40.44,-79.94"), between `min_count` and
/// `max_count` of them. Throws InvalidInput naming the option and what it expects.
std::vector<double> parseNumbers(const std::string& option, const std::string& text, std::size_t min_count,
                                 std::size_t max_count, const std::string& expected);

/// "3,4": label values, whole numbers in [0, 255]; "" gives none. Throws InvalidInput naming the option.
std::vector<int> parseLabelValues(const std::string& option, const std::string& text);

/// "320x240": an image size, WIDTHxHEIGHT in whole pixels, each 1-8192. Throws InvalidInput naming
/// the option and what it expects.
ImageSize parseImageSize(const std::string& option, const std::string& text);

/// --origin: "LAT,LON" or, where `altitude`, "LAT,LON,ALT" (degrees, metres), the latitude in
/// [-90, 90] and the longitude in [-180, 180]. Throws InvalidInput saying what is wrong.
GeoOrigin parseOrigin(const std::string& text, bool altitude = true);

/// A file shipped with mapnav, by its path in the source tree ("maps/park_path.json"): the
/// installed copy next to the program (../share/mapnav/...) when there is one, else the source
/// tree's.
std::string dataPath(const std::string& relative);

/// `v` with `digits` decimals, or `missing` ("-", "null") when there is none.
std::string fixedOr(const std::optional<double>& v, int digits, const std::string& missing);

/// `FILE:/pointer: severity: check: message`, one per line.
void printIssues(const Issues& issues, const std::string& file, std::ostream& out);

/// The command line itself is wrong in a way CLI11 cannot see: an argument missing that only
/// another one makes necessary ("--images and --labels go together"). Exit 2, as CLI11's own.
class UsageError : public Error {
 public:
  using Error::Error;
};

/// Runs a command body, turning every exception into a message on `err` and an exit code, the same
/// for the same kind of mistake in every command (cli.h): what was given is wrong (InvalidInput, an
/// invalid map, an unknown id, NotFound, Unreachable) 1; the command line is wrong (UsageError), a
/// file cannot be read or written (IoError) or anything unexpected 2.
int guarded(std::ostream& err, const std::function<int()>& body);

/// `body()`, with `flag` before the message of the InvalidInput it throws: a library's message
/// names the value and the field ("the lane: ..."), the CLI adds the flag it came from
/// ("--lane: the lane: ...").
template <class Body>
auto namingFlag(const std::string& flag, Body&& body) -> decltype(body()) {
  try {
    return body();
  } catch (const ValidationError&) {
    throw;
  } catch (const InvalidInput& e) {
    throw InvalidInput(flag + ": " + e.what());
  }
}

/// --map-options: the Map module's options from a JSON object ("": the defaults). Throws InvalidInput
/// "--map-options: ..." naming the option and its bad value.
MapModuleOptions parseMapModuleOptions(const std::string& json);

/// Loads a valid map and runs `body` on it, or explains on `err` why the map is not valid (exit 1).
int withMap(const std::string& file, std::ostream& err, const std::function<int(const Map&)>& body);

}  // namespace mapnav::cli
