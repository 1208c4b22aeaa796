// The replay source: a recorded log's frames, its faults skipped or repaired and reported by kind.
#include "replay_source.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/core/interrupt.h"
#include "mapnav/geometry/types.h"

namespace mapnav::detail {

namespace {

// The fault a line the reader skipped is, by its check (docs/replay-log-format.md).
LogFaultKind faultKind(const std::string& check) {
  if (check == "log.missing_image") return LogFaultKind::MissingImage;
  if (check == "log.corrupt_image") return LogFaultKind::CorruptImage;
  if (check == "log.image_size") return LogFaultKind::ImageSize;
  if (check == "log.time_order") return LogFaultKind::TimeOrder;
  if (check == "log.truncated") return LogFaultKind::Truncated;
  return LogFaultKind::BadLine;
}

// The motion of two consecutive intervals as one.
void carry(MotionIncrement& into, const MotionIncrement& more) {
  into.distance_m += more.distance_m;
  into.dheading_rad += more.dheading_rad;
}

ReadOptions readOptions(const RunOptions& options) {
  ReadOptions read;
  read.skip_bad_frames = !options.strict;  // strict: the reader throws at the first bad line
  return read;
}

const char* const kCarried = "skipped; its odometry goes to the next frame";

}  // namespace

ReplaySource::ReplaySource(const std::filesystem::path& log_dir, const RunOptions& options)
    : options_(options), log_(ReplayLog::open(log_dir, readOptions(options))), frames_file_(log_dir / "frames.jsonl") {
  const std::size_t frames = log_.frames().size();
  total_ = options.max_frames > 0 ? std::min(options.max_frames, frames) : frames;
}

void ReplaySource::fault(const LogFault& f, const char* check, const char* pointer, SourceFrame& frame) const {
  if (options_.strict) {
    Issue issue;
    issue.severity = Severity::Error;
    issue.check = check;
    issue.where = pointer;
    issue.message = std::string(pointer) + ": " + f.message;
    issue.line = f.line;
    issue.column = 1;
    throw ValidationError(frames_file_.string(), {issue});
  }
  frame.faults.push_back(f);
}

// A frame skipped for its image still moved the vehicle: its odometry goes to the next frame. A line
// out of time order is dropped whole.
void ReplaySource::skippedBefore(int line, SourceFrame& frame) {
  const std::vector<SkippedLine>& skipped = log_.skippedLines();
  for (; next_skipped_ < skipped.size() && skipped[next_skipped_].line < line; ++next_skipped_) {
    const SkippedLine& s = skipped[next_skipped_];
    LogFault f{faultKind(s.check), s.line, s.t, "", "skipped", s.message};
    if (f.kind == LogFaultKind::MissingImage && s.odometry) {
      carry(carried_, *s.odometry);
      f.action = kCarried;
    }
    frame.faults.push_back(f);
  }
}

// A frame whose PNG does not decode, or is not the camera's size, is skipped.
std::optional<Image> ReplaySource::image(std::size_t i, SourceFrame& frame) {
  const LogFrame& f = log_.frames()[i];
  const int line = log_.lineOf(i);
  Image rgb;
  try {
    rgb = toRgb(log_.image(i));
  } catch (const Error& e) {
    carry(carried_, f.odometry);
    fault(LogFault{LogFaultKind::CorruptImage, line, f.t, f.image, kCarried,
                   "image \"" + f.image + "\" is not a readable PNG: " + e.what()},
          "log.corrupt_image", "/image", frame);
    return std::nullopt;
  }
  if (rgb.width != camera().width() || rgb.height != camera().height()) {
    carry(carried_, f.odometry);
    fault(LogFault{LogFaultKind::ImageSize, line, f.t, f.image, kCarried,
                   "image \"" + f.image + "\" is " + std::to_string(rgb.width) + "x" + std::to_string(rgb.height) +
                       "; the log's camera takes " + std::to_string(camera().width()) + "x" +
                       std::to_string(camera().height())},
          "log.image_size", "/image", frame);
    return std::nullopt;
  }
  return rgb;
}

// The odometry since the previous frame delivered (with that of the frames skipped since): faster than
// a vehicle goes, it is a spike and the previous rate stands in for it.
MotionIncrement ReplaySource::odometry(std::size_t i, SourceFrame& frame) {
  const LogFrame& f = log_.frames()[i];
  MotionIncrement odo = carried_;
  carry(odo, f.odometry);
  carried_ = MotionIncrement{};
  const double dt = last_t_ ? f.t - *last_t_ : 1.0 / log_.header().frame_rate_hz;
  if (std::abs(odo.distance_m) > options_.max_odometry_speed_mps * dt ||
      std::abs(odo.dheading_rad) > degToRad(options_.max_odometry_turn_rate_deg_s) * dt) {
    char text[300];
    std::snprintf(text, sizeof text,
                  "odometry %.3f m, %.1f deg in %.3f s is faster than %.2f m/s or %.0f deg/s "
                  "(RunOptions::max_odometry_speed_mps, max_odometry_turn_rate_deg_s)",
                  odo.distance_m, radToDeg(odo.dheading_rad), dt, options_.max_odometry_speed_mps,
                  options_.max_odometry_turn_rate_deg_s);
    fault(LogFault{LogFaultKind::OdometrySpike, log_.lineOf(i), f.t, f.image,
                   last_rate_ ? "odometry replaced by the previous frame's rate" : "odometry replaced by no motion",
                   text},
          "log.odometry_spike", "/odometry", frame);
    odo = last_rate_ ? MotionIncrement{last_rate_->distance_m * dt, last_rate_->dheading_rad * dt} : MotionIncrement{};
  } else {
    last_rate_ = MotionIncrement{odo.distance_m / dt, odo.dheading_rad / dt};
  }
  last_t_ = f.t;
  return odo;
}

bool ReplaySource::next(Driver& /*driver*/, SourceFrame& frame) {
  frame = SourceFrame{};
  if (ended_) return false;
  while (i_ < total_) {
    throwIfInterrupted();
    const std::size_t i = i_++;
    skippedBefore(log_.lineOf(i), frame);
    std::optional<Image> rgb = image(i, frame);
    if (!rgb) continue;
    const LogFrame& f = log_.frames()[i];
    frame.odometry = odometry(i, frame);
    distance_m_ += frame.odometry.distance_m;
    frame.index = i;
    frame.t = f.t;
    frame.rgb = std::move(*rgb);
    frame.truth = f.truth;
    frame.gnss.reset();
    if (f.gnss) frame.gnss = f.gnss->position, frame.gnss_sigma_m = f.gnss->sigma_m;
    frame.image = f.image;
    return true;
  }
  ended_ = true;
  if (!stoppedEarly()) skippedBefore(std::numeric_limits<int>::max(), frame);  // after the last frame
  return false;
}

}  // namespace mapnav::detail
