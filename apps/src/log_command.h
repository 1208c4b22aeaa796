#pragma once
// `mapnav log info` and `mapnav log frame`: looking into a replay log (docs/replay-log-format.md).
#include <cstddef>
#include <iosfwd>
#include <string>

#include "mapnav/logs/kitti_import.h"
#include "mapnav/logs/kitti_raw_import.h"

namespace mapnav::cli {

struct LogInfoConfig {
  std::string dir;    ///< the log folder
  bool json = false;  ///< print the summary as one JSON object instead of text
};

/// `mapnav log info DIR`: frames, duration, mean frame rate, odometry distance, which of truth /
/// GNSS / masks the frames carry, the camera and the map. Exit 0; 1 when the log is invalid (the
/// issues on `err`); 2 when it cannot be read.
int runLogInfo(const LogInfoConfig& config, std::ostream& out, std::ostream& err);

struct LogFrameConfig {
  std::string dir;         ///< the log folder
  std::size_t index = 0;   ///< 0-based frame number
  std::string output;      ///< the PNG to write (required)
};

/// `mapnav log frame DIR N -o OUT.png`: frame N with its ground-truth road mask overlaid (road
/// pixels blended 40 % towards magenta (255, 0, 255), the road's outline drawn in magenta). A frame
/// without a mask is written as it is, with a note on `err` (exit 0). Exit 1 when N is out of range
/// or the log is invalid, 2 on I/O errors or without an output.
int runLogFrame(const LogFrameConfig& config, std::ostream& out, std::ostream& err);

struct LogImportKittiConfig {
  std::string dir;             ///< the KITTI sequence folder
  std::string output;          ///< the log folder to write (required; must not exist or be empty)
  KittiImportOptions options;
};

/// `mapnav log import-kitti DIR -o LOGDIR` (docs/kitti.md): a KITTI odometry sequence as a replay
/// log with truth and odometry, and LOGDIR/camera.json. Exit 0; 1 when the sequence is invalid
/// (the file and line on `err`, nothing written); 2 when it cannot be read or the log not written.
int runLogImportKitti(const LogImportKittiConfig& config, std::ostream& out, std::ostream& err);

struct LogImportKittiRawConfig {
  std::string dir;             ///< the drive folder (DATE/DATE_drive_NNNN_sync; calibration in DATE/)
  std::string output;          ///< the log folder to write (required; must not exist or be empty)
  std::string origin;          ///< "LAT,LON" or "" (the first OXTS fix)
  KittiRawImportOptions options;
};

/// `mapnav log import-kitti-raw DRIVE -o LOGDIR` (docs/real-drive.md): a KITTI raw drive as a replay
/// log with truth, GNSS fixes and odometry from its OXTS packets, and LOGDIR/camera.json. Exit codes
/// as import-kitti's.
int runLogImportKittiRaw(const LogImportKittiRawConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
