#pragma once
// The centre line of the road ahead from a road region (a mask), for the pipelines that find a
// region and no centre line of their own (the learned network's): as the park road finder's Hough
// gives one (Jochem & Baluja 1993), so that the Map module can steer by it where no road edge is
// labelled. Image pixels (x right, y down, pixel centres at integers); the ground in the vehicle
// frame (x forward, y left, m).
#include <optional>

#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/image/image.h"

namespace mapnav {

struct CentreLineOptions {
  /// Rows that give a centre point at least, else no centre line. ≥ 2
  int min_rows = 6;
  /// The points on the ground span at least this much of the road ahead, m, else no centre line. ≥ 0
  double min_length_m = 2.0;
};

/// Row by row from the bottom of `mask` (1 channel, non-zero inside the road region, each cell
/// `scale` × `scale` pixels of `camera`'s image): the run of region cells that continues the run
/// below it (overlaps it most; the first, in the lowest row with region, the run overlapping
/// `predicted` most — the same grid, may be empty — else the widest), until no run continues it.
/// A run cut by the image's left or right side does not say where the road's middle is and gives
/// no point; the others give the middle of the run, seen on the ground. The centre line is the
/// line through those points weighted by 1 / range² (a pixel's error on the ground grows with the
/// square of its range), from the nearest point's range to the farthest's. Nothing when fewer than
/// min_rows points or a span under min_length_m.
std::optional<Segment2> regionCentreLine(const Image& mask, const Image& predicted, const Camera& camera, int scale,
                                         const CentreLineOptions& options = {});

}  // namespace mapnav
