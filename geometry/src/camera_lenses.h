#pragma once
// The lens models behind createCamera (internal to geometry/src; camera_lenses.cpp): each maps
// camera-frame points to pixels and back. The intrinsics and mount are validated already.
#include <memory>

#include "mapnav/geometry/camera.h"

namespace mapnav::detail {

/// Pin-hole with OpenCV's radial-tangential distortion (0, 4 or 5 coefficients).
std::unique_ptr<Camera> makePinholeCamera(const CameraIntrinsics& intrinsics, const CameraMount& mount);
/// The paper's fish-eye (Wallace 1985, 3.5.1): unit sphere, then perpendicular projection.
std::unique_ptr<Camera> makePaperFisheyeCamera(const CameraIntrinsics& intrinsics, const CameraMount& mount);
/// OpenCV's equidistant fish-eye (cv::fisheye, 0 or 4 coefficients).
std::unique_ptr<Camera> makeEquidistantFisheyeCamera(const CameraIntrinsics& intrinsics, const CameraMount& mount);

}  // namespace mapnav::detail
