// The park-mode speed scene (mapnav/scenes/park_scene.h): rendering and the timed training.
#include "mapnav/scenes/park_scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "mapnav/geometry/types.h"
#include "mapnav/map/predict.h"

namespace mapnav {

namespace {
double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The vehicle's pose `d` metres along R1 (from the origin toward (39.392, 6.946)).
Pose2 alongR1(double d) {
  const double heading = std::atan2(6.946, 39.392);
  return Pose2(Vec2(d * std::cos(heading), d * std::sin(heading)), heading);
}

}  // namespace

ParkScene makeParkScene(const Map& park, int size, int frames) {
  ParkScene s;
  s.size = size;
  CameraIntrinsics in;
  in.width = in.height = size;
  in.fx = in.fy = 904.0 * size / 512.0;
  in.cx = in.cy = (size - 1) / 2.0;
  CameraMount mount;
  mount.tilt_rad = degToRad(22.0);
  s.camera = createCamera(LensModel::Pinhole, in, mount);
  WorldOptions options;
  options.shadow_density = 0.4;
  const World world(park, options);
  const RayTable rays(*s.camera);
  for (int k = 0; k < frames; ++k) s.frames.push_back(world.render(rays, alongR1(5.0 + 2.0 * k), k));
  const Prediction pred = predictView(park, alongR1(5.0), *s.camera);
  s.outline = predictedRoadMask(pred.view, *s.camera);
  return s;
}

ClusterPerceptronOptions parkFinderOptions(int size, int threads, RoadModel road_model) {
  ClusterPerceptronOptions o;
  o.block_size = std::max(2, 8 * size / 512);
  o.threads = threads;
  o.road_model = road_model;
  return o;
}

TrainedParkFinder trainParkFinder(const ParkScene& scene, const ClusterPerceptronOptions& options) {
  TrainedParkFinder t{ClusterPerceptron(options)};
  const Image& f0 = scene.frames.front().rgb;
  t.finder.setCamera(*scene.camera);
  auto start = std::chrono::steady_clock::now();
  t.finder.trainClusters(f0.data.data(), scene.size, scene.size);
  t.cluster_ms = msSince(start);
  start = std::chrono::steady_clock::now();
  t.finder.setRowWidths(trapezoidRowWidths(scene.outline));
  t.finder.trainPerceptron(f0.data.data(), scene.size, scene.size, scene.outline.data.data());
  t.perceptron_ms = msSince(start);
  return t;
}

}  // namespace mapnav
