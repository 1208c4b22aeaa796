#pragma once
// The JSONL trace of a mission run (`mapnav-trace/1`, docs/trace-format.md): one line per token
// posted on the blackboard (time, frame, module, type, payload), plus the records that frame them —
// the mission, the route, each camera frame with its odometry and truth, Motion Control's
// acknowledgement, tokens the blackboard dropped, and the summary. Deterministic: the same inputs
// give the same bytes (no wall-clock time in it; latency is in the run result).
//
// `traceDialogue` reads a trace back and says it as the paper's dialogue (Wallace 1985, Figure 1):
//   Map: Vision will see straight road and cross intersection. ... Detect them.
//   Vision: Ok. I found them. ...
//   Navigator: Drive on it 2.5 meters and turn to right 90 degrees.
//   Motion Control: Ok. I drive.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mapnav/geometry/pose2.h"
#include "mapnav/localization/pose_filter.h"
#include "mapnav/mission/blackboard.h"
#include "mapnav/mission/runner.h"
#include "mapnav/navigator/road_position.h"
#include "mapnav/navigator/route.h"

namespace mapnav {

inline constexpr std::string_view kTraceFormat = "mapnav-trace/1";

/// The first record: what ran.
struct TraceHeader {
  std::string mode;          ///< "replay" or "closed-loop"
  std::string mission;       ///< name
  std::string map;           ///< the map file
  std::string camera_json;   ///< the camera, as a mapnav-camera/1 object
  std::string log;           ///< replay: the log folder ("" in closed loop)
  std::string pipeline;
  RoadPosition start, goal;
  std::vector<RoadPosition> via;
  Pose2 start_pose, goal_pose;
  double speed_mps = 0, frame_rate_hz = 0;
  std::optional<std::size_t> resume_after_frames;
  int image_width = 0, image_height = 0;
};

/// A camera frame with what the sensors (and the evaluation) know of it.
struct TraceFrame {
  std::size_t index = 0;
  double t = 0;
  std::string image;            ///< replay: the PNG, relative to the log folder ("" in closed loop)
  MotionIncrement odometry;     ///< since the previous frame
  std::optional<Pose2> truth;
  std::optional<Pose2> truth_on_map;  ///< the truth on the vehicle's map when the world differs from it (SourceFrame)
  Pose2 odometry_only;          ///< dead reckoning alone from the start
};

class TraceWriter {
 public:
  void header(const TraceHeader& header);
  /// The Navigator's route: `why` is "planned" or "replanned".
  void route(double t, const Route& route, std::string_view why);
  void frame(const TraceFrame& frame);
  /// A fault of the replayed log (`Sensors/LogFault`), at time `t` (the last frame's: the trace's
  /// time never goes back; the line's own is in the payload).
  void fault(double t, const LogFault& fault);
  void posting(const Posting& posting);
  void drop(const Drop& drop);
  /// Motion Control's acknowledgement of the command it holds (null: none).
  void executing(double t, const MotionCommand* command, bool execute, bool turning_in_place = false);
  void summary(const MissionRun& run);

  /// Everything written so far, one record per line.
  const std::string& text() const { return text_; }
  /// Writes the trace atomically. Throws IoError naming the file.
  void save(const std::filesystem::path& path) const;

 private:
  void line(double t, std::string_view module, std::string_view type, const std::string& payload_json);
  std::string text_;
  std::optional<std::size_t> frame_;
};

/// The trace `text` (read from `file`) as the paper's dialogue, one sentence per line, frames
/// introduced by "[frame N, t s]". Throws ValidationError for `file` listing every bad line
/// (Issue::line set, check `trace.not_json`, `trace.field`, `trace.type` or `trace.empty`).
std::string traceDialogue(std::string_view text, const std::string& file);

}  // namespace mapnav
