// The trace written (trace.h, TraceWriter): one JSON line per token and event, its numbers rounded
// to fixed steps. Reading it back as the dialogue: trace_dialogue.cpp.
#include "mapnav/mission/trace.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "mapnav/core/io.h"
#include "mapnav/core/json.h"
#include "mapnav/localization/pose_filter.h"
#include "rounding.h"

namespace mapnav {

namespace {

// Fixed rounding keeps the trace short and its bytes independent of the last bits of a computation
// that is itself deterministic (rounding.h).
double fixed(double x, double scale) { return detail::roundTo(x, scale); }
double m4(double x) { return fixed(x, 1e4); }   // metres: 0.1 mm
double px(double x) { return fixed(x, 1e2); }   // pixels: 0.01 px
double deg(double rad) { return fixed(radToDeg(rad), 1e4); }
double sig(double x) {  // six significant digits
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return std::strtod(text, nullptr) + 0.0;
}

// A symmetric 3 x 3 matrix as its upper triangle [00, 01, 02, 11, 12, 22], six significant digits.
Json upperTriangle(const Mat3& c) {
  return Json::array({sig(c(0, 0)), sig(c(0, 1)), sig(c(0, 2)), sig(c(1, 1)), sig(c(1, 2)), sig(c(2, 2))});
}

Json pose(const Pose2& p) { return Json{{"x", m4(p.x())}, {"y", m4(p.y())}, {"heading_deg", deg(p.heading())}}; }
Json point(const Vec2& p, double (*round)(double)) { return Json::array({round(p.x()), round(p.y())}); }
Json segment(const Segment2& s, double (*round)(double)) { return Json::array({point(s.a, round), point(s.b, round)}); }
Json points(const std::vector<Vec2>& ps, double (*round)(double)) {
  Json out = Json::array();
  for (const Vec2& p : ps) out.push_back(point(p, round));
  return out;
}

Json turn(const Leg& leg) {
  return Json{{"at", leg.at},
              {"onto", leg.road},
              {"direction", turnDirection(leg.angle)},
              {"degrees", fixed(radToDeg(leg.angle), 10)}};
}

Json predictionPayload(const PredictionToken& p) {
  Json regions = Json::array();
  for (const PredictedRegion& r : p.view.regions) {
    regions.push_back({{"id", r.id}, {"kind", r.kind}, {"surface", r.surface}, {"segments", r.segments}});
  }
  Json segments = Json::array();
  for (const InterestSegment& s : p.view.segments) {
    segments.push_back({{"id", s.id},
                        {"owner", s.owner},
                        {"side", s.side},
                        {"left_surface", s.left_surface},
                        {"right_surface", s.right_surface},
                        {"vehicle", segment(s.vehicle, m4)},
                        {"image", segment(s.image, px)}});
  }
  Json relations = Json::array();
  for (const SegmentRelation& r : p.view.relations) {
    Json j{{"type", r.type == SegmentRelation::Type::Parallel ? "parallel" : "crossing"}, {"a", r.a}, {"b", r.b}};
    if (r.type == SegmentRelation::Type::Parallel) {
      j["separation_m"] = m4(r.separation_m);
    } else {
      j["angle_deg"] = deg(r.angle_rad);
      j["point"] = point(r.point, m4);
    }
    relations.push_back(std::move(j));
  }
  Json landmarks = Json::array();
  for (const PredictedLandmark& l : p.view.landmarks) {
    landmarks.push_back({{"id", l.id},
                         {"kind", l.kind},
                         {"vehicle", point(l.vehicle, m4)},
                         {"image_base", point(l.image_base, px)},
                         {"width_px", px(l.width_px)}});
  }
  return Json{{"made_for", pose(p.made_for)},
              {"pose_covariance", upperTriangle(p.view.pose_covariance)},
              {"footprint", points(p.view.footprint, m4)},
              {"regions", std::move(regions)},
              {"segments", std::move(segments)},
              {"relations", std::move(relations)},
              {"landmarks", std::move(landmarks)}};
}

Json stepPayload(const MeasuredStep& s) {
  if (!s.found) return Json{{"found", false}, {"reason", s.reason}};
  return Json{{"found", true}, {"distance_m", m4(s.distance_m)}, {"sigma_m", m4(s.sigma_m)}, {"left_m", m4(s.left_m)},
              {"peak", fixed(s.peak, 1e4)}};
}

Json detectionPayload(const DetectedObject& d) {
  Json lines = Json::array();
  for (const DetectedLine& l : d.lines) {
    lines.push_back({{"label", l.label ? Json(*l.label) : Json(nullptr)},
                     {"score", fixed(l.score, 1e4)},
                     {"frame_edge", l.frame_edge},
                     {"image", segment(l.image, px)},
                     {"vehicle", segment(l.vehicle, m4)}});
  }
  Json landmarks = Json::array();
  for (const DetectedLandmark& l : d.landmarks) {
    Json j{{"id", l.id}, {"found", l.found}};
    if (l.found) {
      j["image_base"] = point(l.image_base, px);
      j["sigma_px"] = Json::array({sig(std::sqrt(l.covariance(0, 0))), sig(std::sqrt(l.covariance(1, 1)))});
      j["score"] = fixed(l.score, 1e4);
    } else {
      j["reason"] = l.reason;
    }
    landmarks.push_back(std::move(j));
  }
  return Json{{"status", d.status == DetectedObject::Status::Ok ? "ok" : "failed"},
              {"reason", d.reason},
              {"confidence", fixed(d.confidence, 1e4)},
              {"lines", std::move(lines)},
              {"region_image", points(d.region_image, px)},
              {"centerline", d.centerline_vehicle ? segment(*d.centerline_vehicle, m4) : Json(nullptr)},
              {"landmarks", std::move(landmarks)},
              {"step", d.step ? stepPayload(*d.step) : Json(nullptr)}};
}

Json positionPayload(const CurrentPosition& p) {
  const Mat3& c = p.covariance;
  // Standard deviations across and along the vehicle's heading.
  const Mat3 local = rotatePoseCovariance(c, p.pose.rotation().transpose());
  return Json{{"pose", pose(p.pose)},
              {"covariance", upperTriangle(c)},
              {"sigma",
               {{"lateral_m", sig(std::sqrt(std::max(0.0, local(1, 1))))},
                {"along_m", sig(std::sqrt(std::max(0.0, local(0, 0))))},
                {"heading_deg", sig(radToDeg(std::sqrt(std::max(0.0, c(2, 2)))))}}},
              {"observed", {{"lateral", p.observed_lateral}, {"along", p.observed_along}, {"heading", p.observed_heading}}},
              {"status", toString(p.status)},
              {"reason", p.reason},
              {"lines_used", p.lines_used},
              {"landmarks_used", p.landmarks_used},
              {"landmarks_rejected", p.landmarks_rejected},
              {"step_used", p.step_used},
              {"along_cue", toString(p.along_cue)},
              {"outliers", p.outliers},
              {"mahalanobis_d2", sig(p.mahalanobis_d2)},
              {"rejected_fit", p.rejected_fit ? pose(*p.rejected_fit) : Json()},
              {"rejected_fit_rms_m", p.rejected_fit ? Json(sig(p.rejected_fit_rms_m)) : Json()},
              {"region_agreement", p.region_agreement ? Json(sig(*p.region_agreement)) : Json()}};
}

Json commandPayload(const MotionCommand& c, std::uint64_t aborts) {
  return Json{{"sequence", c.sequence},
              {"aborts", aborts},
              {"kind", toString(c.kind)},
              {"reason", c.reason},
              {"road", c.road},
              {"drive_m", fixed(c.drive_m, 1e3)},
              {"same_road", c.same_road},
              {"next_turn", c.next_turn ? turn(*c.next_turn) : Json(nullptr)},
              {"path_ends_at_goal", c.path_ends_at_goal},
              {"path_ends_at_turn", c.path_ends_at_turn},
              {"speed_mps", m4(c.speed_mps)},
              {"setpoint", {{"speed_mps", m4(c.setpoint.speed_mps)}, {"turn_rate_deg_s", deg(c.setpoint.turn_rate_rad_s)}}},
              {"lookahead", point(c.lookahead_point, m4)},
              {"path", points(c.path, [](double x) { return fixed(x, 1e3); })}};
}

Json nullable(const std::optional<std::size_t>& v) { return v ? Json(*v) : Json(nullptr); }

}  // namespace

void TraceWriter::line(double t, std::string_view module, std::string_view type, const std::string& payload_json) {
  Json head{{"t", fixed(t, 1e6)}, {"frame", frame_ ? Json(*frame_) : Json(nullptr)}, {"module", module}, {"type", type}};
  std::string text = head.dump();
  text.pop_back();  // the closing brace: the payload follows
  text += ",\"payload\":";
  text += payload_json;
  text += "}\n";
  text_ += text;
}

void TraceWriter::header(const TraceHeader& h) {
  Json via = Json::array();
  for (const RoadPosition& p : h.via) via.push_back(toString(p));
  Issues ignored;
  Json payload{{"format", kTraceFormat},
               {"mode", h.mode},
               {"mission", h.mission},
               {"map", h.map},
               {"camera", parseJson(h.camera_json, ignored).value_or(Json(nullptr))},
               {"log", h.log.empty() ? Json(nullptr) : Json(h.log)},
               {"pipeline", h.pipeline},
               {"start", toString(h.start)},
               {"via", std::move(via)},
               {"goal", toString(h.goal)},
               {"start_pose", pose(h.start_pose)},
               {"goal_pose", pose(h.goal_pose)},
               {"speed_mps", h.speed_mps},
               {"frame_rate_hz", h.frame_rate_hz},
               {"halt", {{"resume_after_frames", nullable(h.resume_after_frames)}}},
               {"image", {{"width", h.image_width}, {"height", h.image_height}}}};
  frame_.reset();
  line(0, "User", "Mission", payload.dump());
}

void TraceWriter::route(double t, const Route& route, std::string_view why) {
  Json legs = Json::array();
  for (const Leg& leg : route.legs) {
    if (leg.action == LegAction::Drive) {
      legs.push_back({{"action", "drive"}, {"road", leg.road}, {"meters", fixed(leg.meters, 1e3)}});
    } else {
      Json j = turn(leg);
      j["action"] = "turn";
      legs.push_back(std::move(j));
    }
  }
  Json payload{{"why", why},
               {"from", toString(route.from)},
               {"to", toString(route.to)},
               {"length_m", fixed(route.length_m, 1e3)},
               {"legs", std::move(legs)},
               {"intersections", route.intersections},
               {"line", points(route.line.points(), [](double x) { return fixed(x, 1e3); })},
               {"dialogue", toDialogue(route)}};
  line(t, "Navigator", "Route", payload.dump());
}

void TraceWriter::frame(const TraceFrame& f) {
  frame_ = f.index;
  Json payload{{"image", f.image.empty() ? Json(nullptr) : Json(f.image)},
               {"odometry",
                {{"distance_m", sig(f.odometry.distance_m)}, {"dheading_deg", sig(radToDeg(f.odometry.dheading_rad))}}},
               {"truth", f.truth ? pose(*f.truth) : Json(nullptr)},
               {"odometry_only", pose(f.odometry_only)}};
  line(f.t, "Sensors", "Frame", payload.dump());
}

void TraceWriter::fault(double t, const LogFault& f) {
  Json payload{{"kind", toString(f.kind)},
               {"line", f.line},
               {"line_t", f.t ? Json(fixed(*f.t, 1e6)) : Json(nullptr)},
               {"image", f.image.empty() ? Json(nullptr) : Json(f.image)},
               {"action", f.action},
               {"message", f.message}};
  line(t, "Sensors", "LogFault", payload.dump());
}

void TraceWriter::posting(const Posting& p) {
  const double t = tokenTime(p.token);
  const std::string_view module = toString(p.from), type = toString(tokenType(p.token));
  Json payload = std::visit(
      [&](const auto& token) -> Json {
        using T = std::decay_t<decltype(token)>;
        if constexpr (std::is_same_v<T, PredictionToken>) {
          return predictionPayload(token);
        } else if constexpr (std::is_same_v<T, DetectedObject>) {
          return detectionPayload(token);
        } else if constexpr (std::is_same_v<T, CurrentPosition>) {
          return positionPayload(token);
        } else if constexpr (std::is_same_v<T, MotionCommand>) {
          return commandPayload(token, p.aborts);
        } else if constexpr (std::is_same_v<T, VisionFailure>) {
          return Json{{"reason", token.reason}};
        } else if constexpr (std::is_same_v<T, Halt>) {
          return Json{{"reason", token.reason},
                      {"control_to", token.control_to},
                      {"resume_after_frames", nullable(token.resume_after_frames)}};
        } else {
          return Json{{"frames_halted", token.frames_halted}};
        }
      },
      p.token);
  line(t, module, type, payload.dump());
}

void TraceWriter::drop(const Drop& d) {
  Json payload{{"token", toString(d.type)}, {"token_time", fixed(d.token_time, 1e6)}, {"why", d.why}};
  line(d.time, "Blackboard", "Dropped", payload.dump());
}

void TraceWriter::executing(double t, const MotionCommand* c, bool execute, bool turning_in_place) {
  Json payload{{"sequence", c != nullptr ? Json(c->sequence) : Json(nullptr)},
               {"executes", execute},
               {"kind", c != nullptr ? Json(toString(c->kind)) : Json("stop")},
               {"turning_in_place", turning_in_place}};
  line(t, "MotionControl", "Executing", payload.dump());
}

namespace {

// The filter's consistency over the run (null without truth; nees_mean null without a defined NEES).
Json consistencyPayload(const MissionMetrics& m) {
  const FilterConsistency& c = m.consistency;
  if (!m.has_truth || c.frames == 0) return nullptr;
  return Json{{"within_2sigma_along", fixed(c.within_2sigma_along, 1e4)},
              {"within_2sigma_lateral", fixed(c.within_2sigma_lateral, 1e4)},
              {"within_2sigma_heading", fixed(c.within_2sigma_heading, 1e4)},
              {"nees_mean", c.nees_frames > 0 ? Json(fixed(c.nees_mean, 1e2)) : Json(nullptr)}};
}

}  // namespace

void TraceWriter::summary(const MissionRun& run) {
  const MissionMetrics& m = run.metrics;
  auto stats = [&](const ErrorStats& s) -> Json {
    if (!m.has_truth) return nullptr;
    return Json{{"lateral_rms_m", m4(s.lateral_rms_m)}, {"lateral_max_m", m4(s.lateral_max_m)},
                {"along_rms_m", m4(s.along_rms_m)},     {"along_max_m", m4(s.along_max_m)},
                {"heading_rms_deg", fixed(s.heading_rms_deg, 1e4)}, {"heading_max_deg", fixed(s.heading_max_deg, 1e4)},
                {"max_error_m", m4(s.max_error_m)}};
  };
  Json payload{{"outcome", run.outcome},
               {"reached_goal", m.reached_goal},
               {"frames", m.frames},
               {"goal_distance_m", m4(m.goal_distance_m)},
               {"ended_by_halt", run.ended_by_halt},
               {"stopped_early", run.stopped_early},
               {"estimate", stats(m.estimate)},
               {"odometry_only", stats(m.odometry_only)},
               {"along_after_intersection_max_m", m.has_truth ? Json(m4(m.along_after_intersection_max_m)) : Json(nullptr)},
               {"intersections_checked", m.intersections_checked},
               {"max_offset_from_centre_m", m.has_truth ? Json(m4(m.max_offset_from_centre_m)) : Json(nullptr)},
               {"consistency", consistencyPayload(m)},
               {"left_path_frames", m.left_path_frames},
               {"vision_failures", m.vision_failures},
               {"halts", m.halts},
               {"replans", m.replans},
               {"log_faults", m.log_faults.total()}};
  line(run.frames.empty() ? 0 : run.frames.back().t, "Mission", "Summary", payload.dump());
}

void TraceWriter::save(const std::filesystem::path& path) const { writeFileAtomic(path, text_); }

}  // namespace mapnav
