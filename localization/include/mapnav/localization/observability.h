#pragma once
// The along-road observability of a line measurement (Wallace 1985, 2.2.3): "when only straight
// portion of the road is in the view frame, the measurement [...] can constrain the vehicle position
// and orientation only perpendicular to the road. In such case, the location along the road is
// calculated using the vehicle motion." Which of the vehicle's directions an information matrix
// over (x, y, heading) constrains.
#include <vector>

#include "mapnav/geometry/types.h"

namespace mapnav {

/// Which directions a measurement constrains, from its information matrix. Along and lateral are
/// the vehicle's axes at `heading` (forward x and left y), so "along" is along the road while the
/// vehicle follows one. A direction is observed when it lies within 45° of the span of the
/// eigenvectors whose eigenvalue reaches `min_information`. (Line measurements leave unobserved
/// either nothing, one pure translation along parallel lines, or everything.)
struct Observability {
  bool lateral = false;
  bool along = false;
  bool heading = false;
  /// Unit eigenvectors (x, y, heading) of the unobserved directions, smallest eigenvalue first.
  std::vector<Vec3> unobserved;
};

/// `information` over (x, y, heading) in the world frame (1/m^2, 1/(m rad), 1/rad^2); `heading` in
/// rad; `min_information` in the information's units (1: a standard deviation of 1 m or 1 rad).
Observability observability(const Mat3& information, double heading, double min_information = 1.0);

}  // namespace mapnav
