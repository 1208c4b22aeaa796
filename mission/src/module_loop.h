#pragma once
// The module loop (internal to mission/), the same in replay and in closed loop: once a frame, in the
// paper's order, Map (prediction) → Vision → Map (matching) → Navigator → Motion Control; the
// operator's resume before them; the trace, the evaluation against the truth and the frame record
// after them. Between frames of a closed loop it is the plant's Driver: Motion Control's command for
// each control step, the true position recorded for "stays on the path".
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/localization/localize.h"
#include "mapnav/map/map.h"
#include "mapnav/mission/blackboard.h"
#include "mapnav/mission/frame_source.h"
#include "mapnav/mission/metrics.h"
#include "mapnav/mission/mission_file.h"
#include "mapnav/mission/modules.h"
#include "mapnav/mission/path_agreement.h"
#include "mapnav/mission/runner.h"
#include "mapnav/mission/trace.h"
#include "mapnav/navigator/steering.h"
#include "mapnav/navigator/vehicle.h"

namespace mapnav::detail {

/// `p` made absolute and canonical where it exists (as written when that fails), for the trace.
std::string absolutePath(const std::filesystem::path& p);

/// The frames' truth poses by frame index (nothing for an index no frame has, or a frame without).
TruthPoses framesTruth(const std::vector<FrameRecord>& frames);

class ModuleLoop final : public Driver {
 public:
  /// `execute`: Motion Control drives (closed loop) or only records (replay). Fills the run's
  /// pipeline, route, start, goal and image size. `world`: the map the frames' world is drawn from,
  /// against which the truth is judged (how far the vehicle is from a road's centre: "on the path");
  /// the modules navigate by `map`. The two are one map but in a simulated world that differs from
  /// its map (sim/map_error.h).
  ModuleLoop(const MissionFile& mission, const Map& map, const Map& world, const Camera& camera,
             const RunOptions& options, bool execute, const VehicleLimits& limits, MissionRun& run);

  /// The trace's header and planned route; `log_dir` as the trace names it ("" in closed loop).
  void header(const std::string& log_dir);
  /// One frame; false when the mission ends here (a halt with no resume).
  bool frame(const SourceFrame& frame);
  /// A fault of the replayed log: recorded, counted and traced (before the next frame's records).
  void fault(const LogFault& f);
  /// The run's metrics, replans and odometry scale, once the frames are done; and, when the run has
  /// truth, each frame's path agreement against `truth` (the truth poses by frame index).
  void finish(const TruthPoses& truth);
  void writeTrace();

  // Driver: Motion Control between frames.
  VehicleCommand command(double t, const Pose2& truth) override;
  bool arrived() const override { return motion_.arrived(); }

  const NavigatorModule& navigator() const { return navigator_; }

 private:
  struct Pending {
    std::size_t before;  // the number of postings queued when it was dropped
    Drop drop;
  };

  bool tracing() const { return !options_.trace.empty(); }
  // The true position between frames (closed loop: every control step), for "stays on the path".
  void observeTruth(const Vec2& position);
  // The frame's evaluation against the truth.
  void evaluate(const Pose2& truth, FrameRecord& r);
  // The trace lines of what was posted and dropped, in the order it happened.
  void flush();

  const MissionFile& mission_;
  const Map& map_;
  const Map& world_;
  const Camera& camera_;
  const RunOptions& options_;
  MissionRun& run_;
  Blackboard board_;
  NavigatorModule navigator_;
  MapModule map_module_;
  VisionModule vision_;
  MotionControlModule motion_;
  PoseFilter odometry_only_;
  PathTracker truth_tracker_;
  TraceWriter trace_;
  std::vector<Posting> postings_;
  std::vector<Pending> drops_;
  std::size_t replans_seen_ = 0;
  std::size_t last_failure_ = 0, halt_start_ = 0;
  std::optional<PathOffset> between_;  // the worst offset since the last frame (observeTruth)
  std::vector<DetectedObject> roads_;  // each frame's detection, what path agreement reads (roadFound)
};

}  // namespace mapnav::detail
