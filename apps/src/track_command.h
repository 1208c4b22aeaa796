#pragma once
// `mapnav log track` (docs/kitti.md): the mapless tracking loop of mapnav/mission/track.h over a
// replay log, its overlays and contact sheet written, its per-frame measurements printed.
#include <cstddef>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/mission/track.h"
#include "mapnav/vision/segmentation_eval.h"

namespace mapnav::cli {

struct LogTrackConfig {
  std::string dir;                       ///< the log folder
  std::string pipeline = "edge-tracker";
  std::string options_json = "{}";
  std::vector<std::string> plugins;
  std::string camera;                    ///< a camera file instead of the log's own; "" = the log's
  /// The first frame's road outline: this image trapezoid (docs/eval.md) when set, else the lane below.
  std::optional<TrapezoidOptions> trapezoid;
  /// The first frame's road outline without a trapezoid: the vehicle's lane on the ground (laneOutline),
  /// this wide and reaching this far ahead, metres. 3 m: a car's lane (set the path's width for a
  /// sidewalk vehicle); 30 m: about as far as the road is more than a few pixels wide.
  double lane_width_m = 3.0;
  double lane_far_m = 30.0;
  /// Tracking frame to frame: a pipeline with a `prior_px` option (cluster-perceptron) keeps to this
  /// many pixels of the road it found a frame before, carried by the odometry, unless `options_json`
  /// sets prior_px itself; 0 = the pipeline's own default. 20: on kitti_vo_seq1 the Hough's maximum
  /// leaves the lane for the verge or the parking strip in 14 of 51 frames without a prior, in none
  /// with 10 to 40 px, and 30 or more let the offset to the path jump (docs/kitti.md).
  double prior_px = 20;
  std::string overlays;                  ///< folder for one overlay per frame, or ""
  std::string contact_sheet;             ///< a PNG of 8 overlays evenly spread over the run, or ""
  /// --row, --max-frames; the path agreement's at its defaults.
  TrackOptions track;
  bool json = false;
};

/// Runs the pipeline over the log; exit 0 when it ran (whatever it found), 1 for invalid input, 2
/// when the log cannot be read or the overlays not written.
int runLogTrack(const LogTrackConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
