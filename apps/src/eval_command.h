#pragma once
// `mapnav eval segmentation` (docs/eval.md): a vision pipeline over a labelled photo set, scored
// as the KITTI road benchmark and CamVid do.
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "mapnav/geometry/camera.h"
#include "mapnav/vision/bev_eval.h"
#include "mapnav/vision/segmentation_eval.h"

namespace mapnav::cli {

struct EvalSegmentationConfig {
  std::string pipeline = "sidewalk";
  std::string options_json = "{}";
  std::vector<std::string> plugins;
  std::string images, labels;          ///< folders; an image's label is the PNG of the same stem
  LabelClasses classes;
  std::string bootstrap = "trapezoid";  ///< or "labels-first-frame"
  TrapezoidOptions trapezoid;
  std::string camera;                   ///< optional camera file; default: the assumed pin-hole (docs/eval.md)
  bool bev = false;                     ///< score in a bird's-eye grid (needs `camera`) instead of per pixel
  BevGrid bev_grid;                     ///< that grid; KITTI's by default
  std::string overlays;                 ///< folder for TP/FP/FN overlays, or empty
  bool json = false;
};

int runEvalSegmentation(const EvalSegmentationConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
