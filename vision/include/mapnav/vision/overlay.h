#pragma once
// The paper's Figure 2 for one frame: predicted interest segments thin, detected lines bold
// (matched ones green and labelled, unmatched red, frame edges grey), the road region outlined.
#include "mapnav/geometry/camera.h"
#include "mapnav/sim/image.h"
#include "mapnav/vision_iface/detected_object.h"
#include "mapnav/vision_iface/predicted_object.h"

namespace mapnav {

Image drawDetection(const Image& frame, const PredictedObject& prediction, const DetectedObject& detection);
/// The same, and the detection's centre line (when it has one) projected with `camera` onto the
/// image, thick magenta.
Image drawDetection(const Image& frame, const PredictedObject& prediction, const DetectedObject& detection,
                    const Camera& camera);

/// The road region as a 1-channel mask (255 inside), the size of `like`.
Image regionMask(const DetectedObject& detection, int width, int height);

}  // namespace mapnav
