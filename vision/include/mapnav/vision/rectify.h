#pragma once
// Image rectification (Wallace et al. 1985, 3.5.1): the camera frame warped into a map-like view
// of the ground plane, as if flying over the road and looking straight down.
//
// A rectangular grid on the ground (vehicle frame: x forward, y left) is the rectified image: each
// grid point is projected into the camera frame once, through the camera's own lens model (pin-hole
// with distortion, the paper's fish-eye, the equidistant fish-eye), and the result is kept as a
// lookup table, so that every later frame is rectified by table look-ups and bilinear
// interpolation alone.
//
// The rectified image: row 0 is the far edge (x = x_max_m), the last row the near edge
// (x = x_min_m); column 0 is the left edge (y = y_max_m), the last column the right edge
// (y = y_min_m). Pixel (c, r) is the ground point
//   x = x_max_m − (r + 0.5) · metres_per_pixel,  y = y_max_m − (c + 0.5) · metres_per_pixel.
// Grid points the camera does not image (behind it, beyond the lens' field, outside the frame) are
// black.
#include <memory>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/types.h"
#include "mapnav/image/image.h"

namespace mapnav {

struct RectifyOptions {
  /// The ground range rectified, vehicle frame, m: x forward, y left.
  double x_min_m = 1.0, x_max_m = 15.0;
  double y_min_m = -6.0, y_max_m = 6.0;
  /// Ground size of one rectified pixel, m. > 0.
  double metres_per_pixel = 0.02;

  /// rectifyOptionTable()'s rules: throws InvalidInput naming the first bad field (non-finite, min ≥
  /// max, metres_per_pixel ≤ 0, or an output larger than 16384 pixels a side).
  void validate() const;
  /// Rectified image size, pixels: ceil((max − min) / metres_per_pixel).
  int width() const;
  int height() const;
};
/// Its table: each option's name (the member's), rule and description.
const OptionTable<RectifyOptions>& rectifyOptionTable();

class Rectifier {
 public:
  /// Builds the lookup table for this camera (any lens model) once. Validates the options.
  Rectifier(const Camera& camera, RectifyOptions options = {});
  ~Rectifier();
  Rectifier(Rectifier&&) noexcept;
  Rectifier& operator=(Rectifier&&) noexcept;

  /// The rectified frame (same number of channels as `frame`: 1 or 3). Throws InvalidInput when
  /// the frame's size is not the camera's.
  Image apply(const Image& frame) const;

  const RectifyOptions& options() const;
  int width() const;   ///< rectified image width, pixels
  int height() const;  ///< rectified image height, pixels
  /// The ground point (vehicle frame) at the centre of rectified pixel (col, row).
  Vec2 groundAt(double col, double row) const;
  /// The rectified pixel (col, row) of a ground point (may lie outside the image).
  Vec2 pixelAt(const Vec2& ground) const;
  /// Fraction of rectified pixels that see something (their ground point is in the frame).
  double coverage() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The frame as the camera's ideal pin-hole would have taken it: same size, focal lengths and
/// principal point, no lens distortion, so that straight lines in the world are straight in the
/// image. Black where the real lens saw nothing. Throws InvalidInput for a frame of another size or
/// a camera that is not a pin-hole.
Image undistortFrame(const Camera& camera, const Image& frame);

}  // namespace mapnav
