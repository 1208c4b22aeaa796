#pragma once
// The sidewalk speed scene, shared by `mapnav bench` and bench/sidewalk_bench.cpp (Google Benchmark):
// the Terregator pin-hole (512 x 480) on maps/cmu_campus.json, consecutive frames 0.6 m apart down R1
// (the campus_dialogue world: light shadows and leaves, sensor noise), each with the Map's
// prediction from the true pose — what the Vision module gets in the mission loop.
#include <memory>
#include <vector>

#include "mapnav/geometry/camera.h"
#include "mapnav/map/map.h"
#include "mapnav/sim/world.h"
#include "mapnav/tokens/predicted_object.h"

namespace mapnav::cli {

struct SidewalkScene {
  Map map;
  std::unique_ptr<Camera> camera;
  std::vector<Pose2> poses;
  std::vector<Frame> frames;
  std::vector<PredictedObject> predictions;
};

/// Renders `frames` frames (≥ 1) of the scene; the map and camera come from the same folder as
/// defaultParkMapPath().
SidewalkScene makeSidewalkScene(int frames = 8);

}  // namespace mapnav::cli
