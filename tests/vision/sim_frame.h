#pragma once
// A frame the simulator rendered, as the vision steps see it.
#include "mapnav/geometry/camera.h"
#include "mapnav/sim/world.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav::testing {

/// `frame`'s pixels (which stay in it: keep it alive) and `camera`, as a VisionFrame.
inline VisionFrame visionFrame(const Frame& frame, const Camera& camera) {
  VisionFrame f;
  f.width = frame.rgb.width;
  f.height = frame.rgb.height;
  f.rgb = frame.rgb.data.data();
  f.camera = &camera;
  return f;
}

}  // namespace mapnav::testing
