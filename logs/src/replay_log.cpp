#include "mapnav/logs/replay_log.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <system_error>
#include <utility>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/core/json.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/image/png.h"

namespace mapnav {

namespace fs = std::filesystem;

const OptionTable<LogHeader>& logHeaderOptionTable() {
  using O = LogHeader;
  static const OptionTable<O> table = OptionTable<O>("LogHeader")
                                          .field("name", &O::name, "for people; \"\" when absent")
                                          .field("map", &O::map, "the map the log was recorded on (\"\": none)")
                                          .field("frame_rate_hz", &O::frame_rate_hz, above(0), "nominal frame rate, Hz");
  return table;
}

const OptionTable<ReadOptions>& readOptionTable() {
  using O = ReadOptions;
  static const OptionTable<O> table =
      OptionTable<O>("ReadOptions")
          .field("skip_bad_frames", &O::skip_bad_frames, "skip bad frames.jsonl lines (kept as warnings) instead of failing")
          .field("verify_images", &O::verify_images, "also decode every image and mask")
          .field("max_line_bytes", &O::max_line_bytes, above(0), "longer lines are log.line_too_long without being parsed");
  return table;
}

namespace {

constexpr std::string_view kLogFile = "log.json";
constexpr std::string_view kFramesFile = "frames.jsonl";


/// A relative path that stays inside the log folder: not empty, not absolute, no "..", no NUL or
/// backslash (logs are portable).
bool safeRelativePath(const std::string& text) {
  if (text.empty() || text.find('\0') != std::string::npos || text.find('\\') != std::string::npos) return false;
  const fs::path path(text);
  if (path.is_absolute() || path.has_root_name() || path.has_root_directory()) return false;
  for (const auto& part : path) {
    if (part == "..") return false;
  }
  return true;
}

// ---- log.json ---------------------------------------------------------------------------------

std::optional<LogHeader> parseHeader(std::string_view text, Issues& issues) {
  const std::size_t before = countSeverity(issues, Severity::Error);
  const auto json = parseJson(text, issues);
  if (!json) return std::nullopt;
  JsonObject top(*json, "", issues);
  if (!top.isObject()) return std::nullopt;

  if (const auto format = top.string("format")) {
    if (*format != kLogFormat) {
      addIssue(issues, Severity::Error, "schema.format", "/format",
               "unknown format \"" + *format + "\"; expected \"" + std::string(kLogFormat) + "\"");
    }
  }
  if (const Json* schema = top.member("$schema", false); schema != nullptr && !schema->is_string()) {
    addIssue(issues, Severity::Error, "schema.type", "/$schema", "expected a string");
  }
  LogHeader header;
  header.name = top.string("name", false).value_or("");
  if (const Json* camera = top.member("camera", true)) {
    if (!camera->is_object()) {
      addIssue(issues, Severity::Error, "schema.type", "/camera",
               "expected a mapnav-camera/1 object, got " + std::string(jsonTypeName(*camera)));
    } else {
      Issues found;
      auto parsed = parseCamera(camera->dump(), found);
      for (Issue& issue : found) {
        issue.where = "/camera" + issue.where;
        issue.line = 0;
        issue.column = 0;
        issues.push_back(std::move(issue));
      }
      header.camera = std::move(parsed);
    }
  }
  header.map = top.string("map", false).value_or("");
  if (const auto rate = top.number("frame_rate_hz")) header.frame_rate_hz = *rate;
  if (const Json* units_json = top.member("units", false)) {
    JsonObject units(*units_json, "/units", issues);
    const std::pair<std::string_view, std::string_view> fixed[] = {{"distance", "m"}, {"angle", "deg"}};
    for (const auto& [key, value] : fixed) {
      if (const auto got = units.string(key, false); got && *got != value) {
        addIssue(issues, Severity::Error, "schema.enum", units.pointer(key),
                 "unit \"" + *got + "\" is not supported; mapnav-log/1 uses \"" + std::string(value) + "\"");
      }
    }
    units.rejectUnknownMembers();
  }
  top.rejectUnknownMembers();
  if (const auto broken = logHeaderOptionTable().brokenRule(header))  // frame_rate_hz > 0
    addIssue(issues, Severity::Error, "schema.range", "/" + logHeaderOptionTable().fields()[broken->first].name, broken->second);
  if (countSeverity(issues, Severity::Error) != before || !header.camera) return std::nullopt;
  return header;
}

std::string headerToJson(const LogHeader& header) {
  Json doc = Json::object();
  doc["format"] = kLogFormat;
  if (!header.name.empty()) doc["name"] = header.name;
  doc["camera"] = Json::parse(cameraToJson(*header.camera));
  if (!header.map.empty()) doc["map"] = header.map;
  doc["frame_rate_hz"] = header.frame_rate_hz;
  doc["units"] = {{"distance", "m"}, {"angle", "deg"}};
  return dumpJson(doc);
}

// ---- frames.jsonl -----------------------------------------------------------------------------

/// The check a line's JSON-reading issue is reported under.
std::string lineCheck(const std::string& check) {
  if (check == "json.syntax" || check == "json.too_deep") return "log.not_json";  // the message says which
  if (check == "json.not_finite") return "log.not_finite";
  if (check.rfind("schema.", 0) == 0) return "log.field";
  return check;
}

/// One frames.jsonl line as read: the frame when the line is good, else what could be read of it.
struct ParsedLine {
  std::optional<LogFrame> frame;
  std::optional<double> t;
  std::optional<MotionIncrement> odometry;
};

/// Reads one frames.jsonl line. Every issue found is appended to `issues` (errors, with their JSON
/// Pointer in `where`, not yet with the line number).
ParsedLine parseFrame(std::string_view text, const fs::path& dir, const ReadOptions& options,
                      const std::optional<double>& last_t, const Camera& camera, Issues& issues) {
  ParsedLine parsed;
  Issues found;
  const auto json = parseJson(text, found);
  if (!json) {
    for (Issue& issue : found) issue.check = lineCheck(issue.check);
    issues.insert(issues.end(), found.begin(), found.end());
    return parsed;
  }
  LogFrame frame;
  bool ok = true;
  JsonObject top(*json, "", found);
  if (top.isObject()) {
    const auto t = top.number("t");
    const auto image = top.string("image");
    const auto mask = top.string("mask", false);
    std::optional<MotionIncrement> odometry;
    if (const Json* odo_json = top.member("odometry", true)) {
      JsonObject odo(*odo_json, "/odometry", found);
      const auto distance = odo.number("distance_m");
      const auto dheading = odo.number("dheading_deg");
      odo.rejectUnknownMembers();
      if (distance && dheading) odometry = MotionIncrement{*distance, degToRad(*dheading)};
    }
    if (const Json* truth_json = top.member("truth", false)) {
      JsonObject truth(*truth_json, "/truth", found);
      const auto x = truth.number("x");
      const auto y = truth.number("y");
      const auto heading = truth.number("heading_deg");
      truth.rejectUnknownMembers();
      if (x && y && heading) frame.truth = Pose2(*x, *y, degToRad(*heading));
      ok = ok && frame.truth.has_value();
    }
    if (const Json* gnss_json = top.member("gnss", false)) {
      JsonObject gnss(*gnss_json, "/gnss", found);
      const auto x = gnss.number("x");
      const auto y = gnss.number("y");
      const auto sigma = gnss.number("sigma_m");
      gnss.rejectUnknownMembers();
      if (sigma && !(*sigma > 0.0)) {
        addIssue(found, Severity::Error, "schema.range", "/gnss/sigma_m", "number " + numberText(*sigma) + " must be > 0");
      } else if (x && y && sigma) {
        frame.gnss = GnssFix{Vec2(*x, *y), *sigma};
      }
      ok = ok && frame.gnss.has_value();
    }
    top.rejectUnknownMembers();
    parsed.t = t;
    parsed.odometry = odometry;
    ok = ok && t && image && odometry && (mask || !top.has("mask"));
    for (Issue& issue : found) issue.check = lineCheck(issue.check);
    if (t) {
      frame.t = *t;
      if (last_t && !(*t > *last_t)) {
        addIssue(found, Severity::Error, "log.time_order", "/t",
                 "t = " + numberText(*t) + " s is not after the previous frame's " + numberText(*last_t) +
                     " s (times must increase strictly)");
        ok = false;
      }
    }
    if (odometry) frame.odometry = *odometry;
    // The files: inside the folder, present, and (when asked) decodable and of the camera's size.
    const std::pair<const std::optional<std::string>*, std::string_view> files[] = {{&image, "image"}, {&mask, "mask"}};
    for (const auto& [path, key] : files) {
      if (!path->has_value()) continue;
      const std::string& relative = **path;
      const std::string pointer = "/" + std::string(key);
      if (!safeRelativePath(relative)) {
        addIssue(found, Severity::Error, "log.bad_path", pointer,
                 std::string(key) + " path \"" + relative +
                     "\" must be relative to the log folder and stay inside it (no \"..\", not absolute)");
        ok = false;
        continue;
      }
      const fs::path full = dir / relative;
      std::error_code ec;
      if (!fs::is_regular_file(full, ec)) {
        addIssue(found, Severity::Error, "log.missing_image", pointer,
                 std::string(key) + " file \"" + relative + "\" does not exist in the log folder");
        ok = false;
        continue;
      }
      if (!options.verify_images) continue;
      try {
        const Image decoded = readPng(full);
        const bool is_mask = key == "mask";
        if (decoded.width != camera.width() || decoded.height != camera.height() ||
            (is_mask && decoded.channels != 1)) {
          addIssue(found, Severity::Error, "log.image_size", pointer,
                   std::string(key) + " \"" + relative + "\" is " + std::to_string(decoded.width) + "x" +
                       std::to_string(decoded.height) + "x" + std::to_string(decoded.channels) + "; the camera takes " +
                       std::to_string(camera.width()) + "x" + std::to_string(camera.height()) +
                       (is_mask ? "x1" : " (1 or 3 channels)"));
          ok = false;
        }
      } catch (const Error& e) {
        addIssue(found, Severity::Error, "log.corrupt_image", pointer,
                 std::string(key) + " \"" + relative + "\" is not a readable PNG: " + e.what());
        ok = false;
      }
    }
    if (ok) {
      frame.image = *image;
      frame.mask = mask;
    }
  } else {
    for (Issue& issue : found) issue.check = lineCheck(issue.check);
    ok = false;
  }
  ok = ok && !hasErrors(found);
  issues.insert(issues.end(), found.begin(), found.end());
  if (ok) parsed.frame = std::move(frame);
  return parsed;
}

}  // namespace

std::optional<LogFrame> parseLogFrame(std::string_view text, const fs::path& dir, const ReadOptions& options,
                                      const std::optional<double>& last_t, const Camera& camera, Issues& issues) {
  return parseFrame(text, dir, options, last_t, camera, issues).frame;
}

namespace {

Json frameToJson(const LogFrame& frame) {
  Json line = Json::object();
  line["t"] = frame.t;
  line["image"] = frame.image;
  if (frame.mask) line["mask"] = *frame.mask;
  line["odometry"] = {{"distance_m", frame.odometry.distance_m},
                      {"dheading_deg", degreesFor(frame.odometry.dheading_rad)}};
  if (frame.truth) {
    line["truth"] = {{"x", frame.truth->x()}, {"y", frame.truth->y()}, {"heading_deg", degreesFor(frame.truth->heading())}};
  }
  if (frame.gnss) {
    line["gnss"] = {{"x", frame.gnss->position.x()}, {"y", frame.gnss->position.y()}, {"sigma_m", frame.gnss->sigma_m}};
  }
  return line;
}

std::string indexedPath(std::string_view folder, std::size_t index) {
  std::array<char, 32> name{};
  std::snprintf(name.data(), name.size(), "%06zu.png", index);
  return std::string(folder) + "/" + name.data();
}

void requireFinite(double value, std::string_view field) {
  if (!std::isfinite(value)) {
    throw InvalidInput("ReplayLogWriter::add: " + std::string(field) + " = " + numberText(value) + ": must be finite");
  }
}

}  // namespace

// ---- LogHeader, ReadOptions -------------------------------------------------------------------

void LogHeader::validate() const {
  // The camera is an object, not a value a table holds.
  if (camera == nullptr) throw InvalidInput("LogHeader::camera = 0: must be set (not null)");
  logHeaderOptionTable().validate(*this);
}

void ReadOptions::validate() const { readOptionTable().validate(*this); }

// ---- ReplayLogWriter --------------------------------------------------------------------------

ReplayLogWriter::ReplayLogWriter(fs::path dir, LogHeader header) : dir_(std::move(dir)), header_(std::move(header)) {
  header_.validate();
  if (dir_.filename().empty()) dir_ = dir_.parent_path();  // "out/" names the folder "out"
  if (dir_.empty()) throw InvalidInput("ReplayLogWriter: an empty folder name");
  tmp_ = dir_;
  tmp_ += ".partial-" + std::to_string(::getpid());
  const std::string log_json = headerToJson(header_);  // throws InvalidInput before touching the disk
  std::error_code ec;
  fs::remove_all(tmp_, ec);
  fs::create_directories(tmp_ / "images", ec);
  if (ec) throw IoError(tmp_.string() + ": cannot create the folder: " + ec.message());
  try {
    writeFileAtomic(tmp_ / kLogFile, log_json);
  } catch (...) {
    fs::remove_all(tmp_, ec);
    throw;
  }
}

ReplayLogWriter::~ReplayLogWriter() {
  if (finished_) return;
  std::error_code ec;
  fs::remove_all(tmp_, ec);  // nothing to do about a failure in a destructor
}

LogFrame ReplayLogWriter::add(const LogFrame& frame, const Image& image, const Image* mask) {
  if (finished_) throw InvalidInput("ReplayLogWriter::add: the log " + dir_.string() + " is already finished");
  requireFinite(frame.t, "t");
  if (last_t_ && !(frame.t > *last_t_)) {
    throw InvalidInput("ReplayLogWriter::add: t = " + numberText(frame.t) + " is not after the previous frame's " +
                       numberText(*last_t_));
  }
  requireFinite(frame.odometry.distance_m, "odometry.distance_m");
  requireFinite(frame.odometry.dheading_rad, "odometry.dheading_rad");
  if (frame.truth) {
    requireFinite(frame.truth->x(), "truth.x");
    requireFinite(frame.truth->y(), "truth.y");
    requireFinite(frame.truth->heading(), "truth.heading");
  }
  if (frame.gnss) {
    requireFinite(frame.gnss->position.x(), "gnss.position.x");
    requireFinite(frame.gnss->position.y(), "gnss.position.y");
    requireFinite(frame.gnss->sigma_m, "gnss.sigma_m");
    if (!(frame.gnss->sigma_m > 0.0)) {
      throw InvalidInput("ReplayLogWriter::add: gnss.sigma_m = " + numberText(frame.gnss->sigma_m) + ": must be > 0");
    }
  }
  const Camera& camera = *header_.camera;
  auto checkSize = [&](const Image& im, std::string_view what, bool grey_only) {
    const bool channels_ok = grey_only ? im.channels == 1 : (im.channels == 1 || im.channels == 3);
    if (im.width != camera.width() || im.height != camera.height() || !channels_ok ||
        im.data.size() != static_cast<std::size_t>(im.width) * static_cast<std::size_t>(im.height) *
                              static_cast<std::size_t>(std::max(im.channels, 0))) {
      throw InvalidInput("ReplayLogWriter::add: the " + std::string(what) + " is " + std::to_string(im.width) + "x" +
                         std::to_string(im.height) + "x" + std::to_string(im.channels) + "; the camera takes " +
                         std::to_string(camera.width()) + "x" + std::to_string(camera.height()) +
                         (grey_only ? "x1" : " with 1 or 3 channels"));
    }
  };
  checkSize(image, "image", false);
  if (mask != nullptr) checkSize(*mask, "mask", true);

  LogFrame recorded = frame;
  recorded.image = indexedPath("images", count_);
  recorded.mask.reset();
  writePng(image, tmp_ / recorded.image);
  if (mask != nullptr) {
    recorded.mask = indexedPath("masks", count_);
    std::error_code ec;
    fs::create_directories(tmp_ / "masks", ec);
    if (ec) throw IoError((tmp_ / "masks").string() + ": cannot create the folder: " + ec.message());
    writePng(*mask, tmp_ / *recorded.mask);
  }
  lines_ += frameToJson(recorded).dump();
  lines_ += '\n';
  ++count_;
  last_t_ = frame.t;
  return recorded;
}

void ReplayLogWriter::finish() {
  if (finished_) throw InvalidInput("ReplayLogWriter::finish: the log " + dir_.string() + " is already finished");
  writeFileAtomic(tmp_ / kFramesFile, lines_);
  std::error_code ec;
  if (fs::exists(fs::symlink_status(dir_, ec))) {
    if (!fs::is_directory(fs::symlink_status(dir_, ec)) || !fs::is_empty(dir_, ec) || ec) {
      throw IoError(dir_.string() + ": already exists and is not an empty folder; not overwriting it with the log");
    }
    fs::remove(dir_, ec);
    if (ec) throw IoError(dir_.string() + ": cannot replace the empty folder: " + ec.message());
  }
  fs::rename(tmp_, dir_, ec);
  if (ec) throw IoError(dir_.string() + ": cannot move the finished log into place: " + ec.message());
  finished_ = true;
}

// ---- ReplayLog --------------------------------------------------------------------------------

ReplayLog ReplayLog::open(const fs::path& dir, const ReadOptions& options) {
  options.validate();
  ReplayLog log;
  log.dir_ = dir;
  {
    const fs::path path = dir / kLogFile;
    const std::string text = readFile(path);
    Issues issues;
    auto header = parseHeader(text, issues);
    if (!header) throw ValidationError(path.string(), std::move(issues));
    log.header_ = std::move(*header);
  }
  const fs::path frames_path = dir / kFramesFile;
  const std::string text = readFile(frames_path);
  std::optional<double> last_t;
  std::size_t begin = 0;
  int line_number = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + begin, end - begin);
    begin = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.find_first_not_of(" \t") == std::string_view::npos) continue;  // blank lines carry nothing

    Issues found;
    ParsedLine parsed;
    if (line.size() > options.max_line_bytes) {
      addIssue(found, Severity::Error, "log.line_too_long", "",
               "the line is " + std::to_string(line.size()) + " bytes long; at most " +
                   std::to_string(options.max_line_bytes) + " are read (ReadOptions::max_line_bytes)");
    } else {
      parsed = parseFrame(line, dir, options, last_t, *log.header_.camera, found);
    }
    // The last line, without its newline and not JSON: the log was cut while this line was written.
    const bool last_unterminated = end == text.size();
    if (last_unterminated && !found.empty() && found.front().check == "log.not_json") {
      found.front().check = "log.truncated";
      found.front().message = "the last line is cut short (no newline at its end, incomplete JSON): " + found.front().message;
    }
    for (Issue& issue : found) {  // FILE:LINE:COL locates it; the pointer goes into the message
      issue.line = line_number;
      if (issue.column <= 0) issue.column = 1;
      if (!issue.where.empty()) issue.message = issue.where + ": " + issue.message;
    }
    if (parsed.frame) {
      last_t = parsed.frame->t;
      log.frames_.push_back(std::move(*parsed.frame));
      log.frame_lines_.push_back(line_number);
      continue;
    }
    if (found.empty()) addIssue(found, Severity::Error, "log.field", "", "the frame is invalid");  // not expected
    if (!options.skip_bad_frames) throw ValidationError(frames_path.string(), std::move(found));
    ++log.skipped_;
    log.skipped_lines_.push_back(SkippedLine{line_number, found.front().check, found.front().message,
                                             found.front().where, parsed.t, parsed.odometry});
    for (Issue& issue : found) {
      issue.severity = Severity::Warning;
      log.issues_.push_back(std::move(issue));
    }
  }
  return log;
}

std::optional<fs::path> ReplayLog::mapPath() const {
  if (header_.map.empty()) return std::nullopt;
  const fs::path map(header_.map);
  return map.is_absolute() ? map : dir_ / map;
}

int ReplayLog::lineOf(std::size_t i) const {
  frame(i);  // the range check
  return frame_lines_[i];
}

const LogFrame& ReplayLog::frame(std::size_t i) const {
  if (i >= frames_.size()) {
    throw InvalidInput("frame " + std::to_string(i) + " is out of range: the log " + dir_.string() + " has " +
                       std::to_string(frames_.size()) + " frames");
  }
  return frames_[i];
}

Image ReplayLog::image(std::size_t i) const { return readPng(dir_ / frame(i).image); }

std::optional<Image> ReplayLog::mask(std::size_t i) const {
  const LogFrame& f = frame(i);
  if (!f.mask) return std::nullopt;
  return readPng(dir_ / *f.mask);
}

}  // namespace mapnav
