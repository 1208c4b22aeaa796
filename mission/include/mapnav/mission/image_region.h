#pragma once
// A prediction without a map: one road region given in image pixels (a bootstrap trapezoid, a
// labelled region, a polygon the user draws), back-projected to the ground, for training a
// pipeline where there is no map to predict from (`mapnav segment --train-region`, `mapnav eval`,
// the mapless tracking loop of mission/track.h).
#include <vector>

#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/types.h"
#include "mapnav/map/predict.h"

namespace mapnav {

/// One predicted road, id "train-region": the polygon (pixels: u right, v down) back-projected to
/// the ground in the vehicle frame (points above the horizon dropped), with the camera's view
/// footprint at PredictOptions' default near and far distances. Throws InvalidInput when fewer
/// than 3 of its points see the ground.
Prediction predictionFromImageRegion(const std::vector<Vec2>& polygon, const Camera& camera);

}  // namespace mapnav
