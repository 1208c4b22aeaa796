// A vision pipeline evaluated on labelled photos: `mapnav eval segmentation` from Python, its
// figures as the dict of `--json`; and the learned network trained on them (`mapnav train
// segmentation`).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "convert.h"
#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/eval/segmentation_evaluation.h"
#include "mapnav/eval/training_set.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav::python {

namespace {

using namespace pybind11::literals;

SegmentationEvalOptions evalOptions(const std::string& bootstrap, const std::optional<std::string>& camera, bool bev,
                                    const std::optional<std::vector<double>>& bev_range,
                                    const std::optional<double>& bev_cell, const std::optional<std::string>& overlays,
                                    const std::optional<std::pair<int, int>>& resize, bool grey) {
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
  o.grey = grey;
  return o;
}

// The scores as the JSON text `mapnav eval segmentation --json` prints; python/mapnav/__init__.py's
// evaluate_segmentation gives them as a dict.
std::string evaluateText(const py::object& pipeline, const std::string& images, const std::string& labels,
                         const std::vector<int>& road_values, const std::vector<int>& ignore_values,
                         const std::string& bootstrap, const std::optional<std::string>& camera, bool bev,
                         const std::optional<std::vector<double>>& bev_range, const std::optional<double>& bev_cell,
                         const std::optional<std::string>& overlays, const py::object& options,
                         const std::optional<std::pair<int, int>>& resize, bool grey) {
  const SegmentationEvalOptions o = evalOptions(bootstrap, camera, bev, bev_range, bev_cell, overlays, resize, grey);
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

// The call as the model file records it (its training.command, docs/learned.md "The model file").
std::string trainingCall(const TrainingSet& set, const SegmentationTrainOptions& options, const std::string& output) {
  Json args = Json::object();
  if (!set.images.empty()) args["images"] = set.images, args["labels"] = set.labels;
  if (!set.logs.empty()) args["logs"] = set.logs, args["log_stride"] = set.log_stride;
  args["road_values"] = set.classes.road;
  args["ignore_values"] = set.classes.ignore;
  if (!set.camera.empty()) args["camera"] = set.camera;
  args["options"] = Json::parse(segmentationTrainOptionTable().json(options));
  args["output"] = output;
  return "mapnav.train_segmentation(**" + args.dump() + ")";
}

py::object train(const std::string& output, const std::optional<std::string>& images,
                 const std::optional<std::string>& labels, const std::vector<std::string>& logs, int log_stride,
                 const std::vector<int>& road_values, const std::vector<int>& ignore_values,
                 const std::optional<std::string>& camera, const py::object& options, const py::object& progress) {
  TrainingSet set;
  set.images = images.value_or("");
  set.labels = labels.value_or("");
  set.logs = logs;
  set.log_stride = log_stride;
  set.classes = LabelClasses{road_values, ignore_values};
  set.camera = camera.value_or("");
  const SegmentationTrainOptions o = segmentationTrainOptionTable().parse(optionsText(options), {}, "options");
  if (!progress.is_none() && !PyCallable_Check(progress.ptr())) throw InvalidInput("progress: must be callable or None");
  std::function<void(const EpochReport&)> report;
  if (!progress.is_none())
    report = [&progress](const EpochReport& r) {
      const py::gil_scoped_acquire gil;
      progress(py::dict("epoch"_a = r.epoch, "epochs"_a = r.epochs, "loss"_a = r.loss,
                        "validation_iou"_a = r.validation_iou ? py::object(py::float_(*r.validation_iou)) : py::none()));
    };
  const std::string command = trainingCall(set, o, output);
  TrainedModelSummary model;
  {
    const py::gil_scoped_release released;  // the training runs for minutes; other Python threads go on
    model = trainSegmentationModel(set, o, report, command, output);
  }
  return fromJson(trainedModelJson(output, model));
}

}  // namespace

void bindEval(py::module_& m) {
  m.def("_evaluate_task", &evaluateText, py::arg("pipeline"), py::arg("images"), py::arg("labels"),
        py::arg("road_values") = std::vector<int>{3}, py::arg("ignore_values") = std::vector<int>{},
        py::arg("bootstrap") = "trapezoid", py::arg("camera") = py::none(), py::arg("bev") = false,
        py::arg("bev_range") = py::none(), py::arg("bev_cell") = py::none(), py::arg("overlays") = py::none(),
        py::arg("options") = py::none(), py::arg("resize") = py::none(), py::arg("grey") = false,
        "evaluate_segmentation's scores as the JSON text `mapnav eval segmentation --json` prints "
        "(mapnav.evaluate_segmentation, mapnav.distributed).");
  m.def("train_segmentation", &train, py::arg("output"), py::arg("images") = py::none(), py::arg("labels") = py::none(),
        py::arg("logs") = std::vector<std::string>{}, py::arg("log_stride") = TrainingSet{}.log_stride,
        py::arg("road_values") = std::vector<int>{3}, py::arg("ignore_values") = std::vector<int>{},
        py::arg("camera") = py::none(), py::arg("options") = py::none(), py::arg("progress") = py::none(),
        "`mapnav train segmentation` (docs/learned.md): the learned pipeline's network trained on the labelled "
        "photos of the folders `images` and `labels` and/or the frames of simulator logs (every log_stride-th), "
        "written atomically to `output`; the dict its --json prints. options: a dict or JSON text of "
        "SegmentationTrainOptions (docs/options.md: epochs, seed, width, height, threads, augmentation); "
        "progress(dict) is called after every epoch with epoch, epochs, loss and validation_iou. Same inputs, "
        "options and seed, same model bytes. NotFound when this build has no learned module.");
}

}  // namespace mapnav::python
