#pragma once
// Reproducing the road region (Wallace 1985, 2.2.1): a conservative per-pixel threshold, a
// reduction to 8 × 8 blocks with a proportion threshold, one or two dilations and erosions, the one
// connected region that is the road (the component overlapping the prediction most, else the one
// touching the bottom of the image most), then its boundary. The block region decides *which* pixels
// form the road; the reproduced region is the pixel classification inside it (within a margin of a
// block), closed, opened and with its small holes filled, so that its boundary keeps pixel accuracy:
// its main part, and the parts a line (a lane marking, a kerb) splits from it.
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/types.h"
#include "mapnav/image/image.h"

namespace mapnav {

struct RegionOptions {
  int block_size = 8;            ///< block side, pixels. ≥ 1
  double block_fraction = 0.5;   ///< a block is road when at least this fraction of its pixels is. (0, 1]
  int morph_iterations = 1;      ///< block-level closings, then openings (3 × 3). ≥ 0
  int refine_margin_blocks = 1;  ///< the pixel region may reach this many blocks beyond the block region. ≥ 0
  int pixel_morph_px = 2;        ///< pixel-level closing then opening radius, pixels. ≥ 0
  /// Fill the region's holes up to this fraction of its area (leaves, cracks, slab gaps); larger
  /// holes (a car on the road) stay holes. 0 = fill none, 1 = fill every hole. In [0, 1]
  double max_hole_fraction = 0.02;
  /// The road-coloured pixels inside the block region can fall into several parts where a line
  /// crosses the road (a lane marking, a kerb between road and pavement). The mask keeps every
  /// other part within two blocks' side of the main part (16 px at the defaults) that holds at
  /// least this fraction of what the main part holds of the block region; the outline (`contour`)
  /// stays the main part's. ≥ 0; above 1: the main part only.
  double min_part_fraction = 0.1;
  bool reference = false;        ///< OpenCV's morphology instead of the fast binary one (same answer)

  /// regionOptionTable()'s rules. Throws InvalidInput naming the first bad field.
  void validate() const;
};
/// Its table: each option's name (the member's), rule and description.
const OptionTable<RegionOptions>& regionOptionTable();

struct RegionResult {
  bool found = false;
  Image mask;                 ///< 1 channel, 255 inside the reproduced region (its large holes left out)
  std::vector<Vec2> contour;  ///< the outer boundary of its main part (pixel centres), closed ring without repeat
  double area_px = 0;
};

/// `road_pixels`: 1 channel, non-zero where the pixel is classified road. `valid`: where the pixel
/// sees the ground (others are never road). `predicted`: the predicted road in the image (may be
/// empty: then the bottom rule picks the region).
RegionResult reproduceRegion(const Image& road_pixels, const Image& valid, const Image& predicted,
                             const RegionOptions& options = {});

/// The ring filled (1 channel, 255 inside, boundary included), width × height.
Image rasterizePolygon(const Polygon2& ring, int width, int height);

}  // namespace mapnav
