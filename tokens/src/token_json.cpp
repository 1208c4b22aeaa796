// The tokens as JSON (token_json.h): the one writer of each token's fields.
#include "mapnav/tokens/token_json.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace mapnav {

namespace token_json {

double metres(double x) { return roundTo(x, 1e4); }
double pixels(double x) { return roundTo(x, 1e2); }
double degrees(double radians) { return roundTo(radToDeg(radians), 1e4); }
double significant(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return std::strtod(text, nullptr) + 0.0;
}

Json pose(const Pose2& p) { return Json{{"x", metres(p.x())}, {"y", metres(p.y())}, {"heading_deg", degrees(p.heading())}}; }
Json point(const Vec2& p, double (*round)(double)) { return Json::array({round(p.x()), round(p.y())}); }
Json segment(const Segment2& s, double (*round)(double)) { return Json::array({point(s.a, round), point(s.b, round)}); }
Json points(const std::vector<Vec2>& ps, double (*round)(double)) {
  Json out = Json::array();
  for (const Vec2& p : ps) out.push_back(point(p, round));
  return out;
}
Json upperTriangle(const Mat3& c) {
  return Json::array({significant(c(0, 0)), significant(c(0, 1)), significant(c(0, 2)), significant(c(1, 1)),
                      significant(c(1, 2)), significant(c(2, 2))});
}

}  // namespace token_json

using namespace token_json;

namespace {

Json regionsJson(const std::vector<PredictedRegion>& regions) {
  Json out = Json::array();
  for (const PredictedRegion& r : regions) out.push_back({{"id", r.id}, {"kind", r.kind}, {"surface", r.surface}, {"segments", r.segments}});
  return out;
}

Json segmentsJson(const std::vector<InterestSegment>& segments) {
  Json out = Json::array();
  for (const InterestSegment& s : segments) {
    out.push_back({{"id", s.id},
                   {"owner", s.owner},
                   {"side", s.side},
                   {"left_surface", s.left_surface},
                   {"right_surface", s.right_surface},
                   {"vehicle", segment(s.vehicle, metres)},
                   {"image", segment(s.image, pixels)}});
  }
  return out;
}

Json relationsJson(const std::vector<SegmentRelation>& relations) {
  Json out = Json::array();
  for (const SegmentRelation& r : relations) {
    Json j{{"type", r.type == SegmentRelation::Type::Parallel ? "parallel" : "crossing"}, {"a", r.a}, {"b", r.b}};
    if (r.type == SegmentRelation::Type::Parallel) {
      j["separation_m"] = metres(r.separation_m);
    } else {
      j["angle_deg"] = degrees(r.angle_rad);
      j["point"] = point(r.point, metres);
    }
    out.push_back(std::move(j));
  }
  return out;
}

Json stepJson(const MeasuredStep& s) {
  if (!s.found) return Json{{"found", false}, {"reason", s.reason}};
  return Json{{"found", true}, {"distance_m", metres(s.distance_m)}, {"sigma_m", metres(s.sigma_m)}, {"left_m", metres(s.left_m)},
              {"peak", roundTo(s.peak, 1e4)}};
}

}  // namespace

Json toJson(const PredictedObject& view) {
  Json landmarks = Json::array();
  for (const PredictedLandmark& l : view.landmarks) {
    landmarks.push_back({{"id", l.id},
                         {"kind", l.kind},
                         {"vehicle", point(l.vehicle, metres)},
                         {"image_base", point(l.image_base, pixels)},
                         {"width_px", pixels(l.width_px)}});
  }
  Json out{{"pose_covariance", upperTriangle(view.pose_covariance)}};
  if (view.map_sigma_m > 0) out["map_sigma_m"] = significant(view.map_sigma_m);
  out["footprint"] = points(view.footprint, metres);
  out["regions"] = regionsJson(view.regions);
  out["segments"] = segmentsJson(view.segments);
  out["relations"] = relationsJson(view.relations);
  out["landmarks"] = std::move(landmarks);
  return out;
}

Json toJson(const DetectedObject& d) {
  Json lines = Json::array();
  for (const DetectedLine& l : d.lines) {
    lines.push_back({{"label", l.label ? Json(*l.label) : Json(nullptr)},
                     {"score", roundTo(l.score, 1e4)},
                     {"frame_edge", l.frame_edge},
                     {"image", segment(l.image, pixels)},
                     {"vehicle", segment(l.vehicle, metres)}});
  }
  Json landmarks = Json::array();
  for (const DetectedLandmark& l : d.landmarks) {
    Json j{{"id", l.id}, {"found", l.found}};
    if (l.found) {
      j["image_base"] = point(l.image_base, pixels);
      j["sigma_px"] = Json::array({significant(std::sqrt(l.covariance(0, 0))), significant(std::sqrt(l.covariance(1, 1)))});
      j["score"] = roundTo(l.score, 1e4);
    } else {
      j["reason"] = l.reason;
    }
    landmarks.push_back(std::move(j));
  }
  return Json{{"status", d.status == DetectedObject::Status::Ok ? "ok" : "failed"},
              {"reason", d.reason},
              {"confidence", roundTo(d.confidence, 1e4)},
              {"lines", std::move(lines)},
              {"region_image", points(d.region_image, pixels)},
              {"centerline", d.centerline_vehicle ? segment(*d.centerline_vehicle, metres) : Json(nullptr)},
              {"landmarks", std::move(landmarks)},
              {"step", d.step ? stepJson(*d.step) : Json(nullptr)}};
}

Json toJson(const CurrentPosition& p) {
  const Mat3& c = p.covariance;
  // Standard deviations across and along the vehicle's heading.
  const Mat3 local = rotatePoseCovariance(c, p.pose.rotation().transpose());
  Json out{{"pose", pose(p.pose)},
              {"covariance", upperTriangle(c)},
              {"sigma",
               {{"lateral_m", significant(std::sqrt(std::max(0.0, local(1, 1))))},
                {"along_m", significant(std::sqrt(std::max(0.0, local(0, 0))))},
                {"heading_deg", significant(radToDeg(std::sqrt(std::max(0.0, c(2, 2)))))}}},
              {"observed", {{"lateral", p.observed_lateral}, {"along", p.observed_along}, {"heading", p.observed_heading}}},
              {"status", toString(p.status)},
              {"reason", p.reason},
              {"lines_used", p.lines_used},
              {"landmarks_used", p.landmarks_used},
              {"landmarks_rejected", p.landmarks_rejected},
              {"step_used", p.step_used},
              {"along_cue", toString(p.along_cue)},
              {"outliers", p.outliers},
              {"mahalanobis_d2", significant(p.mahalanobis_d2)},
              {"rejected_fit", p.rejected_fit ? pose(*p.rejected_fit) : Json()},
              {"rejected_fit_rms_m", p.rejected_fit ? Json(significant(p.rejected_fit_rms_m)) : Json()},
              {"region_agreement", p.region_agreement ? Json(significant(*p.region_agreement)) : Json()}};
  if (!p.integrity.empty()) out["integrity"] = p.integrity;
  if (!p.map_covariance.isZero()) {  // the map's own error, only for a map that states one
    out["map_sigma"] = {{"position_m", significant(std::sqrt(p.map_covariance(0, 0)))},
                        {"heading_deg", significant(radToDeg(std::sqrt(p.map_covariance(2, 2))))}};
  }
  return out;
}

}  // namespace mapnav
