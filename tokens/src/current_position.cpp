// PositionStatus's and AlongCue's names, as the trace and the mission reports write them.
#include "mapnav/tokens/current_position.h"

namespace mapnav {

std::string_view toString(PositionStatus status) {
  switch (status) {
    case PositionStatus::Corrected: return "corrected";
    case PositionStatus::OdometryOnly: return "odometry-only";
    case PositionStatus::Rejected: return "rejected";
    case PositionStatus::Lost: return "lost";
  }
  return "odometry-only";
}

std::optional<PositionStatus> positionStatusFromString(std::string_view text) {
  for (PositionStatus s : {PositionStatus::Corrected, PositionStatus::OdometryOnly, PositionStatus::Rejected,
                           PositionStatus::Lost}) {
    if (toString(s) == text) return s;
  }
  return std::nullopt;
}

std::string_view toString(AlongCue cue) {
  switch (cue) {
    case AlongCue::None: return "none";
    case AlongCue::Intersection: return "intersection";
    case AlongCue::Landmark: return "landmark";
  }
  return "none";
}

}  // namespace mapnav
