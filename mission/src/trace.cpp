#include "mapnav/mission/trace.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/core/json.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/localization/pose_filter.h"
#include "rounding.h"

namespace mapnav {

// ---------------------------------------------------------------------------------------------
// Writing

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

// ---------------------------------------------------------------------------------------------
// Reading: the dialogue

namespace {

struct BadLine {
  std::string check, message;
};

// Typed access to one record with the JSON Pointer of whatever is wrong.
class Fields {
 public:
  Fields(const Json& j, std::string pointer) : j_(j), pointer_(std::move(pointer)) {
    if (!j_.is_object()) fail(pointer_, "expected an object, got " + std::string(jsonTypeName(j_)));
  }
  const Json& get(const char* key) const {
    const auto it = j_.find(key);
    if (it == j_.end()) fail(at(key), "missing");
    return *it;
  }
  bool has(const char* key) const { return j_.contains(key) && !j_.at(key).is_null(); }
  double num(const char* key) const {
    const Json& v = get(key);
    if (!v.is_number()) fail(at(key), "expected a number, got " + std::string(jsonTypeName(v)));
    return v.get<double>();
  }
  std::string str(const char* key) const {
    const Json& v = get(key);
    if (!v.is_string()) fail(at(key), "expected a string, got " + std::string(jsonTypeName(v)));
    return v.get<std::string>();
  }
  bool boolean(const char* key) const {
    const Json& v = get(key);
    if (!v.is_boolean()) fail(at(key), "expected true or false, got " + std::string(jsonTypeName(v)));
    return v.get<bool>();
  }
  Fields obj(const char* key) const { return Fields(get(key), at(key)); }
  const Json& arr(const char* key) const {
    const Json& v = get(key);
    if (!v.is_array()) fail(at(key), "expected an array, got " + std::string(jsonTypeName(v)));
    return v;
  }
  std::string at(const char* key) const { return pointerJoin(pointer_, key); }
  const std::string& pointer() const { return pointer_; }
  [[noreturn]] static void fail(const std::string& where, const std::string& message) {
    throw BadLine{"trace.field", where + ": " + message};
  }

 private:
  const Json& j_;
  std::string pointer_;
};

std::string sayPosition(const std::string& text) {
  try {
    const RoadPosition p = parseRoadPosition(text);
    return "road " + p.road + ", " + strprintf("%g", p.meters) + " meters from " + p.node;
  } catch (const InvalidInput&) {
    return text;
  }
}

std::string sayTurn(const Fields& turn) {
  const std::string direction = turn.str("direction");
  if (direction == "straight") return "go straight through " + turn.str("at");
  // The skid-steer vehicle turns on its tracks (navigator/vehicle.h): no three-point turn.
  if (direction == "around") return "turn around in place at " + sayPosition(turn.str("at"));
  return "turn to " + direction + " " + strprintf("%.0f", std::abs(turn.num("degrees"))) + " degrees";
}

std::string joinList(const std::vector<std::string>& items) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    out += (i == 0 ? "" : i + 1 == items.size() ? " and " : ", ") + items[i];
  }
  return out;
}

// The surfaces beyond the edges of the road being driven: of the road-edge segments in view that
// run within 30 degrees of the heading, the nearest one left of the vehicle and the nearest one right
// of it (vehicle frame), and the surface on their outer side.
void shoulders(const Json& segments, const std::string& pointer, std::string& left, std::string& right) {
  double best_left = 1e300, best_right = 1e300;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const Fields s(segments[i], pointerJoin(pointer, i));
    if (s.str("side") == "corner") continue;
    const Json& v = s.arr("vehicle");
    if (v.size() != 2 || !v[0].is_array() || !v[1].is_array() || v[0].size() != 2 || v[1].size() != 2 ||
        !v[0][0].is_number() || !v[0][1].is_number() || !v[1][0].is_number() || !v[1][1].is_number()) {
      Fields::fail(s.at("vehicle"), "expected [[x, y], [x, y]]");
    }
    const Vec2 a(v[0][0].get<double>(), v[0][1].get<double>()), b(v[1][0].get<double>(), v[1][1].get<double>());
    const Vec2 d = b - a;
    if (d.norm() < 1e-9 || std::abs(d.x()) < std::cos(degToRad(30)) * d.norm()) continue;
    const double y = (a.y() + b.y()) / 2;
    const Vec2 normal = leftNormal(d);  // the segment's left side, walking a → b
    if (y > 0 && y < best_left) {
      best_left = y;
      left = normal.y() > 0 ? s.str("left_surface") : s.str("right_surface");
    }
    if (y <= 0 && -y < best_right) {
      best_right = -y;
      right = normal.y() < 0 ? s.str("left_surface") : s.str("right_surface");
    }
  }
}

std::string say(const std::string& module, const std::string& type, const Fields& p, std::optional<std::size_t> frame,
                double t) {
  if (type == "Mission") {
    std::string via;
    for (std::size_t i = 0; i < p.arr("via").size(); ++i) {
      const Json& v = p.arr("via")[i];
      if (!v.is_string()) Fields::fail(pointerJoin(p.at("via"), i), "expected a road position");
      via += (i == 0 ? ", via " : "; then ") + sayPosition(v.get<std::string>());
    }
    const std::string log = p.has("log") ? " of " + p.str("log") : "";
    return "User: Robot is at " + sayPosition(p.str("start")) + ".\n      Navigate to " + sayPosition(p.str("goal")) + via +
           ".\n      (" + p.str("mode") + log + ", vision pipeline \"" + p.str("pipeline") + "\")";
  }
  if (type == "Route") {
    std::string dialogue = p.str("dialogue");
    for (char& c : dialogue) {
      if (c == '\n') c = ' ';
    }
    while (!dialogue.empty() && dialogue.back() == ' ') dialogue.pop_back();
    return "Navigator: Route " + p.str("why") + ", " + strprintf("%.1f", p.num("length_m")) + " m: " + dialogue;
  }
  if (type == "LogFault") {
    return "Sensors: frames.jsonl line " + strprintf("%.0f", p.num("line")) + ": " + p.str("kind") + " (" +
           p.str("message") + "); " + p.str("action") + ".";
  }
  if (type == "Frame") {
    return "[frame " + (frame ? std::to_string(*frame) : std::string("?")) + ", " + strprintf("%.1f", t) + " s]";
  }
  if (type == "PredictedObject") {
    const Json& regions = p.arr("regions");
    if (regions.empty()) return "Map: Vision will see no road from here.";
    // "straight road (R2, R4) and cross intersection (I2)": kinds in order of appearance.
    std::vector<std::pair<std::string, std::string>> groups;
    for (std::size_t i = 0; i < regions.size(); ++i) {
      const Fields r(regions[i], pointerJoin(p.at("regions"), i));
      const std::string kind = r.str("kind"), id = r.str("id");
      auto it = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == kind; });
      if (it == groups.end()) {
        groups.emplace_back(kind, id);
      } else {
        it->second += ", " + id;
      }
    }
    std::vector<std::string> kinds;
    for (const auto& [kind, ids] : groups) kinds.push_back(kind + " (" + ids + ")");
    std::string left, right;
    shoulders(p.arr("segments"), p.at("segments"), left, right);
    std::string colours;
    if (!left.empty() && !right.empty()) {
      colours = left == right ? " The color on the left and on the right is " + left + "."
                              : " The color on the left is " + left + ", on the right " + right + ".";
    }
    return "Map: Vision will see " + joinList(kinds) + "." + colours +
           (regions.size() == 1 ? " Detect it." : " Detect them.");
  }
  if (type == "DetectedObject") {
    if (p.str("status") != "ok") return "Vision: I cannot find it: " + p.str("reason") + ".";
    std::vector<std::string> labels;
    const Json& lines = p.arr("lines");
    if (lines.empty()) {
      return "Vision: Ok. I found no lines" + (p.str("reason").empty() ? "" : " (" + p.str("reason") + ")") + ".";
    }
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const Fields l(lines[i], pointerJoin(p.at("lines"), i));
      if (l.has("label")) labels.push_back(l.str("label"));
    }
    std::string text = "Vision: Ok. I found them. " + std::to_string(lines.size()) + " lines";
    if (!labels.empty()) text += ", matched to " + joinList(labels);
    if (p.has("centerline")) text += "; the centre line";
    return text + ".";
  }
  if (type == "CurrentPosition") {
    const Fields pose = p.obj("pose");
    const Fields sigma = p.obj("sigma");
    std::string text = "Map: You are at (" + strprintf("%.2f", pose.num("x")) + ", " + strprintf("%.2f", pose.num("y")) +
                       ") heading " + strprintf("%.1f", pose.num("heading_deg")) + " degrees, ±" +
                       strprintf("%.3f", sigma.num("lateral_m")) + " m across, ±" + strprintf("%.3f", sigma.num("along_m")) +
                       " m along";
    const std::string status = p.str("status");
    const std::string reason = p.str("reason");
    if (status == "lost") {
      text += "; I am lost (" + reason + ").";
    } else if (reason.rfind("re-localised", 0) == 0) {
      text += "; " + reason + ".";
    } else if (status == "corrected") {
      const Fields observed = p.obj("observed");
      std::vector<std::string> what;
      if (observed.boolean("lateral")) what.push_back("across");
      if (observed.boolean("along")) what.push_back("along");
      if (observed.boolean("heading")) what.push_back("heading");
      const long long landmarks = p.has("landmarks_used") ? static_cast<long long>(p.num("landmarks_used")) : 0;
      text += "; " + std::to_string(static_cast<long long>(p.num("lines_used"))) + " lines" +
              (landmarks > 0 ? " and " + std::to_string(landmarks) + " landmark" + (landmarks == 1 ? "" : "s") : "") +
              " matched, " + (what.empty() ? std::string("nothing") : joinList(what)) + " corrected";
      text += p.has("along_cue") && p.str("along_cue") == "landmark" ? " (along by a landmark)." : ".";
    } else {
      text += "; by odometry alone (" + reason + ").";
    }
    return text;
  }
  if (type == "MotionCommand") {
    if (p.str("kind") == "stop") return "Navigator: Stop. (" + p.str("reason") + ")";
    const std::string on = p.boolean("same_road") ? "it" : p.str("road");
    std::string then = "stop at the goal";
    if (p.has("next_turn")) then = sayTurn(p.obj("next_turn"));
    return "Navigator: Drive on " + on + " " + strprintf("%.1f", p.num("drive_m")) + " meters and " + then + ".";
  }
  if (type == "VisionFailure") return "";  // the failed DetectedObject says it
  if (type == "Halt") {
    const std::string when = p.has("resume_after_frames")
                                 ? "until the " + p.str("control_to") + " hands control back (after " +
                                       strprintf("%.0f", p.num("resume_after_frames")) + " frames)"
                                 : "and the mission ends";
    return "Vision: I halt (" + p.str("reason") + "). Control passes to the " + p.str("control_to") + "; motion stops " +
           when + ".";
  }
  if (type == "Resume") {
    return "User: I hand control back (after " + strprintf("%.0f", p.num("frames_halted")) + " frames halted).";
  }
  if (type == "Executing") {
    if (!p.boolean("executes")) return "Motion Control: Ok. (replay: recorded, not driven)";
    if (p.str("kind") != "drive") return "Motion Control: Ok. I stop.";
    // The skid-steer vehicle turns on its tracks (navigator/vehicle.h): back from a turnaround.
    return p.has("turning_in_place") && p.boolean("turning_in_place") ? "Motion Control: Ok. I turn in place, then drive."
                                                                       : "Motion Control: Ok. I drive.";
  }
  if (type == "Dropped") {
    return "Blackboard: dropped the " + p.str("token") + " of " + strprintf("%.2f", p.num("token_time")) + " s (" +
           p.str("why") + ").";
  }
  if (type == "Summary") {
    std::string text = "Mission: " + p.str("outcome") + ". " + strprintf("%.0f", p.num("frames")) + " frames";
    if (p.has("estimate")) {
      const Fields e = p.obj("estimate");
      text += "; lateral RMS " + strprintf("%.3f", e.num("lateral_rms_m")) + " m, heading RMS " +
              strprintf("%.2f", e.num("heading_rms_deg")) + " degrees";
    }
    text += "; " + strprintf("%.0f", p.num("vision_failures")) + " vision failures, " + strprintf("%.0f", p.num("replans")) +
            " replans";
    if (p.has("log_faults") && p.num("log_faults") > 0) {
      text += "; " + strprintf("%.0f", p.num("log_faults")) + " faults of the log skipped or repaired";
    }
    text += ".";
    return text;
  }
  (void)module;
  throw BadLine{"trace.type", "/type: unknown record type \"" + type + "\""};
}

// The record types each module may write.
bool knownType(const std::string& module, const std::string& type) {
  static const std::vector<std::pair<std::string, std::string>> known = {
      {"User", "Mission"},          {"User", "Resume"},        {"Navigator", "Route"},     {"Navigator", "MotionCommand"},
      {"Sensors", "Frame"},         {"Sensors", "LogFault"},   {"Map", "PredictedObject"}, {"Map", "CurrentPosition"}, {"Vision", "DetectedObject"},
      {"Vision", "VisionFailure"},  {"Vision", "Halt"},        {"MotionControl", "Executing"},
      {"Blackboard", "Dropped"},    {"Mission", "Summary"}};
  for (const auto& [m, t] : known) {
    if (m == module && t == type) return true;
  }
  return false;
}

}  // namespace

std::string traceDialogue(std::string_view text, const std::string& file) {
  Issues issues;
  std::string out;
  std::size_t records = 0;
  int number = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view raw = text.substr(start, end - start);
    start = end + 1;
    ++number;
    if (!raw.empty() && raw.back() == '\r') raw.remove_suffix(1);
    if (raw.find_first_not_of(" \t") == std::string_view::npos) continue;
    auto bad = [&](const std::string& check, const std::string& message) {
      Issue issue;
      issue.severity = Severity::Error;
      issue.check = check;
      issue.message = message;
      issue.line = number;
      issue.column = 1;
      issues.push_back(std::move(issue));
    };
    Json j;
    try {
      j = Json::parse(raw);
    } catch (const Json::exception& e) {
      bad("trace.not_json", std::string("not JSON: ") + e.what());
      continue;
    }
    try {
      const Fields record(j, "");
      const double t = record.num("t");
      std::optional<std::size_t> frame;
      if (record.has("frame")) {
        const Json& f = record.get("frame");
        if (!f.is_number_unsigned() && !(f.is_number_integer() && f.get<long long>() >= 0)) {
          Fields::fail("/frame", "expected a frame number or null");
        }
        frame = f.get<std::size_t>();
      } else {
        (void)record.get("frame");  // present, null
      }
      const std::string module = record.str("module"), type = record.str("type");
      if (!moduleFromString(module)) throw BadLine{"trace.type", "/module: unknown module \"" + module + "\""};
      if (!knownType(module, type)) {
        throw BadLine{"trace.type", "/type: " + module + " does not write \"" + type + "\" records"};
      }
      const std::string sentence = say(module, type, record.obj("payload"), frame, t);
      ++records;
      if (!sentence.empty()) out += sentence + "\n";
    } catch (const BadLine& e) {
      bad(e.check, e.message);
    } catch (const Json::exception& e) {
      bad("trace.field", e.what());
    }
  }
  if (issues.empty() && records == 0) {
    Issue issue;
    issue.check = "trace.empty";
    issue.message = "no records: not a mapnav trace";
    issue.line = 1;
    issue.column = 1;
    issues.push_back(issue);
  }
  if (!issues.empty()) throw ValidationError(file, std::move(issues));
  return out;
}

}  // namespace mapnav
