#pragma once
// `mapnav log track` (docs/kitti.md): the mapless tracking loop of mapnav/mission/track.h over a
// replay log, its overlays and contact sheet written, its per-frame measurements printed.
#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

#include "mapnav/vision/segmentation_eval.h"

namespace mapnav::cli {

struct LogTrackConfig {
  std::string dir;                       ///< the log folder
  std::string pipeline = "edge-tracker";
  std::string options_json = "{}";
  std::vector<std::string> plugins;
  std::string camera;                    ///< a camera file instead of the log's own; "" = the log's
  TrapezoidOptions trapezoid;            ///< the first frame's road outline (docs/eval.md)
  std::string overlays;                  ///< folder for one overlay per frame, or ""
  std::string contact_sheet;             ///< a PNG of 8 overlays evenly spread over the run, or ""
  /// The image row where the edges and the centre line are measured, pixels; −1 = 85 % of the
  /// height (KITTI: row 314, about 9 m ahead).
  double row = -1;
  std::size_t max_frames = 0;            ///< 0 = every frame
  bool json = false;
};

/// Runs the pipeline over the log; exit 0 when it ran (whatever it found), 1 for invalid input, 2
/// when the log cannot be read or the overlays not written.
int runLogTrack(const LogTrackConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
