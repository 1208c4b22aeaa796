// The trace read back as the paper's dialogue (trace.h, traceDialogue): each record's payload
// checked field by field (the JSON Pointer of what is wrong) and said by the function its record type
// has in one table, kRecordTypes, which is also the list of what each module may write.
#include "mapnav/mission/trace.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/geometry/types.h"
#include "mapnav/mission/blackboard.h"
#include "mapnav/navigator/road_position.h"

namespace mapnav {

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

// When a record was written: its frame (null before the first) and its time, s.
struct RecordTime {
  std::optional<std::size_t> frame;
  double t = 0;
};

std::string sayMission(const Fields& p, const RecordTime&) {
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

std::string sayRoute(const Fields& p, const RecordTime&) {
  std::string dialogue = p.str("dialogue");
  for (char& c : dialogue) {
    if (c == '\n') c = ' ';
  }
  while (!dialogue.empty() && dialogue.back() == ' ') dialogue.pop_back();
  return "Navigator: Route " + p.str("why") + ", " + strprintf("%.1f", p.num("length_m")) + " m: " + dialogue;
}

std::string sayLogFault(const Fields& p, const RecordTime&) {
  return "Sensors: frames.jsonl line " + strprintf("%.0f", p.num("line")) + ": " + p.str("kind") + " (" +
         p.str("message") + "); " + p.str("action") + ".";
}

std::string sayFrame(const Fields&, const RecordTime& when) {
  return "[frame " + (when.frame ? std::to_string(*when.frame) : std::string("?")) + ", " + strprintf("%.1f", when.t) + " s]";
}

std::string sayPredictedObject(const Fields& p, const RecordTime&) {
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

std::string sayDetectedObject(const Fields& p, const RecordTime&) {
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

std::string sayCurrentPosition(const Fields& p, const RecordTime&) {
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

std::string sayMotionCommand(const Fields& p, const RecordTime&) {
  if (p.str("kind") == "stop") return "Navigator: Stop. (" + p.str("reason") + ")";
  const std::string on = p.boolean("same_road") ? "it" : p.str("road");
  std::string then = "stop at the goal";
  if (p.has("next_turn")) then = sayTurn(p.obj("next_turn"));
  return "Navigator: Drive on " + on + " " + strprintf("%.1f", p.num("drive_m")) + " meters and " + then + ".";
}

std::string sayVisionFailure(const Fields&, const RecordTime&) { return ""; }  // the failed DetectedObject says it

std::string sayHalt(const Fields& p, const RecordTime&) {
  const std::string when = p.has("resume_after_frames")
                               ? "until the " + p.str("control_to") + " hands control back (after " +
                                     strprintf("%.0f", p.num("resume_after_frames")) + " frames)"
                               : "and the mission ends";
  return "Vision: I halt (" + p.str("reason") + "). Control passes to the " + p.str("control_to") + "; motion stops " +
         when + ".";
}

std::string sayResume(const Fields& p, const RecordTime&) {
  return "User: I hand control back (after " + strprintf("%.0f", p.num("frames_halted")) + " frames halted).";
}

std::string sayExecuting(const Fields& p, const RecordTime&) {
  if (!p.boolean("executes")) return "Motion Control: Ok. (replay: recorded, not driven)";
  if (p.str("kind") != "drive") return "Motion Control: Ok. I stop.";
  // The skid-steer vehicle turns on its tracks (navigator/vehicle.h): back from a turnaround.
  return p.has("turning_in_place") && p.boolean("turning_in_place") ? "Motion Control: Ok. I turn in place, then drive."
                                                                     : "Motion Control: Ok. I drive.";
}

std::string sayDropped(const Fields& p, const RecordTime&) {
  return "Blackboard: dropped the " + p.str("token") + " of " + strprintf("%.2f", p.num("token_time")) + " s (" +
         p.str("why") + ").";
}

std::string saySummary(const Fields& p, const RecordTime&) {
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

// The record types each module may write, and how each is said.
struct RecordType {
  const char* module;
  const char* type;
  std::string (*say)(const Fields& payload, const RecordTime& when);
};
constexpr RecordType kRecordTypes[] = {
    {"User", "Mission", sayMission},
    {"User", "Resume", sayResume},
    {"Navigator", "Route", sayRoute},
    {"Navigator", "MotionCommand", sayMotionCommand},
    {"Sensors", "Frame", sayFrame},
    {"Sensors", "LogFault", sayLogFault},
    {"Map", "PredictedObject", sayPredictedObject},
    {"Map", "CurrentPosition", sayCurrentPosition},
    {"Vision", "DetectedObject", sayDetectedObject},
    {"Vision", "VisionFailure", sayVisionFailure},
    {"Vision", "Halt", sayHalt},
    {"MotionControl", "Executing", sayExecuting},
    {"Blackboard", "Dropped", sayDropped},
    {"Mission", "Summary", saySummary},
};

// The record type `module` writes under `type`, or nullptr.
const RecordType* recordType(const std::string& module, const std::string& type) {
  for (const RecordType& r : kRecordTypes) {
    if (r.module == module && r.type == type) return &r;
  }
  return nullptr;
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
      const RecordType* kind = recordType(module, type);
      if (kind == nullptr) throw BadLine{"trace.type", "/type: " + module + " does not write \"" + type + "\" records"};
      const std::string sentence = kind->say(record.obj("payload"), RecordTime{frame, t});
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
