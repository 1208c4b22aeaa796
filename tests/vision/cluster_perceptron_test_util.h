#pragma once
// Shared helpers of the cluster-perceptron tests (cluster_perceptron_*_test.cpp): the park's world and
// camera, poses on its straight stretches, a finder trained on a frame, and the IoU of two masks.
#include <cmath>
#include <cstddef>
#include <numbers>
#include <utility>
#include <vector>

#include "eval_common.h"
#include "mapnav/map/predict.h"
#include "mapnav/image/image.h"
#include "mapnav/sim/world.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav::visiontest {

inline const Camera& cam() { return visiontest::pinhole(); }

/// The park without its map landmarks, the world the road finder's frame-by-frame
/// figures below were measured in: they score the road against its shoulders and the seeded tree
/// shadows. What the landmarks (a lamp post's shadow across the path, a bench or a tree trunk at the
/// edge) do to them is in docs/measurements.md; the closed loops drive the park with its landmarks.
inline const Map& parkScenery() {
  static const Map map = testing::withoutLandmarks(testing::mapPath("park_path.json"));
  return map;
}

inline WorldOptions parkWorld() {
  WorldOptions wo;
  wo.shadow_density = 0.4;
  return wo;
}

/// A pose near a road's centre line, and the arc length s of the centre line's point it stands by
/// (the truth the tests measure against: the centre line from s on, in the road's direction).
struct RoadPose {
  Pose2 pose;
  const Road* road;
  double s;
};

/// Poses on straight stretches: the road's centre line is straight from 2 m behind to 25 m ahead.
inline std::vector<RoadPose> straightPoses(double step) {
  std::vector<RoadPose> out;
  int k = 0;
  const double lateral[] = {0.0, 0.2, -0.25, 0.1};
  const double dheading[] = {0.0, 2.0, -2.5, 1.0};
  for (const Road& road : park().roads()) {
    const Polyline2& line = road.centerline;
    for (double s = 3.0; s + 25.0 < line.length(); s += step) {
      const Vec2 t0 = line.tangentAt(s - 2.0);
      bool straight = true;
      for (double d = 0; d <= 25.0 && straight; d += 1.0) {
        const Vec2 t = line.tangentAt(s + d);
        straight = std::abs(std::atan2(t0.x() * t.y() - t0.y() * t.x(), t0.dot(t))) < 0.002;
      }
      if (!straight) continue;
      const Vec2 left(-t0.y(), t0.x());
      const double heading = std::atan2(t0.y(), t0.x()) + dheading[k % 4] * std::numbers::pi / 180.0;
      out.push_back({Pose2(line.pointAt(s) + lateral[k % 4] * left, heading), &road, s});
      ++k;
    }
  }
  return out;
}

/// The finder trained on the frame of `world` (rendered from `map`) at `pose`, bootstrapped from the
/// map's predicted road outline.
inline ClusterPerceptron trainedOn(const World& world, const Pose2& pose, double t, ClusterPerceptronOptions o = {},
                            const Map& map = park()) {
  const Frame f = world.render(cam(), pose, t);
  const Prediction pred = predictView(map, pose, cam());
  const Image outline = predictedRoadMask(pred.view, cam());
  ClusterPerceptron cp(o);
  cp.trainClusters(f.rgb.data.data(), f.rgb.width, f.rgb.height);
  cp.setRowWidths(trapezoidRowWidths(outline));
  cp.setCamera(cam());
  cp.trainPerceptron(f.rgb.data.data(), f.rgb.width, f.rgb.height, outline.data.data());
  return cp;
}

/// The intersection over union of two 1-channel masks (non-zero = in).
inline double maskIoU(const Image& found, const Image& truth) {
  double tp = 0, fp = 0, fn = 0;
  for (std::size_t k = 0; k < found.data.size(); ++k) {
    const bool d = found.data[k] != 0, t = truth.data[k] != 0;
    tp += d && t;
    fp += d && !t;
    fn += !d && t;
  }
  return tp / (tp + fp + fn);
}

}  // namespace mapnav::visiontest
