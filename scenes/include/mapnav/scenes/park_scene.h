#pragma once
// The park-mode speed scene, shared by `mapnav bench` and bench/park_bench.cpp (Google Benchmark):
// a size × size pin-hole scaled from the Terregator camera (f = 904 px at 512, tilted 22° down) on
// maps/park_path.json, a few consecutive synthetic frames along R1 (shadow_density 0.4), and the
// Jochem & Baluja road finder trained on the first frame from the predicted road outline.
#include <memory>
#include <vector>

#include "mapnav/geometry/camera.h"
#include "mapnav/image/image.h"
#include "mapnav/map/map.h"
#include "mapnav/sim/world.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav {

/// What is rendered once per size.
struct ParkScene {
  int size = 0;
  std::unique_ptr<Camera> camera;
  std::vector<Frame> frames;  ///< consecutive frames 2 m apart along R1, from 5 m
  Image outline;              ///< the predicted road outline of the first frame (1 channel)
};

/// Renders the scene of `park` (maps/park_path.json) at `size` × `size` pixels (size ≥ 16) with
/// `frames` frames.
ParkScene makeParkScene(const Map& park, int size, int frames = 4);

/// The road finder's options for the scene: blocks of 8 px at 512, scaled with the size.
ClusterPerceptronOptions parkFinderOptions(int size, int threads = 1, RoadModel road_model = RoadModel::Line);

/// A finder trained on the scene's first frame, with how long each training step took.
struct TrainedParkFinder {
  ClusterPerceptron finder;
  double cluster_ms = 0;     ///< §3 clustering
  double perceptron_ms = 0;  ///< §5 row widths + §4 perceptron
  double trainMs() const { return cluster_ms + perceptron_ms; }
};

/// §3–§5 training on the first frame from the predicted outline (timed with steady_clock); the
/// scene's camera given to the finder (the arc model's row geometry).
TrainedParkFinder trainParkFinder(const ParkScene& scene, const ClusterPerceptronOptions& options);

}  // namespace mapnav
