#pragma once
// Path agreement (`mapnav log track`, docs/kitti.md; `mapnav replay` and `run` when they have the
// truth, docs/mission-format.md): how well the road a pipeline found agrees with where the vehicle
// really drove next. A car keeps its lane, so its own future path, taken from a
// log's truth poses, lies on the road, and its offset from the road's centre line is nearly constant
// from frame to frame: a road found that misses the path, a centre line that turns away from it, and
// an offset that jumps are the finder's errors.
//
// Frames and units: the future path and the centre line live in the frame's vehicle frame (x forward,
// y left, metres, the vehicle's reference point at the origin); pixels are image coordinates (u right,
// v down); angles are degrees, as the CLI prints them.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/tokens/detected_object.h"

namespace mapnav {

/// Where the path is sampled and what counts as agreement (the defaults: docs/kitti.md's goals).
struct PathAgreementOptions {
  double near_m = 2.0;    ///< the first sample's arc length along the path from the vehicle, m
  double far_m = 15.0;    ///< the last sample's, m (> near_m)
  double step_m = 0.25;   ///< the samples' spacing in arc length, m (> 0)
  /// A path that reaches less far than this (the log ends) is "path too short": the frame is not
  /// measured. The default leaves 5 m of samples from near_m.
  double min_reach_m = 7.0;
  /// The path's direction is the line fitted to its samples between these arc lengths, m; a path that
  /// does not reach direction_far_m gives no angle.
  double direction_near_m = 5.0;
  double direction_far_m = 10.0;
  /// The lateral offset between the path and the centre line is measured at this x ahead, m.
  double offset_ahead_m = 7.5;
  /// A frame agrees when at least this fraction of its path in view lies inside the road found.
  double inside_goal = 0.95;
  /// A centre line agrees when it is within this angle of the path's direction, degrees.
  double angle_goal_deg = 3.0;
  /// Consecutive frames agree when their offsets differ by at most this, m.
  double offset_jump_goal_m = 0.3;

  /// Throws InvalidInput ("PathAgreementOptions::step_m = 0: must be finite and > 0") for a bad field.
  void validate() const;
};

/// The options' names, rules and descriptions, the rules between fields (far_m > near_m, ...) after
/// the fields' own; validate() checks them.
const OptionTable<PathAgreementOptions>& pathAgreementOptionTable();

/// The truth poses of a run's frames by frame index, world frame; nothing where a frame has none:
/// what futurePath reads (`log track` takes a log's, a mission run the log's or the simulator's).
using TruthPoses = std::vector<std::optional<Pose2>>;

/// The truth poses of a log's frames, in order.
TruthPoses truthPoses(const std::vector<LogFrame>& frames);

/// The vehicle's future path at frame `i`: the truth positions of frames i + 1, i + 2, ... (up to
/// the first frame without truth) in frame i's vehicle frame, as a polyline from the origin,
/// resampled every step_m of arc length from near_m to far_m (or to where the path ends, when that is
/// nearer). Empty when frame i has no truth or the path reaches less than min_reach_m.
std::vector<Vec2> futurePath(const TruthPoses& truth, std::size_t i, const PathAgreementOptions& options = {});
/// The same on a log's frames: futurePath(truthPoses(frames), i, options).
std::vector<Vec2> futurePath(const std::vector<LogFrame>& frames, std::size_t i, const PathAgreementOptions& options = {});

/// Whether a frame's path could be measured.
enum class PathStatus {
  Measured,
  NoTruth,    ///< the frame has no truth pose
  TooShort,   ///< the log ends less than min_reach_m ahead (or the next frame has no truth)
  OutOfView,  ///< no sample of the path is in the image
};
/// "measured", "no truth", "path too short", "path out of view".
std::string_view toString(PathStatus status);

/// One frame's agreement.
struct PathAgreement {
  PathStatus status = PathStatus::Measured;
  std::vector<Vec2> path;        ///< the future path's samples, vehicle frame, m (futurePath)
  std::vector<Vec2> path_image;  ///< the samples in view, pixels, in order
  std::size_t out_of_view = 0;   ///< samples left out: behind the camera or outside the image
  std::size_t inside = 0;        ///< samples in view inside the road found
  bool road_found = false;       ///< the detection succeeded and gave a road region
  bool centre_line = false;      ///< the detection succeeded and gave a centre line
  /// inside / path_image.size(); 0 when the detection failed or gave no road region; nothing when
  /// the frame is not measured.
  std::optional<double> inside_fraction;
  /// The share of the ground in view that region_image covers, 0..1, counted on a lattice of every
  /// 4th pixel of every 4th row (a pixel sees the ground when Camera::backproject meets it): the
  /// trivial region "everything below the horizon" holds every path and scores 1, so a region holds
  /// the path usefully only with a share well under 1. 0 when the detection failed; nothing when it
  /// gives no region_image or the frame is not measured.
  std::optional<double> ground_share;
  /// The path's unit direction over direction_near_m..direction_far_m (a least-squares line, pointing
  /// ahead); nothing when the path does not reach direction_far_m.
  std::optional<Vec2> path_direction;
  /// The path's y where it first reaches x = offset_ahead_m, m; nothing when it does not.
  std::optional<double> path_y_ahead;
  /// The angle between the centre line found and path_direction, degrees, 0..90; nothing without
  /// either.
  std::optional<double> angle_deg;
  /// path_y_ahead minus the centre line's y at x = offset_ahead_m (the line extended), m: positive
  /// when the vehicle drives left of the centre line found; nothing without either.
  std::optional<double> offset_m;
};

/// The road found: the detection's region_image (pixels) when it has 3 or more vertices, else its
/// region_vehicle (on the ground); none when the detection failed or has neither. A sample is in
/// view when it projects (Camera::projectGround) inside the image (Camera::inImage); inside when its
/// pixel lies in region_image (the boundary counts as inside), or the sample itself in region_vehicle.
PathAgreement pathAgreement(std::vector<Vec2> path, const DetectedObject& detection, const Camera& camera,
                            const PathAgreementOptions& options = {});

/// The same for frame `i` of a run: futurePath, then pathAgreement; NoTruth or TooShort when
/// futurePath is empty. (pathAgreement of an empty path is TooShort.)
PathAgreement pathAgreement(const TruthPoses& truth, std::size_t i, const DetectedObject& detection,
                            const Camera& camera, const PathAgreementOptions& options = {});
/// The same on a log's frames: pathAgreement(truthPoses(frames), i, ...).
PathAgreement pathAgreement(const std::vector<LogFrame>& frames, std::size_t i, const DetectedObject& detection,
                            const Camera& camera, const PathAgreementOptions& options = {});

/// What pathAgreement reads of a detection and nothing else: its status, region_image,
/// region_vehicle and centerline_vehicle. A run keeps this of each frame's detection until the
/// frame's future path is known (the masks and lines would cost memory for nothing).
DetectedObject roadFound(const DetectedObject& detection);

/// A run's agreement over its frames, in order. Only measured frames count. Frames where the
/// detection failed or found no road region count as 0 inside; frames without a centre line count as
/// not within angle_goal_deg, and a pair where either frame has no offset as not within
/// offset_jump_goal_m. Medians are nearest-rank (the lower middle value of an even count). Fractions
/// and medians are nothing when nothing was counted, and the angle's and the offset's fractions also
/// when no frame had a centre line (not a centre-line pipeline).
struct PathAgreementSummary {
  std::size_t frames = 0;           ///< frames run
  std::size_t measured = 0;         ///< frames with a path in view
  std::size_t no_truth = 0;         ///< unmeasured: PathStatus::NoTruth
  std::size_t path_too_short = 0;   ///< unmeasured: PathStatus::TooShort
  std::size_t out_of_view = 0;      ///< unmeasured: PathStatus::OutOfView
  std::size_t no_region = 0;        ///< measured frames with no road found (failed or no region): 0 inside
  std::optional<double> median_inside;         ///< over the measured frames
  std::optional<double> median_ground_share;   ///< over the measured frames that have one
  std::size_t inside_goal_frames = 0;          ///< measured frames with inside_fraction ≥ inside_goal
  std::optional<double> inside_goal_fraction;  ///< inside_goal_frames / measured

  std::size_t centre_line_frames = 0;  ///< frames run with a centre line (0: not a centre-line pipeline)
  std::size_t angle_frames = 0;        ///< measured frames whose path gives a direction
  std::size_t angle_missing = 0;       ///< of those, frames without a centre line
  std::optional<double> median_angle_deg;     ///< over the frames with an angle
  std::size_t angle_goal_frames = 0;          ///< of angle_frames, those with angle ≤ angle_goal_deg
  std::optional<double> angle_goal_fraction;  ///< angle_goal_frames / angle_frames
  std::size_t offset_pairs = 0;        ///< consecutive measured frames both giving path_y_ahead
  std::size_t offset_missing = 0;      ///< of those, pairs where either frame has no offset
  std::optional<double> median_offset_jump_m;      ///< |Δ offset| over the pairs with both offsets
  std::size_t offset_goal_pairs = 0;               ///< of offset_pairs, those with |Δ offset| ≤ offset_jump_goal_m
  std::optional<double> offset_goal_fraction;      ///< offset_goal_pairs / offset_pairs
};

PathAgreementSummary summarizePathAgreement(const std::vector<PathAgreement>& frames,
                                            const PathAgreementOptions& options = {});

/// |Δ offset| between frame i − 1 and frame i (i ≥ 1) when both have an offset, m.
std::optional<double> offsetJump(const std::vector<PathAgreement>& frames, std::size_t i);

/// The summary as `--json` prints it (`mapnav log track`'s and `mapnav replay` / `run`'s
/// "path_agreement", docs/kitti.md): one JSON object, on one line — {"path_m", "goals", "frames",
/// "measured", "unmeasured", "no_road_found", "median_inside", ..., "offset_goal_fraction"}.
std::string pathAgreementJson(const PathAgreementSummary& summary, const PathAgreementOptions& options);

/// The summary for people, as both commands print it: a heading line "path agreement (the true future
/// path 2-15 m ahead, from TRUTH_FROM):" and the figures' lines under it, two spaces further in; every
/// line begins with `indent` and ends in a newline.
std::string pathAgreementText(const PathAgreementSummary& summary, const PathAgreementOptions& options,
                              const std::string& truth_from = "the log's truth", const std::string& indent = "");

}  // namespace mapnav
