#pragma once
// Camera calibration (Wallace et al. 1985, 3.5.2): the parameters that carry image points to the
// local ground plane around the vehicle.
//
//  * Tilt from the vanishing line: two straight lines on the ground (or in any plane parallel to
//    it), parallel to each other, such as the paper's "hood ornament" poles bolted to the vehicle,
//    are imaged as two lines that meet at a vanishing point on the horizon. The actual horizon need
//    not be in view.
//  * Scale factors: metre sticks laid on the ground, measured in a rectified image.
//  * Focal length, principal point and lens distortion: the modern method, a chessboard seen at
//    several poses (Zhang's method, cv::calibrateCamera).
#include <optional>
#include <string>
#include <vector>

#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/image/image.h"

namespace mapnav {

/// The image point where the (infinite) lines through two image segments meet, after removing the
/// lens distortion of `intrinsics` (pin-hole, OpenCV k1 k2 p1 p2 [k3]) from their end points.
/// Nothing when the lines are parallel in the image (the vanishing point is at infinity).
/// Throws InvalidInput for a degenerate (zero-length, non-finite) segment.
std::optional<Vec2> vanishingPoint(const CameraIntrinsics& intrinsics, const Segment2& line_a, const Segment2& line_b);

/// The camera's tilt (pitch below the horizon, radians, positive looking down) from the images of
/// two lines that are parallel to each other and to the ground (Wallace 1985, 3.5.2 and Figure 6).
///
/// For a pin-hole camera with zero roll the horizon is the image row v_h through the vanishing
/// point of any family of ground-parallel lines, whatever their direction on the ground: in the
/// camera's (yawed) frame a horizontal direction (d_x forward, d_y left, 0), d_x ≠ 0, has camera
/// coordinates x = −d_y, y = −d_x·sin β, z = d_x·cos β, so its vanishing point lies on the row
/// v_h = cy + fy · y / z = cy − fy · tan β, independent of d_y. Hence
///
///     β = atan((cy − v_h) / fy).
///
/// The lines need not point straight ahead (only the vanishing point's row is used), and the
/// actual horizon need not be in the image (v_h may be far above it). Segment end points are in
/// pixels of the (distorted) image; distortion in `intrinsics` is removed first. Roll is assumed
/// zero. Throws InvalidInput when the segments are degenerate or their lines are parallel in the
/// image (lines parallel to the image plane: no vanishing point).
double tiltFromParallelLines(const CameraIntrinsics& intrinsics, const Segment2& line_a, const Segment2& line_b);

/// Metres per rectified pixel along the vehicle's x (forward: the rectified image's rows) and y
/// (left: its columns).
struct ScaleFactors {
  double x_m_per_px = 0;
  double y_m_per_px = 0;
};

/// The rectified image's scale factors from two metre sticks on the ground (Wallace 1985, 3.5.2):
/// their end points in a rectified image (x = column, y = row, pixels) and their known lengths (m),
/// one laid along the vehicle's x axis (forward) and one along its y axis. A stick spanning Δc
/// columns and Δr rows of length L satisfies L² = (Δr · x_m_per_px)² + (Δc · y_m_per_px)²; the two
/// sticks give two such equations, solved exactly, so a stick need not be perfectly aligned with
/// its axis. For perfectly aligned sticks this is x = L_x / |Δr|, y = L_y / |Δc|. Throws
/// InvalidInput when a length is not positive, or the sticks are (nearly) parallel in the image,
/// or the solution is not positive.
ScaleFactors scaleFromSticks(const Segment2& x_stick_px, double x_stick_length_m, const Segment2& y_stick_px,
                             double y_stick_length_m);

/// What a chessboard calibration found.
struct ChessboardResult {
  CameraIntrinsics intrinsics;      ///< pin-hole; distortion k1 k2 p1 p2 k3
  double rms_reprojection_px = 0;   ///< RMS reprojection error over every corner of every used image
  int images_used = 0;
  std::vector<std::string> rejected;  ///< "NAME: reason" for each image not used
  std::vector<std::string> fitted;    ///< "NAME: what was done" for each image cut or padded to the size
};

/// calibrateChessboard()'s default size tolerance, pixels: it takes the one-pixel-larger photos a
/// camera or an editor sometimes writes (the shared set's 1281 x 721 among 1280 x 720), which a user
/// expects used; a rescaled photo or another camera differs by far more.
constexpr int kChessboardSizeTolerancePx = 2;

/// The inner corners of a cols × rows chessboard in an image (sub-pixel, row by row as OpenCV's
/// cv::findChessboardCorners orders them), or nothing when the board is not found. Throws
/// InvalidInput when cols or rows < 2.
std::optional<std::vector<Vec2>> findChessboard(const Image& image, int cols, int rows);

/// A copy of the image (RGB) with the corners drawn as cv::drawChessboardCorners draws them
/// (coloured and joined when `found`, red circles otherwise).
Image drawChessboardCorners(const Image& image, int cols, int rows, const std::vector<Vec2>& corners, bool found);

/// Calibrates a pin-hole camera (fx fy cx cy, k1 k2 p1 p2 k3) from images of a chessboard with
/// cols × rows inner corners and squares of side square_m: cv::findChessboardCorners,
/// cv::cornerSubPix, cv::calibrateCamera. The image size is the one most images have
/// (mostCommonSize(), whatever their order); an image within `size_tolerance_px` of it in both
/// directions is cut or padded at its right and bottom to it (fitToSize(): its pixels keep their
/// coordinates) and listed in `fitted`; one further off is rejected with its size. Images in which
/// the board is not found are rejected too (each named by `names[i]` when given, else "image i").
/// Throws InvalidInput for bad arguments or when fewer than 3 images can be used.
ChessboardResult calibrateChessboard(const std::vector<Image>& images, int cols, int rows, double square_m,
                                     const std::vector<std::string>& names = {},
                                     int size_tolerance_px = kChessboardSizeTolerancePx);

}  // namespace mapnav
