#pragma once
// What the command line and the Python module share about one frame's detection: the checks of a
// camera frame handed in from outside. The DetectedObject as `mapnav detect --json` prints it is
// tokens/token_json.h's toJson.
#include <string>

#include "mapnav/geometry/camera.h"
#include "mapnav/tokens/detected_object.h"

namespace mapnav {

/// Throws InvalidInput, the message starting with `source` (a file, "image"), unless a frame of
/// `width` x `height` pixels with `channels` channels is an RGB frame of `camera`'s size.
void checkCameraFrame(const std::string& source, int width, int height, int channels, const Camera& camera);

}  // namespace mapnav
