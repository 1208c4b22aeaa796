#pragma once
// The paper's Figure 2 for one frame: predicted interest segments thin, detected lines bold
// (matched ones green and labelled, unmatched red, frame edges grey), the road region outlined.
#include <string>
#include <vector>

#include "mapnav/geometry/camera.h"
#include "mapnav/image/image.h"
#include "mapnav/tokens/detected_object.h"
#include "mapnav/tokens/predicted_object.h"

namespace mapnav {

Image drawDetection(const Image& frame, const PredictedObject& prediction, const DetectedObject& detection);
/// The same, and the detection's centre line (when it has one) projected with `camera` onto the
/// image, thick magenta.
Image drawDetection(const Image& frame, const PredictedObject& prediction, const DetectedObject& detection,
                    const Camera& camera);

/// Draws a path on the ground (vehicle frame, metres: x forward, y left) onto `overlay` (RGB, the
/// camera's image) as a polyline through its points' projections, cyan (0, 255, 255), 2 px, with a
/// dot at each point in the image: `mapnav log track`'s true future path. Points the camera cannot
/// image (behind it) are left out; lines leaving the image are clipped. Throws InvalidInput unless
/// `overlay` is 3-channel.
void drawGroundPath(Image& overlay, const std::vector<Vec2>& path_vehicle, const Camera& camera);

/// One picture of several (a run's overlays for a report): each tile scaled by `scale` (> 0), its
/// caption written at its bottom left, laid out left to right in rows of `columns`, 4 px apart on black.
/// Tiles may differ in size (each cell is the largest tile's); grey tiles become RGB. Throws
/// InvalidInput for no tiles, captions not one per tile, columns < 1 or scale ≤ 0.
Image contactSheet(const std::vector<Image>& tiles, const std::vector<std::string>& captions, int columns,
                   double scale);

/// The road region as a 1-channel mask (255 inside) of width x height pixels: the detection's
/// road_mask when it has one of that size (holes and all), else its region_image filled.
Image regionMask(const DetectedObject& detection, int width, int height);
/// A polygon in pixels (u right, v down) as a 1-channel mask (255 inside), rasterised with
/// 1/16-pixel vertices, pixel centres inside.
Image regionMask(const Polygon2& region_image, int width, int height);
/// Where the camera sees the ground: 1 channel, the camera's image size, 255 at each pixel whose
/// centre's ray meets the ground (Camera::backproject), else 0; for a level camera, the rows below
/// the principal point. What the region pipelines classify, and `mapnav eval`'s baseline
/// "everything below the horizon is road".
Image groundMask(const Camera& camera);

}  // namespace mapnav
