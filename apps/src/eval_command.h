#pragma once
// `mapnav eval segmentation` (docs/eval.md): the command line over the library's evaluation
// (mapnav/eval/segmentation_evaluation.h), which it prints as text or JSON.
#include <iosfwd>
#include <string>
#include <vector>

#include "mapnav/eval/segmentation_evaluation.h"

namespace mapnav::cli {

struct EvalSegmentationConfig {
  std::string pipeline = "sidewalk";
  std::string options_json = "{}";
  std::vector<std::string> plugins;
  std::string images, labels;           ///< folders; an image's label is the PNG of the same stem
  LabelClasses classes;
  /// --bootstrap's text, for options.bootstrap (default: the library's)
  std::string bootstrap = std::string(toString(SegmentationEvalOptions{}.bootstrap));
  SegmentationEvalOptions options;      ///< the camera, the bird's-eye grid, the overlays' folder
  bool json = false;
};

int runEvalSegmentation(const EvalSegmentationConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
