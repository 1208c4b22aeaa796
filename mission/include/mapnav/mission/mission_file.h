#pragma once
// Mission files (`mapnav-mission/1`, docs/mission-format.md): what to simulate or run — the map,
// the camera, where to start and where to go, how fast, how often a frame, what the world looks
// like, which vision pipeline, how noisy the odometry.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mapnav/core/issue.h"
#include "mapnav/core/option_table.h"
#include "mapnav/navigator/road_position.h"

namespace mapnav {

inline constexpr std::string_view kMissionFormat = "mapnav-mission/1";

/// What happens after Vision fails and halts motion (Wallace 1985, 4: "the Vision system halts and
/// signals the blackboard so that another module (or person) [can] take control"). In simulation
/// and replay the operator hands control back after a number of frames, or never.
struct HaltPolicy {
  /// Frames after the last failing frame until the operator hands control back and the Navigator
  /// plans again (0: on the next frame). Nothing: never — the mission ends at the first halt.
  std::optional<std::size_t> resume_after_frames = 2;
};

struct MissionFile {
  std::filesystem::path file;    ///< where it was read from (parseMission's path): what errors in its blocks name
  std::string name;
  std::filesystem::path map;     ///< resolved against the mission file's folder
  std::filesystem::path camera;  ///< likewise
  RoadPosition start, goal;
  std::vector<RoadPosition> via;  ///< visited in order between start and goal (a tour)
  double speed_mps = 0.6;        ///< cruise speed (the Terregator ran at 0.3–1 m/s)
  double frame_rate_hz = 2.0;    ///< camera frames per second
  double wander_m = 0.0;         ///< amplitude of a gentle lateral wander around the route, m
  std::string world_json = "{}";     ///< the `world` block but its `map`, for the renderer's options
  /// The world's `map`, resolved against the mission file's folder: the simulator draws the world
  /// from this map while the vehicle navigates by `map` (a map that is wrong somewhere: its roads
  /// carry the same ids, sim/plant.h); empty (the default): the world is drawn from `map`.
  std::filesystem::path world_map;
  /// `vision.pipeline`; "" when the mission has no `vision` (then the route's surfaces choose:
  /// mission/pipeline_choice.h).
  std::string vision_pipeline;
  std::string vision_options_json = "{}";
  std::string odometry_json = "{}";  ///< the `odometry` block, for the odometry noise model
  HaltPolicy halt;                   ///< the `halt` block
  /// `localization.use_gnss`: the Map module fuses the frames' GNSS fixes (MapModuleOptions::use_gnss;
  /// a run's options may turn it on too, never off).
  bool use_gnss = false;
};

/// The mission's numbers (speed_mps, frame_rate_hz, wander_m) with their rules; the other members of
/// a mission file are files, road positions and blocks that other tables read.
const OptionTable<MissionFile>& missionFileOptionTable();

/// A mission document's text; the structure and values are checked (issues with JSON Pointers), the
/// files it names must exist. `path` is where the text came from: the map and camera resolve against
/// its folder, and its stem is the default name. Appends every problem to `issues`; nothing when
/// there is an error. Never throws for bad text.
std::optional<MissionFile> parseMission(std::string_view text, const std::filesystem::path& path, Issues& issues);

/// parseMission on a file. Throws ValidationError or IoError.
MissionFile loadMission(const std::filesystem::path& path);

}  // namespace mapnav
