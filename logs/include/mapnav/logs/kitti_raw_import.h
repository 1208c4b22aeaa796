#pragma once
// A KITTI raw drive (docs/real-drive.md; `mapnav log import-kitti-raw`) as a replay log: the
// rectified colour frames of one camera, the camera from the calibration files, the truth and GNSS
// fixes from the OXTS GPS/IMU packets, and odometry from the OXTS forward speed and yaw rate.
//
// Layout (KITTI's raw data): DATE/calib_cam_to_cam.txt, calib_imu_to_velo.txt, calib_velo_to_cam.txt
// and DATE/DATE_drive_NNNN_sync/{image_02/data/*.png, image_02/timestamps.txt, oxts/data/*.txt,
// oxts/timestamps.txt}; the drive folder is given, the calibration is read from its parent.
//
// Frames. The world frame is east-north (ENU, metres) about `origin` (GeographicLib's
// LocalCartesian); a pose's heading is counter-clockwise from east, the OXTS yaw. The vehicle's
// reference point is the OXTS unit (the IMU) on the ground: the truth is its lat/lon, and the
// camera's mount is where the calibration chain IMU -> Velodyne -> camera 0 -> rectified camera N
// puts the camera's optical centre and axis in the IMU's frame (x forward, y left, z up), with the
// IMU `imu_height_m` above the road.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/logs/gnss.h"
#include "mapnav/map/geodesy.h"

namespace mapnav {

struct KittiRawImportOptions {
  std::string camera = "02";        ///< the camera: image_NN and P_rect_NN ("00".."03"; 02 is the left colour camera)
  std::optional<LatLon> origin;     ///< the world frame's origin; nothing = the first OXTS fix
  /// The OXTS unit's height above the road, m: 0.93 in KITTI's sensor set-up drawing (Geiger et al.
  /// 2013, Fig. 3). The camera's height is this plus its height above the unit from the calibration.
  double imu_height_m = 0.93;
  int gnss_every = 10;              ///< a GNSS fix every n-th frame (1 s at 10 Hz); 0 = none
  /// The fixes: the OXTS positions degraded as a consumer receiver would give them (its seed is
  /// `seed` + 1). The exact OXTS positions are the log's truth, never its GNSS.
  GnssReceiverOptions gnss;
  double scale_error = 0.0;         ///< odometry: relative distance error (0.02: 2 % long)
  double gyro_bias_deg_s = 0.0;     ///< odometry: constant yaw-rate bias, degrees per second
  std::uint64_t seed = 1;           ///< odometry's noise (with scale_error / gyro_bias only biases: no noise)
  std::string name;                 ///< the log's name; "" = "KITTI raw " and the drive folder's name
  /// The frames as a grey camera gives them (greyed(): luminance in every channel), to measure the
  /// pipelines on a grey camera with the colour camera's drive. Default false.
  bool grey = false;

  /// Throws InvalidInput naming the field and its value.
  void validate() const;
};

/// KittiRawImportOptions' fields but the origin, with their rules (scale_error's and
/// gyro_bias_deg_s's are odometryNoiseOptionTable()'s, which they are handed on to).
const OptionTable<KittiRawImportOptions>& kittiRawImportOptionTable();

struct KittiRawImportResult {
  std::size_t frames = 0;
  double distance_m = 0;     ///< along the truth
  double duration_s = 0;
  LatLon origin;             ///< the world frame's origin used
  CameraMount mount;         ///< what the calibration chain gave
  CameraIntrinsics intrinsics;
  std::size_t gnss_fixes = 0;
};

/// The seconds since midnight of a KITTI timestamp "2011-09-26 13:10:51.175862102"; nothing when it
/// is not one.
std::optional<double> kittiTimeOfDay(const std::string& text);

/// Reads the drive at `drive` (and its parent's calibration) and writes the log folder `out`
/// (complete or not at all) with `out/camera.json`. Throws IoError for a missing file or folder,
/// ValidationError naming the file and line for a bad OXTS packet, calibration entry or timestamp,
/// InvalidInput for frames and packets that do not pair up or images of different sizes.
KittiRawImportResult importKittiRaw(const std::filesystem::path& drive, const std::filesystem::path& out,
                                    const KittiRawImportOptions& options = {});

}  // namespace mapnav
