// Vision: the pipeline registry, Pipeline.detect / .segment on numpy frames, the Detection token,
// images, and the benchmark's sidewalk scene.

#include <cmath>

#include "convert.h"
#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/image/png.h"
#include "mapnav/image/read_image.h"
#include "mapnav/learned/learned_module.h"
#include "mapnav/mission/image_region.h"
#include "mapnav/tokens/token_json.h"
#include "mapnav/scenes/sidewalk_scene.h"
#include "mapnav/vision/detection_io.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision/segmentation_eval.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav::python {

namespace {

using namespace pybind11::literals;

py::object maskOrNone(const Image& image) { return image.empty() ? py::object(py::none()) : toArray(image); }

py::object segmentOrNone(const std::optional<Segment2>& s) {
  return s ? py::object(toArray(std::vector<Vec2>{s->a, s->b})) : py::object(py::none());
}

void bindDetection(py::module_& m) {
  py::class_<DetectedLine>(m, "DetectedLine", "An edge line Vision found.")
      .def_readonly("label", &DetectedLine::label, "the predicted segment id it matches, or None")
      .def_readonly("score", &DetectedLine::score)
      .def_readonly("frame_edge", &DetectedLine::frame_edge)
      .def_property_readonly("image", [](const DetectedLine& l) { return toArray(std::vector<Vec2>{l.image.a, l.image.b}); })
      .def_property_readonly("vehicle", [](const DetectedLine& l) { return toArray(std::vector<Vec2>{l.vehicle.a, l.vehicle.b}); });
  py::class_<DetectedObject>(m, "Detection", "What Vision found in one frame (the Detected Object token).")
      .def_property_readonly("ok", [](const DetectedObject& d) { return d.status == DetectedObject::Status::Ok; })
      .def_readonly("reason", &DetectedObject::reason, "why it failed, \"\" when ok")
      .def_readonly("confidence", &DetectedObject::confidence)
      .def_readonly("lines", &DetectedObject::lines)
      .def_property_readonly("region_image", [](const DetectedObject& d) { return toArray(d.region_image); }, "N x 2, px")
      .def_property_readonly("region_vehicle", [](const DetectedObject& d) { return toArray(d.region_vehicle); }, "N x 2, m")
      .def_property_readonly("centerline", [](const DetectedObject& d) { return segmentOrNone(d.centerline_vehicle); },
                             "2 x 2, vehicle frame, or None")
      .def_property_readonly("road_mask", [](const DetectedObject& d) { return maskOrNone(d.road_mask); })
      .def_property_readonly("road_confidence", [](const DetectedObject& d) { return maskOrNone(d.road_confidence); })
      .def("to_json", [](const DetectedObject& d) { return dumpJson(toJson(d)); },
           "The detection as `mapnav detect --json` prints it (str).")
      .def("__repr__", [](const DetectedObject& d) {
        return d.status == DetectedObject::Status::Ok ? "<Detection ok, " + std::to_string(d.lines.size()) + " lines>"
                                                      : "<Detection failed: " + d.reason + ">";
      });
}

// The frame read in place. The GIL stays held: a pipeline is not safe to share between threads, and
// two Python threads calling one pipeline's detect then take turns instead of racing.
DetectedObject detectIn(VisionPipeline& pipeline, const py::array& image, const PyPrediction& p, double t, bool masks) {
  if (!std::isfinite(t)) throw InvalidInput("timestamp: must be finite");
  const RgbView rgb = rgbView(image, "image");
  checkCameraFrame("image", rgb.width, rgb.height, 3, *p.camera);
  VisionFrame frame{rgb.width, rgb.height, rgb.data, p.camera.get(), t};
  frame.want_masks = masks;
  return pipeline.detect(frame, p.prediction.view);
}

struct Segmentation {
  py::object mask, confidence;
  DetectedObject detection;
};

Segmentation segment(VisionPipeline& pipeline, const py::array& image, const PyPrediction& p, bool masks) {
  Segmentation s;
  s.detection = detectIn(pipeline, image, p, 0.0, masks);
  const int w = p.camera->width(), h = p.camera->height();
  const bool ok = s.detection.status == DetectedObject::Status::Ok;
  s.mask = toArray(ok ? regionMask(s.detection, w, h) : Image(w, h, 1));
  s.confidence = maskOrNone(s.detection.road_confidence);
  return s;
}

void bindPipeline(py::module_& m) {
  py::class_<Segmentation>(m, "Segmentation", "A road mask, the confidence where the pipeline gives one, the detection.")
      .def_readonly("mask", &Segmentation::mask, "H x W uint8, 255 = road (all 0 when the pipeline failed)")
      .def_readonly("confidence", &Segmentation::confidence, "H x W uint8 0..255, or None")
      .def_readonly("detection", &Segmentation::detection);
  py::class_<VisionPipeline>(m, "Pipeline", "A vision pipeline (create_pipeline).")
      .def_property_readonly("name", &VisionPipeline::name)
      .def("detect", &detectIn, py::arg("image"), py::arg("prediction"), py::arg("timestamp") = 0.0,
           py::arg("masks") = false,
           "Runs on an H x W x 3 uint8 C-contiguous frame (read in place, no copy) of the prediction's camera; "
           "masks=True also asks for the per-pixel road_mask and road_confidence.")
      .def("segment", &segment, py::arg("image"), py::arg("prediction"), py::arg("masks") = false,
           "The road mask `mapnav segment` writes (masks=False), with the pipeline's own per-pixel mask and "
           "confidence when masks=True.")
      .def("reset", &VisionPipeline::reset, "Forgets what was learnt from earlier frames.");
  m.def(
      "pipelines",
      [] {
        py::list out;
        for (const PipelineInfo& info : listPipelines()) {
          py::list options, presets;
          for (const OptionInfo& o : info.options)
            options.append(py::dict("name"_a = o.name, "default"_a = fromJson(o.default_json), "description"_a = o.description));
          for (const OptionPreset& p : info.presets)
            presets.append(py::dict("name"_a = p.name, "options"_a = fromJson(p.json), "description"_a = p.description));
          out.append(py::dict("name"_a = info.name, "description"_a = info.description, "options"_a = options,
                              "presets"_a = presets));
        }
        return out;
      },
      "The vision pipelines available, with their options and defaults, as `mapnav pipelines`.");
  m.def(
      "create_pipeline",
      [](const std::string& name, const py::object& options) {
        loadPipelineModule(name);  // "learned" opens the learned module (Torch), as the CLI does
        return createPipeline(name, optionsText(options));
      },
      py::arg("name"), py::arg("options") = py::none(),
      "A pipeline by name, configured with `options` (a dict or JSON text). NotFound lists the names; "
      "InvalidInput names a bad option.");
  m.def("load_plugin", &loadPlugin, py::arg("path"), "Loads a vision plug-in (a shared library); returns how many it registered.");
}

void bindImages(py::module_& m) {
  m.def("read_image", [](const std::string& path) { return toArray(readImage(path)); }, py::arg("path"),
        "A PNG or JPEG as H x W x 3 (colour) or H x W (grey) uint8.");
  m.def("write_png", [](const std::string& path, const py::array& image) { writePng(toImage(image, "image"), path); },
        py::arg("path"), py::arg("image"), "Writes an H x W or H x W x 3 uint8 array as PNG.");
  m.def(
      "prediction_from_region",
      [](const py::object& polygon, std::shared_ptr<const Camera> camera) {
        Prediction p = predictionFromImageRegion(toPoints(polygon, "polygon"), *camera);
        return std::make_shared<PyPrediction>(PyPrediction{std::move(p), std::move(camera), nullptr});
      },
      py::arg("polygon"), py::arg("camera"),
      "A prediction without a map: the image polygon (N x 2, px) as one road, as `mapnav segment --train-region`.");
  m.def("bottom_trapezoid", [](int w, int h) { return toArray(bottomTrapezoid(w, h)); }, py::arg("width"), py::arg("height"),
        "`mapnav eval`'s bootstrap region: the bottom-centre trapezoid of a w x h photo (N x 2, px).");
  m.def(
      "sidewalk_scene",
      [](const std::string& maps, int frames) {
        SidewalkScene s = makeSidewalkScene(maps, frames);
        const std::shared_ptr<const Camera> camera = std::move(s.camera);
        py::list images, predictions;
        for (std::size_t i = 0; i < s.frames.size(); ++i) {
          images.append(toArray(std::move(s.frames[i].rgb)));
          Prediction p;
          p.pose = s.poses[i];
          p.view = s.predictions[i];
          predictions.append(std::make_shared<PyPrediction>(PyPrediction{std::move(p), camera, nullptr}));
        }
        return py::make_tuple(std::const_pointer_cast<Camera>(camera), images, predictions);
      },
      py::arg("maps"), py::arg("frames") = 8,
      "The benchmark's sidewalk scene (bench/sidewalk_bench.cpp, `mapnav bench`): (camera, frames, predictions), "
      "512 x 480 frames down R1 of maps/cmu_campus.json; `maps` is the maps/ folder.");
}

}  // namespace

void bindVision(py::module_& m) {
  bindDetection(m);
  bindPipeline(m);
  bindImages(m);
}

}  // namespace mapnav::python
