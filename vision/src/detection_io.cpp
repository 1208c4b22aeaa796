#include "mapnav/vision/detection_io.h"

#include "mapnav/core/error.h"

namespace mapnav {

void checkCameraFrame(const std::string& source, int width, int height, int channels, const Camera& camera) {
  if (channels != 3) throw InvalidInput(source + ": a camera frame must be an RGB image");
  if (width != camera.width() || height != camera.height()) {
    throw InvalidInput(source + ": the image is " + std::to_string(width) + "x" + std::to_string(height) +
                       " but the camera's is " + std::to_string(camera.width()) + "x" + std::to_string(camera.height()));
  }
}

}  // namespace mapnav
