// A run's path agreement for people and programs (mapnav/mission/path_agreement.h): the JSON object
// and the lines that `mapnav log track` and `mapnav replay` / `run` print, written once for both.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "mapnav/core/json.h"
#include "mapnav/mission/path_agreement.h"

namespace mapnav {

namespace {

/// `v` rounded to `digits` decimals, or null.
Json roundedOrNull(const std::optional<double>& v, int digits) {
  if (!v) return nullptr;
  const double scale = std::pow(10.0, digits);
  return std::round(*v * scale) / scale;
}

/// `v` with `digits` decimals, or "-".
std::string fixedOrDash(const std::optional<double>& v, int digits) {
  if (!v) return "-";
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, *v);
  return text;
}

/// "K of N (K/N)" for a goal met in K of N.
std::string goalCount(std::size_t part, std::size_t whole, const std::optional<double>& fraction) {
  return std::to_string(part) + " of " + std::to_string(whole) + " (" + fixedOrDash(fraction, 3) + ")";
}

}  // namespace

std::string pathAgreementJson(const PathAgreementSummary& s, const PathAgreementOptions& o) {
  const Json j = {
      {"path_m", {o.near_m, o.far_m}},
      {"goals", {{"inside", o.inside_goal}, {"angle_deg", o.angle_goal_deg}, {"offset_jump_m", o.offset_jump_goal_m}}},
      {"frames", s.frames},
      {"measured", s.measured},
      {"unmeasured", {{"no_truth", s.no_truth}, {"path_too_short", s.path_too_short}, {"path_out_of_view", s.out_of_view}}},
      {"no_road_found", s.no_region},
      {"median_inside", roundedOrNull(s.median_inside, 3)},
      {"median_ground_share", roundedOrNull(s.median_ground_share, 3)},
      {"inside_goal_frames", s.inside_goal_frames},
      {"inside_goal_fraction", roundedOrNull(s.inside_goal_fraction, 3)},
      {"centre_line_frames", s.centre_line_frames},
      {"angle_frames", s.angle_frames},
      {"angle_missing", s.angle_missing},
      {"median_angle_deg", roundedOrNull(s.median_angle_deg, 2)},
      {"angle_goal_frames", s.angle_goal_frames},
      {"angle_goal_fraction", roundedOrNull(s.angle_goal_fraction, 3)},
      {"offset_pairs", s.offset_pairs},
      {"offset_missing", s.offset_missing},
      {"median_offset_jump_m", roundedOrNull(s.median_offset_jump_m, 3)},
      {"offset_goal_pairs", s.offset_goal_pairs},
      {"offset_goal_fraction", roundedOrNull(s.offset_goal_fraction, 3)}};
  return j.dump();
}

std::string pathAgreementText(const PathAgreementSummary& s, const PathAgreementOptions& o, const std::string& truth_from,
                              const std::string& indent) {
  std::ostringstream out;
  out << indent << "path agreement (the true future path " << o.near_m << "-" << o.far_m << " m ahead, from "
      << truth_from << "):\n";
  out << indent << "  road found holds >= " << 100 * o.inside_goal << " % of the path in "
      << goalCount(s.inside_goal_frames, s.measured, s.inside_goal_fraction) << " measured frames; median "
      << fixedOrDash(s.median_inside, 3) << "\n";
  out << indent << "  road found covers a median " << fixedOrDash(s.median_ground_share, 3)
      << " of the ground in view (everything below the horizon: 1, and it holds every path)\n";
  if (s.centre_line_frames == 0) {
    out << indent << "  no centre line found: no angle or offset\n";
  } else {
    out << indent << "  centre line within " << o.angle_goal_deg << " deg of the path in "
        << goalCount(s.angle_goal_frames, s.angle_frames, s.angle_goal_fraction) << " frames; median "
        << fixedOrDash(s.median_angle_deg, 2) << " deg (" << s.angle_missing
        << " without a centre line count as not within)\n";
    out << indent << "  offset to the path changes by <= " << o.offset_jump_goal_m << " m in "
        << goalCount(s.offset_goal_pairs, s.offset_pairs, s.offset_goal_fraction) << " consecutive pairs; median "
        << fixedOrDash(s.median_offset_jump_m, 3) << " m (" << s.offset_missing
        << " pairs without both offsets count as not within)\n";
  }
  out << indent << "  not measured: " << s.frames - s.measured << " of " << s.frames << " frames (no truth "
      << s.no_truth << ", path too short " << s.path_too_short << ", path out of view " << s.out_of_view << "); "
      << s.no_region << " measured frames with no road found count as 0 inside\n";
  return out.str();
}

}  // namespace mapnav
