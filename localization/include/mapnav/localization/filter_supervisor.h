#pragma once
// The filter's health: a supervisor that watches each frame's match outcome and says when the pose
// filter, not the lines, is wrong. Its one rule:
//
//   When the gate has rejected the lines of `after_rejections` consecutive frames, each of those
//   frames' lines fit well on their own (no outlier, their end points within `max_rms_m` RMS of
//   their map lines at the pose they give), and the poses they give agree with one another — seen
//   from the estimate, within `agreement_m` across the road and `agreement_deg` in heading — then
//   the filter is inconsistent: widen its pose covariance to (`sigma_m`, `heading_sigma_deg`) and
//   match the frame again.
//
// Off by default (after_rejections 0): where it widened on the random-campus suite and park_loop's
// worlds, no run that failed without it reached its goal with it (docs/measurements.md).
//
// A filter that is surer than it should be is refused the same way frame after frame; a pipeline
// misreading a curve gives a different wrong line each frame, and a misread line among correct ones
// cannot lie on its map line with them. The supervisor knows nothing of missions or park mode: the
// caller decides which frames it sees (MapModule: park mode's, docs/mission-format.md) and applies
// the decision (PoseFilter::resetPoseCovariance).
//
// Frames: the fitted poses are in the world frame; their agreement is judged in the estimate's
// vehicle frame (y left, heading counter-clockwise), where a wrong estimate's offset stays put as
// the vehicle drives.
#include <cstddef>
#include <deque>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/types.h"
#include "mapnav/tokens/current_position.h"

namespace mapnav {

struct FilterSupervisorOptions {
  /// The rejected frames in a row it takes (>= 0; 0, the default: never widen). 3 is the value
  /// the rule was made with; off, the filter does as well or better on the random-campus suite and
  /// park_loop's worlds (docs/measurements.md, "The filter's supervisor, on and off").
  int after_rejections = 0;
  /// Each rejected frame's lines must fit together: no outlier, and their end points within this
  /// RMS distance of their map lines at the pose they give, m (> 0; CurrentPosition::rejected_fit_rms_m).
  /// Correct lines refusing a wrong estimate fit to their noise (one line exactly); random campus 15's
  /// tree-shadow edge 0.6 m inside a 4 m road, taken for its edge, fits at 0.09-0.13 m.
  double max_rms_m = 0.05;
  /// The fitted poses, seen from the estimate, agree within this across the road, m (> 0) ...
  double agreement_m = 0.3;
  /// ... and within this in heading, degrees (> 0). park_loop's R4, seed 2: centre lines 1.6 m left,
  /// then 1.7 m left, then 18 degrees right (a misread curve, not a wrong estimate).
  double agreement_deg = 3.0;
  /// The widened covariance: 1-sigma in x and y, m (> 0) ...
  double sigma_m = 0.5;
  /// ... and in heading, degrees (> 0).
  double heading_sigma_deg = 10.0;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

const OptionTable<FilterSupervisorOptions>& filterSupervisorOptionTable();

/// What the supervisor says after a frame.
struct SupervisorDecision {
  /// The filter is inconsistent: reset its pose covariance to `covariance` and match the frame again.
  bool widen = false;
  Mat3 covariance = Mat3::Zero();  ///< when widen: diag(sigma_m², sigma_m², heading_sigma²), m² and rad²
  std::size_t rejections = 0;      ///< when widen: the agreeing rejected frames behind it
};

class FilterSupervisor {
 public:
  /// Throws InvalidInput for bad options.
  explicit FilterSupervisor(const FilterSupervisorOptions& options = {});

  /// One frame's match outcome, as the filter posted it: reads `status`, `pose` (the estimate),
  /// `rejected_fit`, `rejected_fit_rms_m` and `outliers`. A frame that is not a good rejected fit
  /// (accepted, odometry only, lost, an outlier, a poor fit) ends the run of rejections. When the
  /// rule holds, the decision is to widen, and the run starts again from nothing.
  SupervisorDecision observe(const CurrentPosition& outcome);

  /// Forgets the run of rejections (a frame the caller does not show it).
  void clear() { fits_.clear(); }

  /// The good rejected fits in the current run, at most after_rejections.
  std::size_t rejections() const { return fits_.size(); }
  const FilterSupervisorOptions& options() const { return options_; }

 private:
  bool fitsAgree() const;

  FilterSupervisorOptions options_;
  /// The run's fits as changes to the estimate in its vehicle frame (forward m, left m, heading
  /// rad), oldest first.
  std::deque<Vec3> fits_;
};

}  // namespace mapnav
