// Which of the vehicle's directions a line measurement's information constrains (observability.h).
#include "mapnav/localization/observability.h"

#include "line_problem.h"
#include "mapnav/geometry/pose2.h"

namespace mapnav {

using namespace localization::detail;

Observability observability(const Mat3& information, double heading, double min_information) {
  Observability out;
  const auto [observed, unobserved] = splitDirections(information, min_information);
  out.unobserved = unobserved;
  // A direction is observed when its component in the unobserved span is below sin 45°.
  auto isObserved = [&](const Vec3& d) {
    double hidden = 0;
    for (const Vec3& n : out.unobserved) hidden += n.dot(d) * n.dot(d);
    return hidden < 0.5;
  };
  const Vec2 f = unitVector(heading);
  out.along = isObserved(Vec3(f.x(), f.y(), 0));
  out.lateral = isObserved(Vec3(-f.y(), f.x(), 0));
  out.heading = isObserved(Vec3(0, 0, 1));
  return out;
}

}  // namespace mapnav
