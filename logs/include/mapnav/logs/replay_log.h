#pragma once
// The replay-log format `mapnav-log/1` (docs/replay-log-format.md): a folder holding `log.json`
// (the header: the camera, embedded, the frame rate, the map it was recorded on), `frames.jsonl`
// (one JSON object per camera frame: time, image path, odometry since the previous frame, optional
// ground truth, road mask and GNSS fix) and the PNG images those lines name. Missions run "in
// replay" over such a log. Distances are metres, times seconds; angles are degrees in the files and
// radians here.
#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mapnav/core/issue.h"
#include "mapnav/core/option_table.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/motion.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/image/image.h"

namespace mapnav {

inline constexpr std::string_view kLogFormat = "mapnav-log/1";

/// A satellite position fix in the world frame.
struct GnssFix {
  Vec2 position = Vec2::Zero();  ///< world frame, m
  double sigma_m = 0.0;          ///< 1-sigma horizontal error, m (> 0)

  bool operator==(const GnssFix&) const = default;
};

/// One camera frame of a log.
struct LogFrame {
  double t = 0.0;                   ///< seconds since an arbitrary epoch; finite, strictly increasing
  std::string image;                ///< PNG path relative to the log folder ("images/000000.png")
  std::optional<std::string> mask;  ///< ground-truth road mask PNG (1 channel, 255 = road), relative path
  MotionIncrement odometry;         ///< measured since the previous frame (wheel encoders and a gyro)
  std::optional<Pose2> truth;       ///< the vehicle's true pose, world frame
  std::optional<GnssFix> gnss;      ///< a GNSS fix taken with this frame
};

/// `log.json`: what every frame of the log shares. Movable and copyable (the camera is shared and
/// immutable).
struct LogHeader {
  std::string name;                     ///< for people; "" when absent
  std::shared_ptr<const Camera> camera; ///< the camera that took every frame (required)
  std::string map;                      ///< the map the log was recorded on, as written ("" = none);
                                        ///< a relative path is relative to the log folder
  double frame_rate_hz = 10.0;          ///< nominal frame rate, Hz (> 0, finite)

  /// Throws InvalidInput ("LogHeader::FIELD = VALUE: must be ...") unless camera is set and
  /// frame_rate_hz is finite and > 0.
  void validate() const;
};

/// LogHeader's fields but the camera (an object), with their rules: validate() and log.json's reader.
const OptionTable<LogHeader>& logHeaderOptionTable();

/// Writes a log folder so that it appears complete or not at all: everything goes into the sibling
/// folder `DIR.partial-<pid>` and finish() renames that to DIR. If finish() is never called (an
/// exception, an early return), the destructor removes the temporary folder; a crash leaves only
/// `DIR.partial-<pid>`, never a half-written DIR. The same inputs give the same bytes.
class ReplayLogWriter {
 public:
  /// Validates the header (InvalidInput), creates the temporary folder and writes its log.json
  /// (IoError). A stale temporary folder of the same name is replaced.
  ReplayLogWriter(std::filesystem::path dir, LogHeader header);
  ~ReplayLogWriter();
  ReplayLogWriter(const ReplayLogWriter&) = delete;
  ReplayLogWriter& operator=(const ReplayLogWriter&) = delete;

  /// Appends a frame. `frame.image` and `frame.mask` are ignored and replaced by the paths the
  /// writer picks (`images/%06d.png`, and `masks/%06d.png` when `mask` is not null). Throws
  /// InvalidInput, writing nothing, when t is not finite or not greater than the previous frame's,
  /// when any odometry / truth / GNSS value is not finite or sigma_m ≤ 0, when the image is not
  /// the camera's size with 1 or 3 channels, or the mask not the camera's size with 1 channel.
  /// Returns the frame as recorded (with its paths).
  LogFrame add(const LogFrame& frame, const Image& image, const Image* mask = nullptr);

  /// Writes frames.jsonl and renames the temporary folder to DIR. Throws IoError if DIR exists and
  /// is not an empty folder (an empty folder is replaced), or on any file-system failure (the
  /// temporary folder is then left for the destructor to remove). Calling add() or finish() after a
  /// successful finish() throws InvalidInput.
  void finish();

  std::size_t frameCount() const { return count_; }
  /// The temporary folder being written.
  const std::filesystem::path& partialDir() const { return tmp_; }

 private:
  std::filesystem::path dir_;
  std::filesystem::path tmp_;
  LogHeader header_;
  std::string lines_;  ///< frames.jsonl so far
  std::size_t count_ = 0;
  std::optional<double> last_t_;
  bool finished_ = false;
};

/// How ReplayLog::open reads a log.
struct ReadOptions {
  /// false: the first bad frames.jsonl line throws ValidationError. true: bad lines are skipped,
  /// counted (ReplayLog::skipped()) and their issues kept as warnings (ReplayLog::issues()).
  bool skip_bad_frames = false;
  /// Also decode every image and mask (slow): a PNG that does not decode is `log.corrupt_image`, one
  /// that is not the camera's size (or a mask that is not 1-channel) is `log.image_size`.
  bool verify_images = false;
  /// Lines longer than this many bytes are `log.line_too_long` without being parsed (> 0).
  std::size_t max_line_bytes = std::size_t{1} << 20;

  /// Throws InvalidInput ("ReadOptions::max_line_bytes = 0: must be > 0").
  void validate() const;
};

/// ReadOptions' fields by name, with their rules.
const OptionTable<ReadOptions>& readOptionTable();

/// A frames.jsonl line that ReadOptions::skip_bad_frames skipped, with what could be read of it.
struct SkippedLine {
  int line = 0;                      ///< 1-based line number in frames.jsonl
  std::string check;                 ///< its first issue's check ("log.missing_image", "log.time_order", ...)
  std::string message;               ///< that issue's message (the JSON Pointer first, as in issues())
  std::string where;                 ///< that issue's JSON Pointer inside the line ("/image", "/t", "")
  std::optional<double> t;           ///< the line's `t`, when it could be read
  std::optional<MotionIncrement> odometry;  ///< the line's odometry, when it could be read (the vehicle still moved)
};

/// Reads one frames.jsonl line, as ReplayLog::open does for each: `dir` is the log folder (the image
/// and mask must exist in it; with options.verify_images, decode), `last_t` the previous frame's
/// time, `camera` the header's. Appends every issue (errors, with their JSON Pointer in `where`, not
/// yet with a line number) to `issues`; nothing when the line is not a valid frame.
std::optional<LogFrame> parseLogFrame(std::string_view text, const std::filesystem::path& dir,
                                      const ReadOptions& options, const std::optional<double>& last_t,
                                      const Camera& camera, Issues& issues);

/// A log folder, read and checked. The images are read on demand.
class ReplayLog {
 public:
  /// Reads DIR/log.json and DIR/frames.jsonl and checks every line (the image files exist; with
  /// verify_images, they decode). Throws IoError when DIR, log.json or frames.jsonl cannot be read
  /// (missing), ValidationError (file: the log.json or frames.jsonl path) when log.json is invalid or
  /// (without skip_bad_frames) a frame line is. An empty frames.jsonl is a valid log of 0 frames.
  static ReplayLog open(const std::filesystem::path& dir, const ReadOptions& options = {});

  const std::filesystem::path& dir() const { return dir_; }
  const LogHeader& header() const { return header_; }
  const std::vector<LogFrame>& frames() const { return frames_; }
  /// The number of bad frame lines skipped (always 0 without skip_bad_frames).
  std::size_t skipped() const { return skipped_; }
  /// Warnings: with skip_bad_frames, the issues of every skipped line (with their line numbers, in
  /// frames.jsonl).
  const Issues& issues() const { return issues_; }
  /// With skip_bad_frames, every skipped line in file order (skipped() of them).
  const std::vector<SkippedLine>& skippedLines() const { return skipped_lines_; }
  /// The 1-based frames.jsonl line of frame i. Throws InvalidInput when i is out of range.
  int lineOf(std::size_t i) const;

  /// The header's map path resolved against the log folder; nothing when the log names no map.
  std::optional<std::filesystem::path> mapPath() const;

  /// Frame i's image, read from its PNG. Throws InvalidInput when i is out of range or the PNG does
  /// not decode, IoError when it cannot be read.
  Image image(std::size_t i) const;
  /// Frame i's road mask; nothing when the frame has none. Throws as image().
  std::optional<Image> mask(std::size_t i) const;

 private:
  ReplayLog() = default;
  const LogFrame& frame(std::size_t i) const;

  std::filesystem::path dir_;
  LogHeader header_;
  std::vector<LogFrame> frames_;
  std::vector<int> frame_lines_;  ///< frames_[i]'s line in frames.jsonl
  std::size_t skipped_ = 0;
  std::vector<SkippedLine> skipped_lines_;
  Issues issues_;
};

}  // namespace mapnav
