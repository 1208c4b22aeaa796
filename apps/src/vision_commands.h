#pragma once
// `mapnav rectify` and `mapnav calibrate chessboard` (Wallace 1985, 3.5): config structs and plain
// functions, callable from tests; cli.cpp parses the options into them.
#include <iosfwd>
#include <string>

#include "mapnav/geometry/segment2.h"
#include <vector>

#include "mapnav/vision/calibrate.h"
#include "mapnav/vision/rectify.h"

namespace mapnav::cli {

struct RectifyConfig {
  std::string image;    ///< the camera frame (PNG, or any format OpenCV reads)
  std::string camera;   ///< mapnav-camera/1 JSON
  std::string output;   ///< the rectified image, PNG
  RectifyOptions options;
  bool undistort = false;  ///< write the frame undistorted (the ideal pin-hole's view) instead of the top view
};
/// The frame warped onto the ground grid (rows: x far → near, columns: y left → right).
int runRectify(const RectifyConfig& config, std::ostream& out, std::ostream& err);

struct CalibrateChessboardConfig {
  std::vector<std::string> images;  ///< photos of the board (PNG, JPEG, ...)
  int cols = 9, rows = 6;           ///< inner corners
  double square_m = 0.025;          ///< side of a square, m
  std::string output;               ///< the mapnav-camera/1 JSON written
  std::string corners_dir;          ///< when set, every image with its detected corners drawn, as PNG
  /// Photos whose width and height are each within this many pixels of the most common size are
  /// cut or padded at the right and bottom to it (pixel coordinates unchanged); others are skipped
  /// (calibrateChessboard(), whose default this is).
  int size_tolerance_px = kChessboardSizeTolerancePx;
};
/// Calibrates a pin-hole camera (focal, principal point, k1 k2 p1 p2 k3) and writes it with a
/// default mount, which the user must fill in; prints the RMS reprojection error.
int runCalibrateChessboard(const CalibrateChessboardConfig& config, std::ostream& out, std::ostream& err);

/// `mapnav calibrate tilt`: the tilt from two ground-parallel lines in the image of `camera_file`;
/// writes the camera with that tilt to `output` when it is not empty.
int runCalibrateTilt(const std::string& camera_file, const Segment2& a, const Segment2& b, const std::string& output,
                     std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
