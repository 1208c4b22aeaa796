#pragma once
// What the command line and the Python module share about one frame's detection: the checks of a
// camera frame handed in from outside, and the DetectedObject as `mapnav detect --json` prints it.
#include <string>

#include "mapnav/geometry/camera.h"
#include "mapnav/tokens/detected_object.h"

namespace mapnav {

/// Throws InvalidInput, the message starting with `source` (a file, "image"), unless a frame of
/// `width` x `height` pixels with `channels` channels is an RGB frame of `camera`'s size.
void checkCameraFrame(const std::string& source, int width, int height, int channels, const Camera& camera);

/// The detection as `mapnav detect --json` prints it: status, reason, confidence, the region and
/// the lines in image and vehicle coordinates, the centre line; coordinates to 3 decimals.
std::string detectionToJson(const DetectedObject& detection);

}  // namespace mapnav
