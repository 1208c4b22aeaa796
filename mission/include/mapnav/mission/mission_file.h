#pragma once
// Mission files (`mapnav-mission/1`, docs/mission-format.md): what to simulate or run — the map,
// the camera, where to start and where to go, how fast, how often a frame, what the world looks
// like, which vision pipeline, how noisy the odometry.
#include <filesystem>
#include <string>
#include <vector>

#include "mapnav/core/issue.h"
#include "mapnav/navigator/road_position.h"

namespace mapnav {

inline constexpr std::string_view kMissionFormat = "mapnav-mission/1";

struct MissionFile {
  std::string name;
  std::filesystem::path map;     ///< resolved against the mission file's folder
  std::filesystem::path camera;  ///< likewise
  RoadPosition start, goal;
  std::vector<RoadPosition> via;  ///< visited in order between start and goal (a tour)
  double speed_mps = 0.6;        ///< cruise speed (the Terregator ran at 0.3–1 m/s)
  double frame_rate_hz = 2.0;    ///< camera frames per second
  double wander_m = 0.0;         ///< amplitude of a gentle lateral wander around the route, m
  std::string world_json = "{}";     ///< the `world` block, for the renderer's options
  std::string vision_pipeline;       ///< `vision.pipeline` (used by the vision issues)
  std::string vision_options_json = "{}";
  std::string odometry_json = "{}";  ///< the `odometry` block, for the odometry noise model
};

/// Reads a mission; the structure and values are checked (issues with JSON Pointers), the files it
/// names must exist. Throws ValidationError or IoError.
MissionFile loadMission(const std::filesystem::path& path);

}  // namespace mapnav
