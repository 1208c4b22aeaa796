// A run for people and programs: the `--json` line (runToJson), the summary (summaryText) and the
// log faults' counts (logFaultsText); path agreement as `mapnav log track` prints it.
#include "mapnav/mission/runner.h"

#include <cmath>
#include <cstdio>

#include "mapnav/core/json.h"
#include "mapnav/core/strprintf.h"

namespace mapnav {

namespace {

// {"missing_image":N, ..., "total":N}: every kind, also the ones that did not happen.
Json logFaultsJson(const LogFaultCounts& counts) {
  Json j = Json::object();
  for (std::size_t k = 0; k < kLogFaultKinds; ++k) j[toString(static_cast<LogFaultKind>(k))] = counts.by_kind[k];
  j["total"] = counts.total();
  return j;
}
}  // namespace

std::string logFaultsText(const LogFaultCounts& counts) {
  std::string kinds;
  for (std::size_t k = 0; k < kLogFaultKinds; ++k) {
    const auto kind = static_cast<LogFaultKind>(k);
    if (counts[kind] == 0) continue;
    kinds += (kinds.empty() ? "" : ", ") + toString(kind) + " " + std::to_string(counts[kind]);
  }
  return std::to_string(counts.total()) + " (" + kinds + ")";
}

std::string consistencyText(const FilterConsistency& c, const std::string& indent) {
  char line[300];
  std::snprintf(line, sizeof line,
                "%sfilter consistency: true error within 2 sigma of the covariance in %.1f %% of frames along, %.1f %% "
                "lateral, %.1f %% heading (consistent: 95.4 %%); NEES mean %s (expected 3)\n",
                indent.c_str(), 100 * c.within_2sigma_along, 100 * c.within_2sigma_lateral, 100 * c.within_2sigma_heading,
                c.nees_frames > 0 ? strprintf("%.2f", c.nees_mean).c_str() : "-");
  return line;
}

std::string runToJson(const MissionRun& run) {
  const MissionMetrics& m = run.metrics;
  auto err = [&](double v, double scale) { return m.has_truth ? Json(roundTo(v, scale)) : Json(nullptr); };
  Json j{{"frames", m.frames},
         {"reached_goal", m.reached_goal},
         {"lateral_rms_m", err(m.estimate.lateral_rms_m, 1e5)},
         {"along_rms_m", err(m.estimate.along_rms_m, 1e5)},
         {"heading_rms_deg", err(m.estimate.heading_rms_deg, 1e4)},
         {"max_error_m", err(m.estimate.max_error_m, 1e5)},
         {"odometry_only_max_error_m", err(m.odometry_only.max_error_m, 1e5)},
         {"vision_failures", m.vision_failures},
         {"replans", m.replans},
         {"latency_ms_median", roundTo(m.latency_ms_median, 1e3)},
         {"latency_ms_p99", roundTo(m.latency_ms_p99, 1e3)},
         {"along_after_intersection_max_m", err(m.along_after_intersection_max_m, 1e5)},
         {"max_offset_from_centre_m", err(m.max_offset_from_centre_m, 1e5)},
         {"min_path_clearance_m", err(m.min_path_clearance_m, 1e5)},
         {"left_path_frames", m.left_path_frames},
         {"stayed_on_path", m.has_truth ? Json(m.stayedOnPath()) : Json(nullptr)},
         // More of the same, for people and the report.
         {"mode", run.mode},
         {"mission", run.mission},
         {"pipeline", run.pipeline},
         {"outcome", run.outcome},
         {"goal_distance_m", roundTo(m.goal_distance_m, 1e4)},
         {"arrived_frame", m.arrived_frame ? Json(*m.arrived_frame) : Json(nullptr)},
         {"estimate_goal_distance_m", roundTo(m.estimate_goal_distance_m, 1e4)},
         {"lateral_max_m", err(m.estimate.lateral_max_m, 1e5)},
         {"along_max_m", err(m.estimate.along_max_m, 1e5)},
         {"heading_max_deg", err(m.estimate.heading_max_deg, 1e4)},
         {"odometry_only_lateral_rms_m", err(m.odometry_only.lateral_rms_m, 1e5)},
         {"odometry_only_along_rms_m", err(m.odometry_only.along_rms_m, 1e5)},
         {"odometry_only_heading_rms_deg", err(m.odometry_only.heading_rms_deg, 1e4)},
         {"within_2sigma_along", err(m.consistency.within_2sigma_along, 1e4)},
         {"within_2sigma_lateral", err(m.consistency.within_2sigma_lateral, 1e4)},
         {"within_2sigma_heading", err(m.consistency.within_2sigma_heading, 1e4)},
         {"nees_mean", m.consistency.nees_frames > 0 ? Json(roundTo(m.consistency.nees_mean, 1e3)) : Json(nullptr)},
         {"intersections_checked", m.intersections_checked},
         {"halts", m.halts},
         {"lost_frames", m.lost_frames},
         {"relocalisations", m.relocalisations},
         {"uncertain_frames", m.uncertain_frames},
         {"departures", m.departures},
         {"ended_by_halt", run.ended_by_halt},
         {"latency_ms_max", roundTo(m.latency_ms_max, 1e3)},
         {"vision_ms_median", roundTo(m.vision_ms_median, 1e3)},
         {"odometry_scale", roundTo(run.odometry_scale, 1e6)},
         {"ground_steps_used", m.ground_steps_used},
         {"image_size", std::to_string(run.image_width) + "x" + std::to_string(run.image_height)},
         {"duration_s", roundTo(run.duration_s, 1e3)},
         {"distance_m", roundTo(run.distance_m, 1e3)},
         {"log_faults", logFaultsJson(m.log_faults)},
         {"path_agreement", m.path_agreement ? Json::parse(pathAgreementJson(*m.path_agreement, run.path_options))
                                             : Json(nullptr)}};
  return j.dump() + "\n";
}

std::string summaryText(const MissionRun& run) {
  const MissionMetrics& m = run.metrics;
  std::string out;
  char line[400];
  std::snprintf(line, sizeof line, "%s (%s, pipeline %s): %s\n", run.mission.c_str(), run.mode.c_str(),
                run.pipeline.c_str(), run.outcome.c_str());
  out += line;
  std::snprintf(line, sizeof line, "  %zu frames, %.1f s, %.1f m driven, route %.1f m through %zu intersections\n", m.frames,
                run.duration_s, run.distance_m, run.route.length_m, run.route.intersections.size());
  out += line;
  auto errors = [&](const char* what, const ErrorStats& s) {
    std::snprintf(line, sizeof line,
                  "  %-16s lateral RMS %.3f m (max %.3f), along RMS %.3f m (max %.3f), heading RMS %.2f deg (max %.2f), "
                  "max error %.3f m\n",
                  what, s.lateral_rms_m, s.lateral_max_m, s.along_rms_m, s.along_max_m, s.heading_rms_deg,
                  s.heading_max_deg, s.max_error_m);
    out += line;
  };
  if (m.has_truth) {
    errors("estimate:", m.estimate);
    errors("odometry alone:", m.odometry_only);
    out += consistencyText(m.consistency, "  ");
    std::snprintf(line, sizeof line,
                  "  along-road error within 2 m after each intersection: max %.3f m (%zu of %zu intersections)\n",
                  m.along_after_intersection_max_m, m.intersections_checked, run.route.intersections.size());
    out += line;
    std::snprintf(line, sizeof line,
                  "  on the path: %s (truth at most %.3f m from the centre line, clearance to the edge %.3f m for a "
                  "%.2f m wide vehicle, %zu frames off the path)\n",
                  m.stayedOnPath() ? "yes" : "NO", m.max_offset_from_centre_m, m.min_path_clearance_m,
                  run.vehicle_width_m, m.left_path_frames);
    out += line;
  } else {
    out += "  no ground truth: errors and path agreement not measured\n";
  }
  if (m.path_agreement) {
    const bool log = run.mode == "replay";
    out += pathAgreementText(*m.path_agreement, run.path_options, log ? "the log's truth" : "the simulator's truth", "  ");
  }
  std::snprintf(line, sizeof line, "  vision failures %zu, halts %zu, replans %zu, position lost in %zu frames, re-localised %zu times\n",
                m.vision_failures, m.halts, m.replans, m.lost_frames, m.relocalisations);
  out += line;
  if (m.uncertain_frames > 0 || m.departures > 0) {
    std::snprintf(line, sizeof line,
                  "  integrity: position uncertain in %zu frames; the estimate departed from odometry %zu times (put back on it)\n",
                  m.uncertain_frames, m.departures);
    out += line;
  }
  if (m.log_faults.total() > 0) {
    out += "  log faults skipped or repaired: " + logFaultsText(m.log_faults) + "\n";
  }
  std::snprintf(line, sizeof line,
                "  loop latency (%dx%d): median %.2f ms, p99 %.2f ms, max %.2f ms (Vision alone: median %.2f ms)\n",
                run.image_width, run.image_height, m.latency_ms_median, m.latency_ms_p99, m.latency_ms_max,
                m.vision_ms_median);
  out += line;
  return out;
}

}  // namespace mapnav
