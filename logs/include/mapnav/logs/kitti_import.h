#pragma once
// KITTI odometry sequences (the images, `poses.txt`, `calib.txt`, optionally `times.txt`) as
// replay logs with truth (docs/replay-log-format.md; the command is `mapnav log import-kitti`,
// docs/kitti-import.md).
//
// KITTI's poses are camera-to-world 3×4 matrices [R | t], row-major, in the first camera's frame
// (x right, y down, z forward, metres). The log's world frame is that camera's ground frame in
// mapnav's convention: x = KITTI z (forward at frame 0), y = −KITTI x (left), heading counter-
// clockwise from x. The vehicle's pose is the camera's foot point on the ground and its heading the
// camera's optical axis projected onto the ground: for a pose [R | t],
//     x = t_z,  y = −t_x,  heading = atan2(−R_02, R_22).
#include <cstddef>
#include <filesystem>
#include <string>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/types.h"

namespace mapnav {

struct KittiImportOptions {
  /// The optical centre's height above the road, m (> 0). KITTI's cameras are about 1.65 m up.
  double camera_height_m = 1.65;
  /// The optical axis' angle below the horizon, degrees (−90..90). KITTI's is close to level.
  double camera_tilt_deg = 0.0;
  /// Frame rate, Hz (> 0): the frames are 1/rate apart when the sequence has no times.txt, and the
  /// log's nominal rate. KITTI records at 10 Hz.
  double frame_rate_hz = 10.0;
  /// The image folder inside the sequence; "" = the first folder named image_* in sorted order
  /// (image_0, KITTI's left grey camera, when present).
  std::string images;
  /// The log's name; "" = "KITTI " and the sequence folder's name.
  std::string name;

  /// Throws InvalidInput naming the field and its value.
  void validate() const;
};

/// KittiImportOptions' fields by name, with their rules.
const OptionTable<KittiImportOptions>& kittiImportOptionTable();

struct KittiImportResult {
  std::size_t frames = 0;
  double distance_m = 0;        ///< the sum of the odometry distances
  double duration_s = 0;        ///< last frame's t − first frame's
  std::filesystem::path images; ///< the image folder read
  std::string calib_row;        ///< "P0", "P2", ...: the projection matrix the camera came from
  int width = 0, height = 0, channels = 0;
};

/// The ground-plane vehicle pose of one KITTI camera-to-world matrix, row-major (r00 r01 r02 tx
/// r10 ... tz), as in the header comment.
Pose2 kittiGroundPose(const double (&matrix)[12]);

/// Reads the sequence in `dir` and writes the log folder `out` with ReplayLogWriter (complete or not
/// at all), plus `out/camera.json`, the camera as a mapnav-camera/1 file. Every frame gets its truth
/// and the odometry since the previous frame (the first: none). The images are stored as they are
/// (grey stays grey). Throws IoError when a file or folder is missing or cannot be read, and
/// ValidationError naming the file and line for a bad poses.txt, calib.txt or times.txt: a
/// malformed number, a line without 12 numbers, a matrix that is not a rotation, fewer or more
/// pose lines than images. InvalidInput for images of different sizes.
KittiImportResult importKitti(const std::filesystem::path& dir, const std::filesystem::path& out,
                              const KittiImportOptions& options = {});

}  // namespace mapnav
