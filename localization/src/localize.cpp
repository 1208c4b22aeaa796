// The Map module's step: predict, build the correspondences, update (localize.h).
#include "mapnav/localization/localize.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "mapnav/core/options.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/localization/correspondences.h"
#include "mapnav/map/map.h"
#include "mapnav/map/predict.h"
#include "mapnav/tokens/detected_object.h"

namespace mapnav {

void LocalizeOptions::validate() const {
  auto require = [](bool ok, const char* field, double value, const char* rule) {
    requireOption(ok, "LocalizeOptions", field, value, rule);
  };
  require(std::isfinite(edge_sigma_m) && edge_sigma_m > 0, "edge_sigma_m", edge_sigma_m, "finite and > 0");
  require(std::isfinite(centerline_sigma_m) && centerline_sigma_m > 0, "centerline_sigma_m", centerline_sigma_m,
          "finite and > 0");
  require(std::isfinite(min_line_length_m) && min_line_length_m >= 0, "min_line_length_m", min_line_length_m,
          "finite and >= 0");
  require(std::isfinite(centerline_search_m) && centerline_search_m > 0, "centerline_search_m", centerline_search_m,
          "finite and > 0");
  require(std::isfinite(curve_piece_m) && curve_piece_m >= 0, "curve_piece_m", curve_piece_m, "finite and >= 0");
  require(std::isfinite(edge_sigma_px) && edge_sigma_px >= 0, "edge_sigma_px", edge_sigma_px, "finite and >= 0");
}

std::optional<double> groundMetresPerPixel(const Camera& camera, const Segment2& line) {
  const Vec2 mid = line.pointAt(0.5);
  const Vec2 half = 0.05 * line.direction();  // 10 cm of the line about its midpoint, for its image direction
  const auto p = camera.projectGround(mid), a = camera.projectGround(mid - half), b = camera.projectGround(mid + half);
  if (!p || !a || !b || (*b - *a).norm() < 1e-9) return std::nullopt;
  const auto q = camera.backproject(*p + leftNormal((*b - *a).normalized()));  // one pixel across the image line
  if (!q) return std::nullopt;
  return std::abs((*q - mid).dot(leftNormal(line.direction())));
}

CurrentPosition localize(PoseFilter& filter, const MotionIncrement& motion, const Prediction& prediction,
                         const DetectedObject& detected, const LocalizeOptions& options, const Map* map,
                         const Camera* camera, double dt_s) {
  options.validate();
  filter.predict(motion, dt_s);
  const double t = detected.timestamp;
  if (detected.status != DetectedObject::Status::Ok) {
    return filter.current(t, "vision failed (" + detected.reason + "): odometry only");
  }
  std::vector<LineCorrespondence> lines =
      map != nullptr && options.curve_piece_m > 0
          ? edgeCorrespondences(*map, prediction, detected, filter.pose(), options.edge_sigma_m,
                                options.min_line_length_m, options.curve_piece_m)
          : labelledCorrespondences(prediction, detected, options.edge_sigma_m, options.min_line_length_m);
  if (camera != nullptr && options.edge_sigma_px > 0) {
    for (LineCorrespondence& c : lines) {
      if (const auto mpp = groundMetresPerPixel(*camera, c.detected_vehicle)) {
        c.sigma_m = std::hypot(c.sigma_m, options.edge_sigma_px * *mpp);
      }
    }
  }
  bool park = false;
  if (lines.empty() && map != nullptr && detected.centerline_vehicle &&
      detected.centerline_vehicle->length() >= options.min_line_length_m) {
    if (auto c = centerlineCorrespondence(*map, filter.pose(), *detected.centerline_vehicle,
                                          options.centerline_sigma_m, options.centerline_search_m)) {
      lines.push_back(*c);
      park = true;
    }
  }
  if (lines.empty()) {
    const bool any_label = std::any_of(detected.lines.begin(), detected.lines.end(),
                                       [](const DetectedLine& l) { return l.label && !l.frame_edge; });
    return filter.current(t, any_label ? "no usable lines (no label matches a predicted segment): odometry only"
                                       : "no usable lines (none labelled, no centre line): odometry only");
  }
  CurrentPosition out = filter.update(lines, t);
  if (park) out.reason = "park mode, " + out.reason;
  return out;
}

}  // namespace mapnav
