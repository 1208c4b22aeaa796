#include "mapnav/mission/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include "mapnav/navigator/progress.h"

namespace mapnav {

PoseError poseError(const Pose2& estimate, const Pose2& truth, double road_heading) {
  const Vec2 d = estimate.translation() - truth.translation();
  const Vec2 along = unitVector(road_heading);
  PoseError e;
  e.along_m = d.dot(along);
  e.lateral_m = d.dot(leftNormal(along));
  e.heading_rad = normalizeAngle(estimate.heading() - truth.heading());
  e.distance_m = d.norm();
  return e;
}

FrameConsistency frameConsistency(const PoseError& error, const Mat3& covariance, double road_heading) {
  const Vec2 along = unitVector(road_heading);
  const Vec2 left = leftNormal(along);
  const Mat2 position = covariance.topLeftCorner<2, 2>();
  // |e| <= 2 sigma as e^2 <= 4 sigma^2: no square root, and a zero variance holds only a zero error.
  auto within = [](double e, double variance) { return e * e <= 4.0 * variance; };
  FrameConsistency c;
  c.along = within(error.along_m, along.dot(position * along));
  c.lateral = within(error.lateral_m, left.dot(position * left));
  c.heading = within(error.heading_rad, covariance(2, 2));
  const Eigen::LLT<Mat3> llt(covariance);  // fails unless positive definite
  if (llt.info() == Eigen::Success) {
    const Vec2 d = error.along_m * along + error.lateral_m * left;
    const Vec3 e(d.x(), d.y(), error.heading_rad);
    c.nees = e.dot(llt.solve(e));
  }
  return c;
}

PathOffset pathOffset(const Map& map, const Vec2& position, double vehicle_width_m) {
  const auto p = projectToRoad(map, Pose2(position, 0.0), PathOffset::kOffMap);
  if (!p) return PathOffset{PathOffset::kOffMap, 0.0};
  return PathOffset{p->distance, std::max(0.0, map.road(p->position.road).width / 2 - vehicle_width_m / 2)};
}

namespace {
constexpr std::array<std::string_view, kLogFaultKinds> kLogFaultNames = {
    "missing_image", "corrupt_image", "image_size", "time_order", "odometry_spike", "truncated", "bad_line"};
}  // namespace

std::string toString(LogFaultKind kind) { return std::string(kLogFaultNames[static_cast<std::size_t>(kind)]); }

std::optional<LogFaultKind> logFaultKindFromString(std::string_view text) {
  for (std::size_t i = 0; i < kLogFaultNames.size(); ++i) {
    if (kLogFaultNames[i] == text) return static_cast<LogFaultKind>(i);
  }
  return std::nullopt;
}

std::size_t LogFaultCounts::total() const {
  std::size_t n = 0;
  for (const std::size_t c : by_kind) n += c;
  return n;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  // Nearest rank: the smallest value with at least p % of the values at or below it.
  const double rank = std::ceil(p / 100.0 * static_cast<double>(values.size()));
  const std::size_t i = static_cast<std::size_t>(std::clamp(rank, 1.0, static_cast<double>(values.size()))) - 1;
  return values[i];
}

namespace {

struct Accumulator {
  double lat2 = 0, along2 = 0, head2 = 0;
  std::size_t n = 0;
  ErrorStats stats;
  void add(const PoseError& e) {
    ++n;
    lat2 += e.lateral_m * e.lateral_m;
    along2 += e.along_m * e.along_m;
    head2 += e.heading_rad * e.heading_rad;
    stats.lateral_max_m = std::max(stats.lateral_max_m, std::abs(e.lateral_m));
    stats.along_max_m = std::max(stats.along_max_m, std::abs(e.along_m));
    stats.heading_max_deg = std::max(stats.heading_max_deg, std::abs(radToDeg(e.heading_rad)));
    stats.max_error_m = std::max(stats.max_error_m, e.distance_m);
  }
  ErrorStats finish() const {
    ErrorStats s = stats;
    if (n > 0) {
      s.lateral_rms_m = std::sqrt(lat2 / static_cast<double>(n));
      s.along_rms_m = std::sqrt(along2 / static_cast<double>(n));
      s.heading_rms_deg = radToDeg(std::sqrt(head2 / static_cast<double>(n)));
    }
    return s;
  }
};

}  // namespace

void accumulateMetrics(const std::vector<FrameRecord>& frames, const Route& route, MissionMetrics& into) {
  into.frames = frames.size();
  Accumulator estimate, odometry;
  std::size_t along_in = 0, lateral_in = 0, heading_in = 0;
  double nees_sum = 0;
  FilterConsistency& consistency = into.consistency;
  consistency = FilterConsistency{};
  // The intersections' arc lengths along the route: each turn leg sits where the drive legs before
  // it end (the route's line runs through the intersection's centre).
  std::vector<double> intersection_s;
  double s = 0;
  for (const Leg& leg : route.legs) {
    if (leg.action == LegAction::Drive) s += leg.meters;
    else intersection_s.push_back(s);
  }
  std::vector<bool> checked(intersection_s.size(), false);
  into.along_after_intersection_max_m = 0;
  into.vision_failures = 0;
  into.max_offset_from_centre_m = 0;
  into.min_path_clearance_m = std::numeric_limits<double>::infinity();
  into.left_path_frames = 0;
  into.lost_frames = 0;
  into.uncertain_frames = 0;
  into.departures = 0;
  into.ground_steps_used = 0;
  into.arrived_frame.reset();
  std::vector<double> latency, vision;
  latency.reserve(frames.size());
  vision.reserve(frames.size());
  for (const FrameRecord& f : frames) {
    latency.push_back(f.latency_ms);
    vision.push_back(f.vision_ms);
    if (!f.vision_ok) ++into.vision_failures;
    if (f.status == PositionStatus::Lost) ++into.lost_frames;
    if (f.position_uncertain) ++into.uncertain_frames;
    if (f.departed) ++into.departures;
    if (f.step_used) ++into.ground_steps_used;
    if (f.arrived && !into.arrived_frame) into.arrived_frame = f.index;
    if (!f.truth) continue;
    into.has_truth = true;
    into.max_offset_from_centre_m = std::max(into.max_offset_from_centre_m, f.offset_from_centre_m);
    into.min_path_clearance_m = std::min(into.min_path_clearance_m, f.allowed_offset_m - f.offset_from_centre_m);
    if (f.offPath()) ++into.left_path_frames;
    estimate.add(f.error);
    odometry.add(f.odometry_error);
    const FrameConsistency c = frameConsistency(f.error, f.covariance, f.road_heading_rad);
    ++consistency.frames;
    along_in += c.along;
    lateral_in += c.lateral;
    heading_in += c.heading;
    if (c.nees) {
      ++consistency.nees_frames;
      nees_sum += *c.nees;
    }
    for (std::size_t i = 0; i < intersection_s.size(); ++i) {
      if (f.route_s >= intersection_s[i] && f.route_s <= intersection_s[i] + 2.0) {
        checked[i] = true;
        into.along_after_intersection_max_m = std::max(into.along_after_intersection_max_m, std::abs(f.error.along_m));
      }
    }
  }
  if (!into.has_truth) into.min_path_clearance_m = 0;
  into.intersections_checked = static_cast<std::size_t>(std::count(checked.begin(), checked.end(), true));
  into.estimate = estimate.finish();
  if (consistency.frames > 0) {
    const double n = static_cast<double>(consistency.frames);
    consistency.within_2sigma_along = static_cast<double>(along_in) / n;
    consistency.within_2sigma_lateral = static_cast<double>(lateral_in) / n;
    consistency.within_2sigma_heading = static_cast<double>(heading_in) / n;
  }
  if (consistency.nees_frames > 0) consistency.nees_mean = nees_sum / static_cast<double>(consistency.nees_frames);
  into.odometry_only = odometry.finish();
  into.latency_ms_median = percentile(latency, 50);
  into.latency_ms_p99 = percentile(latency, 99);
  into.latency_ms_max = latency.empty() ? 0 : *std::max_element(latency.begin(), latency.end());
  into.vision_ms_median = percentile(vision, 50);
}

}  // namespace mapnav
