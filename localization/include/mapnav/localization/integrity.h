#pragma once
// Integrity: the Map module's check of its own consistency, so that an estimate that has left the
// road is said to have, instead of being posted with a covariance of centimetres. Three tests:
//
//   Innovations. The gate rejects a frame's lines when their d^2 is beyond its chi-square bound
//   (FilterOptions::gate_probability, p): a consistent filter has a frame rejected with probability
//   1 - p. Among the last `window_frames` frames with a line measurement, k rejections have the
//   binomial tail P(>= k); below 1 - `probability` the position is *uncertain*: the lines keep
//   disagreeing with the estimate (at the defaults, 2 rejections in 10 frames).
//
//   Rarely observed. When fewer than `min_observed_fraction` of the frames of the last
//   `max_unobserved_m` driven observed the position (lines fused that fix it across or along the
//   road, or a landmark; a heading alone does not) the position is uncertain too: it is odometry's,
//   whatever its covariance says, and a lone accepted frame among many does not make it sure.
//
//   Departure from odometry. The monitor dead-reckons its own copy of the filter from an anchor
//   (the start, a reset, then every `anchor_every_m` driven while consistent) with the odometry
//   alone. The estimate minus that dead-reckoned pose, over (x, y, heading), has a covariance of at
//   most the sum of the two covariances and the map's own error (the estimate is relative to the
//   map); beyond the chi-square(3) quantile of `departure_probability` the estimate has *departed*:
//   lines matched to the wrong road, or a pipeline's wrong edges accepted one small step at a time,
//   have pulled it where odometry says the vehicle cannot be. The caller puts the estimate back on
//   the dead-reckoned pose with its covariance (PoseFilter::moveTo, resetPoseCovariance) and says
//   the position was lost.
//
// Frames: world (x, y in m, heading in rad), as the pose filter's.
#include <cstddef>
#include <deque>
#include <string_view>
#include <string>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/motion.h"
#include "mapnav/localization/pose_filter.h"
#include "mapnav/tokens/current_position.h"

namespace mapnav {

struct IntegrityOptions {
  /// Frames with a line measurement whose rejections are counted (>= 0; 0: no innovation test).
  /// 10: about a second of frames, long enough that one bad frame does not decide.
  int window_frames = 10;
  /// The innovation test's confidence, in (0, 1): uncertain when so many rejections in the window
  /// would happen to a consistent filter with less than 1 - this probability.
  double probability = 0.999;
  /// The distance over which the frames that observed the position are counted, m (> 0). 20 m: a
  /// few seconds of driving, over which odometry alone drifts decimetres.
  double max_unobserved_m = 20.0;
  /// Uncertain when fewer than this fraction of those frames observed the position, in [0, 1]
  /// (0: no such test). 0.5: most frames of a road in view observe it.
  double min_observed_fraction = 0.5;
  /// The departure test's chi-square(3) quantile, in (0, 1); 1 turns the test off.
  double departure_probability = 0.9999;
  /// While the position is consistent, the dead reckoning restarts from the estimate after this
  /// distance driven, m (> 0): odometry's own error grows with the square of the distance (its
  /// scale and gyro bias), and from a start kilometres back it would excuse any departure.
  double anchor_every_m = 100.0;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

const OptionTable<IntegrityOptions>& integrityOptionTable();

/// What the monitor says after a frame.
struct IntegrityVerdict {
  enum class State {
    Ok,         ///< every test passes
    Uncertain,  ///< the innovations exceed their bound, or the position was rarely observed
    Departed,   ///< the estimate is where odometry says the vehicle cannot be
  };
  State state = State::Ok;
  std::string reason;            ///< for people: which test, its statistic and bound
  int rejections = 0;            ///< the gate's rejections among the window's frames
  double observed_fraction = 1;  ///< of the frames of the last max_unobserved_m, those that observed the position
  double departure_d2 = 0;       ///< the departure's Mahalanobis d^2
  double departure_bound = 0;    ///< ... and its bound
  Pose2 dead_reckoned;           ///< the dead-reckoned pose, world frame
  Mat3 dead_reckoned_covariance = Mat3::Zero();  ///< its covariance (x, y, heading)
};

std::string_view toString(IntegrityVerdict::State state);

class IntegrityMonitor {
 public:
  /// Anchored at `filter`'s state, whose gate_probability the innovation test takes. Throws
  /// InvalidInput for bad options.
  explicit IntegrityMonitor(const PoseFilter& filter, const IntegrityOptions& options = {});

  /// Dead-reckons the anchored copy with the frame's odometry reading over `dt_s` seconds.
  void predict(const MotionIncrement& motion, double dt_s);

  /// Judges the frame's outcome (`position`, as posted after the update) against the filter's state.
  /// Ok frames count towards re-anchoring (the dead reckoning restarts from the estimate after
  /// anchor_every_m); a Departed one empties the innovation window.
  IntegrityVerdict observe(const CurrentPosition& position, const PoseFilter& filter);

 private:
  // Restarts the dead reckoning from `filter`'s state.
  void anchor(const PoseFilter& filter);

  IntegrityOptions options_;
  PoseFilter dead_reckoning_;
  double since_anchor_m_ = 0;
  struct Recent {
    double distance_m = 0;  // driven in the frame
    bool observed = false;  // the position was observed
  };
  std::deque<Recent> recent_;  // the frames of the last max_unobserved_m, oldest first
  double last_distance_m_ = 0;  // the last predict()'s reading, m
  std::deque<bool> window_;  // rejected, for the last frames with lines, oldest first
};

}  // namespace mapnav
