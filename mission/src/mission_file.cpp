#include "mapnav/mission/mission_file.h"

#include <system_error>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/core/json.h"

namespace mapnav {

const OptionTable<MissionFile>& missionFileOptionTable() {
  using O = MissionFile;
  static const OptionTable<O> table =
      OptionTable<O>("MissionFile")
          .field("speed_mps", &O::speed_mps, inRange(0.01, 40), "cruise speed, m/s (a replayed car log: its own speed)")
          .field("frame_rate_hz", &O::frame_rate_hz, inRange(0.01, 100), "camera frames per second")
          .field("wander_m", &O::wander_m, inRange(0, 5), "amplitude of a gentle lateral wander around the route, m");
  return table;
}

namespace {

// `file` resolved against `folder`; an issue at `pointer` when no file is there.
std::filesystem::path existingFile(const std::string& file, const std::filesystem::path& folder,
                                   const std::string& pointer, Issues& issues) {
  std::filesystem::path target = folder / file;
  std::error_code ec;  // a name the file system refuses (too long) is a missing file, not a throw
  if (!std::filesystem::is_regular_file(target, ec)) {
    addIssue(issues, Severity::Error, "mission.missing_file", pointer,
             "\"" + file + "\" (" + target.string() + ") does not exist" + (ec ? ": " + ec.message() : ""));
  }
  return target;
}

}  // namespace

std::optional<MissionFile> parseMission(std::string_view text, const std::filesystem::path& path, Issues& issues) {
  const std::size_t before = countSeverity(issues, Severity::Error);
  const auto json = parseJson(text, issues);
  MissionFile m;
  m.file = path;
  if (json) {
    JsonObject top(*json, "", issues);
    if (const auto format = top.string("format"); format && *format != kMissionFormat) {
      addIssue(issues, Severity::Error, "schema.format", "/format",
               "unknown format \"" + *format + "\"; expected \"" + std::string(kMissionFormat) + "\"");
    }
    m.name = top.string("name", false).value_or(path.stem().string());
    const std::filesystem::path folder = path.parent_path();
    for (const auto& [key, target] : {std::pair{"map", &m.map}, std::pair{"camera", &m.camera}}) {
      if (const auto file = top.string(key)) *target = existingFile(*file, folder, top.pointer(key), issues);
    }
    for (const auto& [key, target] : {std::pair{"start", &m.start}, std::pair{"goal", &m.goal}}) {
      if (const auto position = top.string(key)) {
        try {
          *target = parseRoadPosition(*position);
        } catch (const InvalidInput& e) {
          addIssue(issues, Severity::Error, "mission.road_position", top.pointer(key), e.what());
        }
      }
    }
    if (const Json* via = top.member("via", false)) {
      if (!via->is_array()) {
        addIssue(issues, Severity::Error, "schema.type", top.pointer("via"), "expected an array of road positions");
      } else {
        for (std::size_t i = 0; i < via->size(); ++i) {
          const std::string where = pointerJoin(top.pointer("via"), i);
          try {
            if (!(*via)[i].is_string()) throw InvalidInput("expected a road position like R1@I1+3");
            m.via.push_back(parseRoadPosition((*via)[i].get<std::string>()));
          } catch (const InvalidInput& e) {
            addIssue(issues, Severity::Error, "mission.road_position", where, e.what());
          }
        }
      }
    }
    Json numbers = Json::object();  // the mission's numbers, read by their table
    for (const OptionFieldSpec& field : missionFileOptionTable().fields())
      if (const Json* value = top.member(field.name, false)) numbers[field.name] = *value;
    m = missionFileOptionTable().read(numbers.dump(), m, "", issues);
    // Blocks read by the modules that own them; here only their shape is checked, and the world's
    // map file resolved (the renderer's options are the rest of the block).
    for (const auto& [key, target] : {std::pair{"world", &m.world_json}, std::pair{"odometry", &m.odometry_json}}) {
      if (const Json* block = top.member(key, false)) {
        if (!block->is_object()) {
          addIssue(issues, Severity::Error, "schema.type", top.pointer(key), "expected an object");
          continue;
        }
        Json rest = *block;
        if (target == &m.world_json) {
          JsonObject world(*block, top.pointer(key), issues);
          if (const auto file = world.string("map", false)) m.world_map = existingFile(*file, folder, world.pointer("map"), issues);
          rest.erase("map");
        }
        *target = rest.dump();
      }
    }
    if (const Json* vision = top.member("vision", false)) {
      JsonObject v(*vision, top.pointer("vision"), issues);
      // Required: options are one pipeline's, and a mission without `vision` gets the one its
      // route's surfaces call for (pipeline_choice.h), never an unnamed default.
      if (const auto pipeline = v.string("pipeline")) {
        m.vision_pipeline = *pipeline;
        if (pipeline->empty()) {
          addIssue(issues, Severity::Error, "schema.range", v.pointer("pipeline"),
                   "empty pipeline name: name one (`mapnav pipelines` lists them), or leave out \"vision\" for the "
                   "one the surfaces of the route's roads call for");
        }
      }
      if (const Json* options = v.member("options", false)) m.vision_options_json = options->dump();
      v.rejectUnknownMembers();
    }
    if (const Json* halt = top.member("halt", false)) {
      JsonObject h(*halt, top.pointer("halt"), issues);
      if (const Json* resume = h.member("resume_after_frames", false)) {
        if (resume->is_null()) {
          m.halt.resume_after_frames.reset();
        } else if (!resume->is_number_integer() && !resume->is_number_unsigned()) {
          addIssue(issues, Severity::Error, "schema.type", h.pointer("resume_after_frames"),
                   "expected a whole number of frames (>= 0) or null (never resume), got " +
                       std::string(jsonTypeName(*resume)));
        } else if (resume->get<long long>() < 0 || resume->get<long long>() > 1000000) {
          addIssue(issues, Severity::Error, "schema.range", h.pointer("resume_after_frames"),
                   "resume_after_frames = " + std::to_string(resume->get<long long>()) + ": must be in [0, 1000000]");
        } else {
          m.halt.resume_after_frames = static_cast<std::size_t>(resume->get<long long>());
        }
      }
      h.rejectUnknownMembers();
    }
    if (const Json* localization = top.member("localization", false)) {
      JsonObject l(*localization, top.pointer("localization"), issues);
      if (const auto use = l.boolean("use_gnss", false)) m.use_gnss = *use;
      l.rejectUnknownMembers();
    }
    top.rejectUnknownMembers();
  }
  if (!json || countSeverity(issues, Severity::Error) != before) return std::nullopt;
  return m;
}

MissionFile loadMission(const std::filesystem::path& path) {
  const std::string text = readFile(path);
  Issues issues;
  auto mission = parseMission(text, path, issues);
  if (!mission) throw ValidationError(path.string(), std::move(issues));
  return std::move(*mission);
}

}  // namespace mapnav
