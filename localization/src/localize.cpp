// The Map module's step: predict, build the correspondences, update (localize.h).
#include "mapnav/localization/localize.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "mapnav/geometry/camera.h"
#include "mapnav/localization/correspondences.h"
#include "mapnav/localization/observability.h"
#include "mapnav/map/map.h"
#include "mapnav/map/predict.h"
#include "mapnav/tokens/detected_object.h"

namespace mapnav {

const OptionTable<LocalizeOptions>& localizeOptionTable() {
  using O = LocalizeOptions;
  static const OptionTable<O> table =
      OptionTable<O>("LocalizeOptions")
          .field("edge_sigma_m", &O::edge_sigma_m, above(0),
                 "1-sigma of a detected edge's end points across their line, m")
          .field("centerline_sigma_m", &O::centerline_sigma_m, above(0),
                 "the same for a detected centre line (park mode), m")
          .field("min_line_length_m", &O::min_line_length_m, atLeast(0), "shorter detected lines are ignored, m")
          .field("centerline_search_m", &O::centerline_search_m, above(0),
                 "park mode: roads at most this far from the centre line, m")
          .field("curve_piece_m", &O::curve_piece_m, atLeast(0),
                 "labelled edges are matched piecewise against the map's edges, pieces at most this long, m (0: the "
                 "predicted chord)")
          .field("edge_sigma_px", &O::edge_sigma_px, atLeast(0),
                 "an edge's sigma also covers this many pixels across the line in the image, px (0: edge_sigma_m "
                 "alone)")
          .field("landmark_sigma_px", &O::landmark_sigma_px, atLeast(0),
                 "a landmark's base pixel covariance is widened by this many pixels each way, px")
          .field("use_ground_step", &O::use_ground_step,
                 "fuse the ground's step (false: the odometry's scale from lines and landmarks alone)")
          .field("step_sigma_m", &O::step_sigma_m, atLeast(0),
                 "the ground step's 1-sigma is widened by this, in quadrature, m");
  return table;
}

void LocalizeOptions::validate() const { localizeOptionTable().validate(*this); }

std::optional<LandmarkObservation> landmarkObservation(const Camera& camera, const std::string& id, const Vec2& image_base,
                                                       const Mat2& pixel_covariance, const Vec2& map_world) {
  const Vec2 origin = camera.center().head<2>();
  const auto ground = camera.backproject(image_base);
  if (!ground) return std::nullopt;
  auto rangeBearing = [&](const Vec2& g) {
    const Vec2 d = g - origin;
    return Vec2(d.norm(), std::atan2(d.y(), d.x()));
  };
  const Vec2 z = rangeBearing(*ground);
  // d(range, bearing) / d(u, v) by central differences of half a pixel.
  Mat2 j;
  for (int k = 0; k < 2; ++k) {
    const Vec2 du = 0.5 * Vec2::Unit(k);
    const auto plus = camera.backproject(image_base + du), minus = camera.backproject(image_base - du);
    if (!plus || !minus) return std::nullopt;
    j.col(k) = rangeBearing(*plus) - rangeBearing(*minus);
    j(1, k) = normalizeAngle(j(1, k));
  }
  LandmarkObservation o;
  o.id = id;
  o.map_world = map_world;
  o.origin_vehicle = origin;
  o.range_m = z.x();
  o.bearing_rad = z.y();
  o.covariance = j * pixel_covariance * j.transpose();
  o.covariance = 0.5 * (o.covariance + o.covariance.transpose()).eval();
  return o;
}

namespace {

// The landmarks Vision found, as observations of the prediction's landmarks (matched by id).
std::vector<LandmarkObservation> landmarkObservations(const Prediction& prediction, const DetectedObject& detected,
                                                      const Camera& camera, double sigma_px) {
  std::vector<LandmarkObservation> out;
  for (const DetectedLandmark& d : detected.landmarks) {
    if (!d.found) continue;
    for (std::size_t i = 0; i < prediction.view.landmarks.size(); ++i) {
      if (prediction.view.landmarks[i].id != d.id || i >= prediction.landmarks.size()) continue;
      const Mat2 covariance = d.covariance + Mat2::Identity() * sigma_px * sigma_px;
      if (auto o = landmarkObservation(camera, d.id, d.image_base, covariance, prediction.landmarks[i]->position)) {
        out.push_back(std::move(*o));
      }
    }
  }
  return out;
}

// Fuses the landmarks into `out` (the lines' result): counts, information, status, the cue.
void addLandmarks(PoseFilter& filter, const std::vector<LandmarkObservation>& observations, CurrentPosition& out) {
  const bool lines_along = out.status == PositionStatus::Corrected && out.observed_along;
  out.along_cue = lines_along ? AlongCue::Intersection : AlongCue::None;
  if (observations.empty()) return;
  const LandmarkUpdateResult r = filter.updateLandmarks(observations);
  out.landmarks_used = static_cast<int>(r.used.size());
  out.landmarks_rejected = r.rejected;
  if (r.used.empty()) {
    out.reason += "; landmark(s) rejected by the gate: " + std::to_string(r.rejected.size());
    return;
  }
  const bool corrected = out.status == PositionStatus::Corrected;
  out.pose = filter.pose();
  out.covariance = filter.covariance();
  out.information = (corrected ? out.information : Mat3::Zero()) + r.information;
  const Observability seen = observability(out.information, out.pose.heading(), filter.options().match.min_information);
  out.observed_lateral = seen.lateral;
  out.observed_along = seen.along;
  out.observed_heading = seen.heading;
  if (!lines_along && seen.along) out.along_cue = AlongCue::Landmark;
  const std::string what = std::to_string(r.used.size()) + " landmark(s)";
  out.reason = corrected ? out.reason + "; " + what : "corrected from " + what + " (" + out.reason + ")";
  out.status = PositionStatus::Corrected;
}

}  // namespace

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
  // The ground's step first: it measures the step predict() just took (PoseFilter::updateStep).
  const bool stepped = options.use_ground_step && detected.step && detected.step->found &&
                       filter.updateStep(detected.step->distance_m,
                                         std::pow(detected.step->sigma_m, 2) + std::pow(options.step_sigma_m, 2));
  const double t = detected.timestamp;
  if (detected.status != DetectedObject::Status::Ok) {
    CurrentPosition out = filter.current(t, "vision failed (" + detected.reason + "): odometry only");
    out.step_used = stepped;
    return out;
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
  CurrentPosition out;
  if (lines.empty()) {
    const bool any_label = std::any_of(detected.lines.begin(), detected.lines.end(),
                                       [](const DetectedLine& l) { return l.label && !l.frame_edge; });
    out = filter.current(t, any_label ? "no usable lines (no label matches a predicted segment): odometry only"
                                      : "no usable lines (none labelled, no centre line): odometry only");
  } else {
    out = filter.update(lines, t);
    if (park) out.reason = "park mode, " + out.reason;
  }
  if (camera != nullptr) {
    addLandmarks(filter, landmarkObservations(prediction, detected, *camera, options.landmark_sigma_px), out);
  }
  out.step_used = stepped;
  return out;
}

}  // namespace mapnav
