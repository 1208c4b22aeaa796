#pragma once
// The sidewalk speed scene, shared by `mapnav bench` and bench/sidewalk_bench.cpp (Google Benchmark):
// the Terregator pin-hole (512 x 480) on maps/cmu_campus.json, consecutive frames 0.6 m apart down R1
// (the campus_dialogue world: light shadows and leaves, sensor noise), each with the Map's
// prediction from the true pose — what the Vision module gets in the mission loop.
#include <filesystem>
#include <memory>
#include <vector>

#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/map/map.h"
#include "mapnav/sim/world.h"
#include "mapnav/tokens/predicted_object.h"

namespace mapnav {

struct SidewalkScene {
  Map map;
  std::unique_ptr<Camera> camera;
  std::vector<Pose2> poses;
  std::vector<Frame> frames;
  std::vector<PredictedObject> predictions;
};

/// Renders `frames` frames (≥ 1) of the scene; `maps` is the folder of cmu_campus.json and
/// cameras/terregator_pinhole.json (the source tree's or the installed maps/).
SidewalkScene makeSidewalkScene(const std::filesystem::path& maps, int frames = 8);

}  // namespace mapnav
