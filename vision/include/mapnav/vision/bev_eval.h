#pragma once
// Scoring in a bird's-eye grid, as the KITTI road benchmark does (docs/eval.md): a metric grid laid
// on the ground ahead of the camera, each cell looked up in the image at the pixel nearest to where
// its centre projects (cells that project outside the image are left out). The grid only chooses
// which pixels are scored, one per cell (PixelSamples); the counting, MaxF and AP are
// segmentation_eval.h's. A pixel near the camera sees less ground than a far one, so a bird's-eye
// score weighs the road by its area on the ground, not in the image.
#include <cstdint>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/image/image.h"
#include "mapnav/vision/segmentation_eval.h"

namespace mapnav {

/// The grid, in KITTI's road frame: x to the right of the camera, z ahead of it, metres, from the
/// ground point below the optical centre, axes along the vehicle's (x right = the vehicle frame's
/// −y, z = its x). The defaults are the KITTI road devkit's (BirdsEyeView: bev_res 0.05,
/// bev_xRange −10..10, bev_zRange 6..46): 400 × 800 cells.
struct BevGrid {
  double x_min_m = -10.0;  ///< left edge (10 m left of the camera)
  double x_max_m = 10.0;   ///< right edge
  double z_min_m = 6.0;    ///< near edge: KITTI starts 6 m ahead, where its camera first sees the road
  double z_max_m = 46.0;   ///< far edge
  double cell_m = 0.05;    ///< cell side

  /// Cells across, round((x_max − x_min) / cell) as KITTI counts them; likewise rows().
  int columns() const;
  int rows() const;
  /// bevGridOptionTable()'s rules: throws InvalidInput naming the first bad field (non-finite
  /// values, min ≥ max, cell ≤ 0, no cell across or along, or more than 20 million cells).
  void validate() const;
};
/// Its table: each option's name (the member's), rule and description.
const OptionTable<BevGrid>& bevGridOptionTable();

/// The grid looked up in one camera's image.
struct BevSampling {
  int columns = 0, rows = 0;
  /// Per cell, row-major with the far row first and the left column first (a map seen from above,
  /// ahead at the top): the row-major index of the pixel its centre projects nearest to, or −1 when
  /// the centre does not project into the image.
  std::vector<std::int32_t> pixel_of_cell;
  /// The pixels of the cells that project into the image, in cell order: what is scored.
  PixelSamples samples;
};

/// Cell (r, c) has its centre at x = x_min + (c + ½) cell, z = z_max − (r + ½) cell; it projects
/// with camera.projectGround and takes the pixel whose centre is nearest (u, v rounded), when the
/// projection lies in the image's pixel area (Camera::inImage).
BevSampling bevSampling(const Camera& camera, const BevGrid& grid);

/// `image` resampled into the grid (columns × rows, same channels): each cell its pixel's value,
/// cells outside the image 0. Throws InvalidInput when a cell's pixel lies outside `image` (an
/// image of another size than the camera's).
Image resampleToBev(const Image& image, const BevSampling& sampling);

}  // namespace mapnav
