// A prediction made of one region given in image pixels (mapnav/mission/image_region.h).
#include "mapnav/mission/image_region.h"

#include "mapnav/core/error.h"

namespace mapnav {

Prediction predictionFromImageRegion(const std::vector<Vec2>& polygon, const Camera& camera) {
  Prediction p;
  PredictedRegion region;
  region.id = "train-region";
  region.kind = "given region";
  Polygon2 ground;
  for (const Vec2& pixel : polygon) {
    if (const auto g = camera.backproject(pixel)) ground.push_back(*g);
  }
  if (ground.size() < 3) {
    throw InvalidInput("the training region: fewer than 3 of its points see the ground (they are above the horizon)");
  }
  region.vehicle = {ground};
  p.view.regions = {region};
  const PredictOptions defaults;
  p.view.footprint = viewFootprint(camera, defaults.near_m, defaults.far_m);
  return p;
}

}  // namespace mapnav
