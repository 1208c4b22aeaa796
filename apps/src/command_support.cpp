#include "command_support.h"

#include <filesystem>
#include <iomanip>
#include <cmath>
#include <ostream>
#include <sstream>
#include <system_error>

#include "cli.h"
#include "mapnav/core/error.h"
#include "mapnav/core/interrupt.h"
#include "mapnav/core/io.h"
#include "mapnav/map/geojson.h"
#include "mapnav/mission/modules.h"

namespace mapnav::cli {

std::string fixedOr(const std::optional<double>& v, int digits, const std::string& missing) {
  if (!v) return missing;
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << *v;
  return s.str();
}

namespace {
namespace fs = std::filesystem;
}  // namespace

void printIssues(const Issues& issues, const std::string& file, std::ostream& out) {
  for (const Issue& issue : issues) out << formatIssue(issue, file) << "\n";
}

// Runs a command body, turning every exception into the message and exit code the CLI promises.
// Interrupted by SIGINT / SIGTERM (core/interrupt.h): 128 + the signal.
int guarded(std::ostream& err, const std::function<int()>& body) {
  try {
    const int code = body();
    // It finished before a check saw the signal (a guarded body inside this one has said it already).
    if (const int signal = interruptSignal(); signal != 0 && code != 128 + signal) {
      err << "mapnav: interrupted by signal " << signal << "\n";
      return 128 + signal;
    }
    return code;
  } catch (const Interrupted& e) {
    err << "mapnav: error: " << e.what() << "\n";
    return 128 + e.signalNumber();
  } catch (const ValidationError& e) {
    printIssues(e.issues(), e.file(), err);
    err << "mapnav: error: " << e.file() << ": invalid (" << countSeverity(e.issues(), Severity::Error) << " errors)\n";
    return kInvalid;
  } catch (const InvalidInput& e) {
    err << "mapnav: error: " << e.what() << "\n";
    return kInvalid;
  } catch (const IoError& e) {
    err << "mapnav: error: " << e.what() << "\n";
    return kUsage;
  } catch (const UsageError& e) {
    err << "mapnav: error: " << e.what() << "\n";
    err << "Run with --help for more information.\n";
    return kUsage;
  } catch (const Error& e) {
    err << "mapnav: error: " << e.what() << "\n";
    return kInvalid;
  } catch (const std::bad_alloc&) {
    err << "mapnav: error: out of memory\n";
    return kUsage;
  } catch (const std::exception& e) {
    err << "mapnav: error: " << e.what() << "\n";
    return kUsage;
  }
}

// Loads a valid map or explains why not: issues on `err`, then the exit code.
MapModuleOptions parseMapModuleOptions(const std::string& json) {
  return namingFlag("--map-options", [&] { return mapModuleOptionTable().parse(json, {}, "MapModuleOptions"); });
}

int withMap(const std::string& file, std::ostream& err, const std::function<int(const Map&)>& body) {
  return guarded(err, [&] {
    Issues issues;
    auto map = readMapFile(file, issues);
    if (!map) {
      printIssues(issues, file, err);
      err << "mapnav: error: " << file << ": not a valid map (" << countSeverity(issues, Severity::Error)
          << " errors); see `mapnav map validate " << file << "`\n";
      return static_cast<int>(kInvalid);
    }
    return body(*map);
  });
}

GeoOrigin parseOrigin(const std::string& text, bool altitude) {
  const std::vector<double> values = parseNumbers("--origin", text, 2, altitude ? 3 : 2,
                                                  altitude ? "LAT,LON or LAT,LON,ALT (degrees, metres)" : "LAT,LON (degrees)");
  if (std::abs(values[0]) > 90 || std::abs(values[1]) > 180) {
    throw InvalidInput("--origin \"" + text + "\": latitude must be in [-90, 90] and longitude in [-180, 180]");
  }
  return GeoOrigin{values[0], values[1], values.size() == 3 ? values[2] : 0.0};
}

std::string dataPath(const std::string& relative) {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / "share" / "mapnav" / relative;
    if (fs::is_regular_file(installed, ec)) return installed.string();
  }
  return std::string(MAPNAV_SOURCE_DIR) + "/" + relative;
}

std::vector<std::string> splitNames(const std::string& text) {
  std::vector<std::string> names;
  std::stringstream in(text);
  for (std::string name; std::getline(in, name, ',');)
    if (!name.empty()) names.push_back(name);
  return names;
}

std::vector<double> parseNumbers(const std::string& option, const std::string& text, std::size_t min_count,
                                 std::size_t max_count, const std::string& expected) {
  std::vector<double> values;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ',');) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != part.size() || !std::isfinite(v)) {
      throw InvalidInput(option + " \"" + text + "\": \"" + part + "\" is not a number; expected " + expected);
    }
    values.push_back(v);
  }
  if (values.size() < min_count || values.size() > max_count) {
    throw InvalidInput(option + " \"" + text + "\": expected " + expected);
  }
  return values;
}

std::vector<int> parseLabelValues(const std::string& option, const std::string& text) {
  std::vector<int> out;
  if (text.empty()) return out;
  for (double v : parseNumbers(option, text, 1, 256, "label values V[,V...] (0-255)")) {
    if (v != std::floor(v)) throw InvalidInput(option + " \"" + text + "\": label values are whole numbers");
    out.push_back(static_cast<int>(v));
  }
  return out;
}

ImageSize parseImageSize(const std::string& option, const std::string& text) {
  const auto bad = [&] {
    return InvalidInput(option + " \"" + text + "\": expected WIDTHxHEIGHT in pixels, each 1-8192 (e.g. 320x240)");
  };
  const std::size_t x = text.find('x');
  if (x == std::string::npos || x == 0 || x + 1 == text.size()) throw bad();
  const auto whole = [&](const std::string& part) {
    if (part.empty() || part.size() > 4 || part.find_first_not_of("0123456789") != std::string::npos) throw bad();
    const int v = std::stoi(part);
    if (v < 1 || v > 8192) throw bad();
    return v;
  };
  return ImageSize{whole(text.substr(0, x)), whole(text.substr(x + 1))};
}

}  // namespace mapnav::cli
