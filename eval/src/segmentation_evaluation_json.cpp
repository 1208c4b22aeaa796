// evaluationJson(): the one writer of an evaluation's JSON (`mapnav eval segmentation --json`,
// Python's evaluate_segmentation).
#include <optional>

#include "json_figure.h"
#include "mapnav/core/json.h"
#include "mapnav/eval/segmentation_evaluation.h"

namespace mapnav {

namespace {

// Which space was scored, so that image and bird's-eye figures are never mistaken for each other.
Json gridJson(const std::optional<ScoredBevGrid>& bev) {
  if (!bev) return nullptr;
  const BevGrid& g = bev->grid;
  return {{"x_m", {g.x_min_m, g.x_max_m}}, {"z_m", {g.z_min_m, g.z_max_m}}, {"cell_m", g.cell_m},
          {"columns", bev->columns},       {"rows", bev->rows},             {"cells_in_image", bev->cells_in_image}};
}

}  // namespace

std::string evaluationJson(const SegmentationEvaluation& e) {
  Json per_image = Json::array();
  for (const PhotoScore& p : e.photos)
    per_image.push_back({{"image", p.image},
                         {"iou", figure(p.counts.iou())},
                         {"failed", p.failure.empty() ? Json(nullptr) : Json(p.failure)}});
  const SegmentationScores& s = e.scores;
  const Json j = {{"pipeline", e.pipeline},
                  {"bootstrap", std::string(toString(e.bootstrap))},
                  {"space", e.bev ? "bev" : "image"},
                  {"bev", gridJson(e.bev)},
                  {"images", s.images},
                  {"failed", e.failed},
                  {"iou", figure(s.iou)},
                  {"iou_median", figure(s.iou_median)},
                  {"iou_worst", figure(s.iou_worst)},
                  {"precision", figure(s.precision)},
                  {"recall", figure(s.recall)},
                  {"maxf", figure(s.maxf)},
                  {"ap", figure(s.ap)},
                  {"baseline_horizon_iou", figure(e.baseline_horizon.iou)},
                  {"baseline_bootstrap_iou", figure(e.baseline_bootstrap.iou)},
                  {"margin", figure(e.margin)},
                  {"per_image", per_image}};
  return dumpJson(j);
}

}  // namespace mapnav
