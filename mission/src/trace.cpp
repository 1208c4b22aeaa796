// The trace written (trace.h, TraceWriter): one JSON line per token and event, its numbers rounded
// to fixed steps. The tokens' payloads are tokens/token_json.h's; reading it back as the dialogue:
// trace_dialogue.cpp.
#include "mapnav/mission/trace.h"

#include <type_traits>
#include <variant>

#include "mapnav/core/io.h"
#include "mapnav/core/json.h"
#include "mapnav/tokens/token_json.h"

namespace mapnav {

namespace {

using namespace token_json;

Json turn(const Leg& leg) {
  return Json{{"at", leg.at},
              {"onto", leg.road},
              {"direction", turnDirection(leg.angle)},
              {"degrees", roundTo(radToDeg(leg.angle), 10)}};
}

Json commandPayload(const MotionCommand& c, std::uint64_t aborts) {
  return Json{{"sequence", c.sequence},
              {"aborts", aborts},
              {"kind", toString(c.kind)},
              {"reason", c.reason},
              {"road", c.road},
              {"drive_m", roundTo(c.drive_m, 1e3)},
              {"same_road", c.same_road},
              {"next_turn", c.next_turn ? turn(*c.next_turn) : Json(nullptr)},
              {"path_ends_at_goal", c.path_ends_at_goal},
              {"path_ends_at_turn", c.path_ends_at_turn},
              {"speed_mps", metres(c.speed_mps)},
              {"setpoint", {{"speed_mps", metres(c.setpoint.speed_mps)}, {"turn_rate_deg_s", degrees(c.setpoint.turn_rate_rad_s)}}},
              {"lookahead", point(c.lookahead_point, metres)},
              {"path", points(c.path, [](double x) { return roundTo(x, 1e3); })}};
}

Json nullable(const std::optional<std::size_t>& v) { return v ? Json(*v) : Json(nullptr); }

}  // namespace

void TraceWriter::line(double t, std::string_view module, std::string_view type, const std::string& payload_json) {
  Json head{{"t", roundTo(t, 1e6)}, {"frame", frame_ ? Json(*frame_) : Json(nullptr)}, {"module", module}, {"type", type}};
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
      legs.push_back({{"action", "drive"}, {"road", leg.road}, {"meters", roundTo(leg.meters, 1e3)}});
    } else {
      Json j = turn(leg);
      j["action"] = "turn";
      legs.push_back(std::move(j));
    }
  }
  Json payload{{"why", why},
               {"from", toString(route.from)},
               {"to", toString(route.to)},
               {"length_m", roundTo(route.length_m, 1e3)},
               {"legs", std::move(legs)},
               {"intersections", route.intersections},
               {"line", points(route.line.points(), [](double x) { return roundTo(x, 1e3); })},
               {"dialogue", toDialogue(route)}};
  line(t, "Navigator", "Route", payload.dump());
}

void TraceWriter::frame(const TraceFrame& f) {
  frame_ = f.index;
  Json payload{{"image", f.image.empty() ? Json(nullptr) : Json(f.image)},
               {"odometry",
                {{"distance_m", significant(f.odometry.distance_m)}, {"dheading_deg", significant(radToDeg(f.odometry.dheading_rad))}}},
               {"truth", f.truth ? pose(*f.truth) : Json(nullptr)},
               {"odometry_only", pose(f.odometry_only)}};
  if (f.truth_on_map) payload["truth_on_map"] = pose(*f.truth_on_map);
  line(f.t, "Sensors", "Frame", payload.dump());
}

void TraceWriter::fault(double t, const LogFault& f) {
  Json payload{{"kind", toString(f.kind)},
               {"line", f.line},
               {"line_t", f.t ? Json(roundTo(*f.t, 1e6)) : Json(nullptr)},
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
          Json j{{"made_for", pose(token.made_for)}};
          j.update(toJson(token.view));
          return j;
        } else if constexpr (std::is_same_v<T, DetectedObject> || std::is_same_v<T, CurrentPosition>) {
          return toJson(token);
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
  Json payload{{"token", toString(d.type)}, {"token_time", roundTo(d.token_time, 1e6)}, {"why", d.why}};
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
  return Json{{"within_2sigma_along", roundTo(c.within_2sigma_along, 1e4)},
              {"within_2sigma_lateral", roundTo(c.within_2sigma_lateral, 1e4)},
              {"within_2sigma_heading", roundTo(c.within_2sigma_heading, 1e4)},
              {"nees_mean", c.nees_frames > 0 ? Json(roundTo(c.nees_mean, 1e2)) : Json(nullptr)}};
}

}  // namespace

void TraceWriter::summary(const MissionRun& run) {
  const MissionMetrics& m = run.metrics;
  auto stats = [&](const ErrorStats& s) -> Json {
    if (!m.has_truth) return nullptr;
    return Json{{"lateral_rms_m", metres(s.lateral_rms_m)}, {"lateral_max_m", metres(s.lateral_max_m)},
                {"along_rms_m", metres(s.along_rms_m)},     {"along_max_m", metres(s.along_max_m)},
                {"heading_rms_deg", roundTo(s.heading_rms_deg, 1e4)}, {"heading_max_deg", roundTo(s.heading_max_deg, 1e4)},
                {"max_error_m", metres(s.max_error_m)}};
  };
  Json payload{{"outcome", run.outcome},
               {"reached_goal", m.reached_goal},
               {"frames", m.frames},
               {"goal_distance_m", metres(m.goal_distance_m)},
               {"ended_by_halt", run.ended_by_halt},
               {"stopped_early", run.stopped_early},
               {"estimate", stats(m.estimate)},
               {"odometry_only", stats(m.odometry_only)},
               {"along_after_intersection_max_m", m.has_truth ? Json(metres(m.along_after_intersection_max_m)) : Json(nullptr)},
               {"intersections_checked", m.intersections_checked},
               {"max_offset_from_centre_m", m.has_truth ? Json(metres(m.max_offset_from_centre_m)) : Json(nullptr)},
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
