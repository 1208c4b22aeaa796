#pragma once
// The picture of a predicted view, like Wallace 1985's Figure 2: on the left the map around the
// vehicle with the view footprint; on the right the camera's image plane with the road regions
// filled and the interest segments bold and labelled.
#include "mapnav/core/option_table.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/map/map.h"
#include "mapnav/map/predict.h"
#include "mapnav/render/canvas.h"

namespace mapnav {

struct PredictionPictureOptions {
  int panel_px = 640;       ///< height of both panels; the image panel keeps the camera's aspect
  double map_margin_m = 8;  ///< map shown around the footprint and the vehicle

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// PredictionPictureOptions' fields by name, with their rules.
const OptionTable<PredictionPictureOptions>& predictionPictureOptionTable();

render::Canvas renderPrediction(const Map& map, const Prediction& prediction, const Camera& camera,
                                const PredictionPictureOptions& options = {});

}  // namespace mapnav
