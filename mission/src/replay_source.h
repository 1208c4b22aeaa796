#pragma once
// The frames of a recorded log (internal to mission/): a FrameSource over the log reader
// (logs/replay_log.h) that owns what a replay does about the log's faults (docs/replay-log-format.md,
// "Faults in replay") and their kinds: a frame whose image is missing, unreadable or not the camera's
// size is skipped and its odometry goes to the next frame; odometry faster than a vehicle goes is a
// spike, replaced by the previous frame's rate; lines the reader skipped are reported by kind. With
// RunOptions::strict, a fault the reader passed is the ValidationError the reader gives for a bad line.
#include <cstddef>
#include <filesystem>
#include <optional>

#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/motion.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/mission/frame_source.h"
#include "mapnav/mission/path_agreement.h"
#include "mapnav/mission/runner.h"

namespace mapnav::detail {

class ReplaySource final : public FrameSource {
 public:
  /// Opens the log (throws as ReplayLog::open; strict: at its first bad line). Uses the options'
  /// strict, max_frames and odometry limits.
  ReplaySource(const std::filesystem::path& log_dir, const RunOptions& options);

  bool next(Driver& driver, SourceFrame& frame) override;
  std::size_t expectedFrames() const override { return total_; }

  /// The log's camera (it took the frames).
  const Camera& camera() const { return *log_.header().camera; }
  /// The odometry of the frames delivered, summed, m.
  double odometryDistance() const { return distance_m_; }
  /// The truth poses of every frame of the log, by frame index (also those skipped and those beyond
  /// max_frames).
  TruthPoses truth() const { return truthPoses(log_.frames()); }
  /// max_frames left frames of the log unread.
  bool stoppedEarly() const { return total_ < log_.frames().size(); }

 private:
  // A fault found here: strict, the reader's error for a bad line (check, JSON Pointer); else kept.
  void fault(const LogFault& f, const char* check, const char* pointer, SourceFrame& frame) const;
  // The lines the reader skipped, up to (not including) `line`.
  void skippedBefore(int line, SourceFrame& frame);
  // Frame i's image, or nothing when it is skipped (a fault, its odometry carried to the next frame).
  std::optional<Image> image(std::size_t i, SourceFrame& frame);
  // The odometry since the previous frame delivered, a spike repaired.
  MotionIncrement odometry(std::size_t i, SourceFrame& frame);

  const RunOptions& options_;
  ReplayLog log_;
  std::filesystem::path frames_file_;
  std::size_t total_ = 0;                     // the frames to read (max_frames)
  std::size_t i_ = 0;                         // the next frame to read
  std::size_t next_skipped_ = 0;              // the next skipped line to report
  bool ended_ = false;                        // next() returned false
  MotionIncrement carried_;                   // the odometry of the frames skipped since the last delivered
  std::optional<double> last_t_;              // the previous frame delivered
  std::optional<MotionIncrement> last_rate_;  // its odometry per second, to replace a spike
  double distance_m_ = 0;
};

}  // namespace mapnav::detail
