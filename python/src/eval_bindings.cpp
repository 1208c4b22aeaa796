// A vision pipeline evaluated on labelled photos: `mapnav eval segmentation` from Python, its
// figures as the dict of `--json`.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "convert.h"
#include "mapnav/core/error.h"
#include "mapnav/eval/segmentation_evaluation.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav::python {

namespace {

SegmentationEvalOptions evalOptions(const std::string& bootstrap, const std::optional<std::string>& camera, bool bev,
                                    const std::optional<std::vector<double>>& bev_range,
                                    const std::optional<double>& bev_cell, const std::optional<std::string>& overlays,
                                    const std::optional<std::pair<int, int>>& resize) {
  SegmentationEvalOptions o;
  if (resize) {  // the evaluation's option table checks them
    o.resize_width = resize->first;
    o.resize_height = resize->second;
  }
  o.bootstrap = evalBootstrapFromString(bootstrap);
  o.camera = camera.value_or("");
  o.bev = bev;
  if ((bev_range || bev_cell) && !bev) throw InvalidInput("bev_range, bev_cell: only with bev=True");
  if (bev_range) {
    if (bev_range->size() != 4)
      throw InvalidInput("bev_range: expected 4 numbers (x0, x1, z0, z1, metres), not " +
                         std::to_string(bev_range->size()));
    o.bev_grid.x_min_m = (*bev_range)[0], o.bev_grid.x_max_m = (*bev_range)[1];
    o.bev_grid.z_min_m = (*bev_range)[2], o.bev_grid.z_max_m = (*bev_range)[3];
  }
  if (bev_cell) o.bev_grid.cell_m = *bev_cell;
  o.overlays = overlays.value_or("");
  return o;
}

// The scores as the JSON text `mapnav eval segmentation --json` prints.
std::string evaluateText(const py::object& pipeline, const std::string& images, const std::string& labels,
                         const std::vector<int>& road_values, const std::vector<int>& ignore_values,
                         const std::string& bootstrap, const std::optional<std::string>& camera, bool bev,
                         const std::optional<std::vector<double>>& bev_range, const std::optional<double>& bev_cell,
                         const std::optional<std::string>& overlays, const py::object& options,
                         const std::optional<std::pair<int, int>>& resize) {
  const SegmentationEvalOptions o = evalOptions(bootstrap, camera, bev, bev_range, bev_cell, overlays, resize);
  std::unique_ptr<VisionPipeline> made;
  VisionPipeline* run = nullptr;
  if (py::isinstance<py::str>(pipeline)) {
    made = createPipeline(pipeline.cast<std::string>(), optionsText(options));
    run = made.get();
  } else {
    if (!options.is_none()) throw InvalidInput("options: only with a pipeline's name (a Pipeline is configured already)");
    run = &pipeline.cast<VisionPipeline&>();
  }
  // The GIL stays held: the pipeline may be one Python holds, and is not safe to share between threads.
  return evaluationJson(evaluateSegmentation(*run, images, labels, LabelClasses{road_values, ignore_values}, o));
}

py::object evaluate(const py::object& pipeline, const std::string& images, const std::string& labels,
                    const std::vector<int>& road_values, const std::vector<int>& ignore_values,
                    const std::string& bootstrap, const std::optional<std::string>& camera, bool bev,
                    const std::optional<std::vector<double>>& bev_range, const std::optional<double>& bev_cell,
                    const std::optional<std::string>& overlays, const py::object& options,
                    const std::optional<std::pair<int, int>>& resize) {
  return fromJson(evaluateText(pipeline, images, labels, road_values, ignore_values, bootstrap, camera, bev, bev_range,
                               bev_cell, overlays, options, resize));
}

}  // namespace

void bindEval(py::module_& m) {
  m.def("evaluate_segmentation", &evaluate, py::arg("pipeline"), py::arg("images"), py::arg("labels"),
        py::arg("road_values") = std::vector<int>{3}, py::arg("ignore_values") = std::vector<int>{},
        py::arg("bootstrap") = "trapezoid", py::arg("camera") = py::none(), py::arg("bev") = false,
        py::arg("bev_range") = py::none(), py::arg("bev_cell") = py::none(), py::arg("overlays") = py::none(),
        py::arg("options") = py::none(), py::arg("resize") = py::none(),
        "A pipeline (a Pipeline, run as it is: reset() it for a fresh start; or a name, made with `options`) over "
        "the labelled photos of the folders `images` and `labels`, scored as `mapnav eval segmentation` does "
        "(docs/eval.md): the dict its --json prints. bootstrap 'trapezoid' or 'labels-first-frame'; camera a "
        "camera file (default: the assumed level pin-hole); bev=True scores in a bird's-eye grid (needs camera; "
        "bev_range (x0, x1, z0, z1) and bev_cell in metres, KITTI's by default); overlays a folder; resize "
        "(width, height) scores the photos resized to that size (as --resize).");
  m.def("_evaluate_task", &evaluateText, py::arg("pipeline"), py::arg("images"), py::arg("labels"),
        py::arg("road_values") = std::vector<int>{3}, py::arg("ignore_values") = std::vector<int>{},
        py::arg("bootstrap") = "trapezoid", py::arg("camera") = py::none(), py::arg("bev") = false,
        py::arg("bev_range") = py::none(), py::arg("bev_cell") = py::none(), py::arg("overlays") = py::none(),
        py::arg("options") = py::none(), py::arg("resize") = py::none(),
        "For mapnav.distributed: evaluate_segmentation's scores as the JSON text `mapnav eval segmentation "
        "--json` prints.");
}

}  // namespace mapnav::python
