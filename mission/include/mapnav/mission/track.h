#pragma once
// The mapless tracking loop (`mapnav log track`, docs/kitti.md): a vision pipeline over a replay log
// without a map. The first frame's prediction is a bootstrap region in the image (a trapezoid: its
// sides the road's edges, its inside the road); every later frame's is the last frame's detection
// carried forward by the odometry, so that the edges and the centre line are tracked frame to frame
// as the Map's predictions would track them. Image coordinates are pixels (u right, v down); the
// carried edges live in the vehicle frame (x forward, y left, metres). When the log has truth, each
// frame's detection is also held against the vehicle's own future path (path_agreement.h).
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/types.h"
#include "mapnav/image/image.h"
#include "mapnav/mission/path_agreement.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/tokens/detected_object.h"
#include "mapnav/vision_iface/pipeline.h"
#include "mapnav/tokens/predicted_object.h"

namespace mapnav {

struct TrackOptions {
  /// The image row where the edges and the centre line are measured, pixels, at most the image's
  /// last row; −1 = 85 % of the height (KITTI: row 314, about 9 m ahead).
  double row = -1;
  /// Run at most this many frames of the log; 0 = every frame.
  std::size_t max_frames = 0;
  /// How each frame's detection is held against the future path (the log's truth, whose frames
  /// beyond max_frames count too).
  PathAgreementOptions path;
};

/// TrackOptions' own fields and, nested under their names, the path agreement's.
const OptionTable<TrackOptions>& trackOptionTable();

/// One frame's result, measured on the run's row.
struct TrackedFrame {
  bool ok = false;
  std::string reason;                     ///< why the pipeline failed
  std::optional<double> left_u, right_u;  ///< the road region's sides on the row, pixels
  std::optional<double> centre_u;         ///< the centre line on the row, pixels
  PathAgreement path;                     ///< the detection against the vehicle's future path
};

struct TrackRun {
  double row = 0;                    ///< the image row measured on, pixels
  std::vector<TrackedFrame> frames;  ///< one per frame run, in the log's order
  PathAgreementOptions path_options; ///< what the frames' path agreement was measured with

  /// The frames where the pipeline found the road.
  std::size_t tracked() const;
  /// The largest change of `member` between consecutive frames where both have a value, pixels.
  std::optional<double> maxJump(std::optional<double> TrackedFrame::*member) const;
  /// The frames' path agreement summed up (summarizePathAgreement with path_options).
  PathAgreementSummary pathAgreement() const;
};

/// Called once per frame, in order, with what an overlay of it shows: the RGB frame, the prediction
/// the pipeline got, what it found and what was measured of it (with the future path).
using TrackObserver = std::function<void(const Image& rgb, const PredictedObject& prediction,
                                         const DetectedObject& detection, const TrackedFrame& measured)>;

/// The vehicle's own lane as a bootstrap outline in pixels (bottomTrapezoid's order: bottom left,
/// bottom right, top right, top left): the ground strip `width_m` wide centred on the vehicle's
/// x axis, from the ground seen at 98 % of the image's height on its centre column to `far_m` ahead
/// (metres), projected with the camera. Unlike an image trapezoid it means the same on every camera:
/// the road right ahead of a vehicle that stands on it. Throws InvalidInput naming `--lane` when
/// width_m or far_m is not positive and finite, when that row does not see the ground or the far end
/// is not beyond it, or a corner cannot be imaged.
Polygon2 laneOutline(const Camera& camera, double width_m, double far_m);

/// Runs `pipeline` over the log's frames with `camera` (whose image size every frame must have).
/// `bootstrap` is the first frame's road outline in pixels, four corners: bottom left, bottom
/// right, top right, top left (bottomTrapezoid's order); its sides are the edges tracked. Throws
/// InvalidInput for a frame of another size, a bootstrap that does not see the ground, a row outside
/// the image or invalid path options; IoError when a frame cannot be read. Each frame's `path` is
/// measured against the log's truth (pathAgreement); without truth it is PathStatus::NoTruth.
TrackRun trackLog(const ReplayLog& log, VisionPipeline& pipeline, const Camera& camera, const Polygon2& bootstrap,
                  const TrackOptions& options = {}, const TrackObserver& observer = {});

}  // namespace mapnav
