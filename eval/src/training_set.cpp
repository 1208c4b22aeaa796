#include "mapnav/eval/training_set.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "json_figure.h"
#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/eval/labelled_photos.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/learned/learned_module.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/vision/overlay.h"

namespace mapnav {

namespace {

/// A label as the trainer wants it: 1 road, 255 left out, 0 the rest.
Image trainingLabel(const Image& label, const LabelClasses& classes) {
  std::uint8_t lut[256] = {};
  for (int v : classes.road) lut[v] = 1;
  for (int v : classes.ignore) lut[v] = 255;
  Image out(label.width, label.height, 1);
  for (std::size_t i = 0; i < out.data.size(); ++i) out.data[i] = lut[label.data[i]];
  return out;
}

/// Every `stride`-th frame of the log at `dir` that has a ground-truth road mask (255 = road).
void appendLogFrames(const std::string& dir, int stride, std::vector<TrainingPhoto>& photos) {
  const ReplayLog log = ReplayLog::open(dir);
  const Image ground = groundMask(*log.header().camera);
  std::size_t added = 0;
  for (std::size_t i = 0; i < log.frames().size(); i += static_cast<std::size_t>(stride)) {
    std::optional<Image> mask = log.mask(i);
    if (!mask) continue;
    for (std::uint8_t& v : mask->data) v = v != 0 ? 1 : 0;
    photos.push_back({dir + " frame " + std::to_string(i), toRgb(log.image(i)), std::move(*mask), ground});
    ++added;
  }
  if (added == 0) throw InvalidInput(dir + ": no frame with a ground-truth road mask (logs of mapnav simulate have them)");
}

}  // namespace

void TrainingSet::validate() const {
  classes.validate();
  if (images.empty() != labels.empty()) throw InvalidInput("images and labels go together");
  if (images.empty() && logs.empty()) throw InvalidInput("nothing to train on: give images and labels, or a log");
  if (log_stride < 1) throw InvalidInput("log_stride " + std::to_string(log_stride) + ": must be >= 1");
}

std::vector<TrainingPhoto> readTrainingPhotos(const TrainingSet& set) {
  set.validate();
  std::vector<TrainingPhoto> photos;
  if (!set.images.empty()) {
    for (const LabelledPhoto& s : readLabelledPhotos(set.images, set.labels, false)) {
      const std::unique_ptr<Camera> camera =
          set.camera.empty() ? assumedPhotoCamera(s.image.width, s.image.height) : loadCamera(set.camera);
      if (camera->width() != s.image.width || camera->height() != s.image.height)
        throw InvalidInput(s.image_file.string() + ": the photo is " + std::to_string(s.image.width) + "x" +
                           std::to_string(s.image.height) + " but the camera's image " + std::to_string(camera->width()) +
                           "x" + std::to_string(camera->height()));
      photos.push_back({s.image_file.string(), s.image, trainingLabel(s.label, set.classes), groundMask(*camera)});
    }
  }
  for (const std::string& dir : set.logs) appendLogFrames(dir, set.log_stride, photos);
  return photos;
}

TrainedModelSummary trainSegmentationModel(const TrainingSet& set, const SegmentationTrainOptions& options,
                                           const std::function<void(const EpochReport&)>& progress,
                                           const std::string& command, const std::string& output) {
  options.validate();
  if (output.empty()) throw InvalidInput("output: the model file to write is required");
  const std::vector<TrainingPhoto> photos = readTrainingPhotos(set);
  return learnedModule().train(photos, options, progress, command, output);
}

std::string trainedModelJson(const std::string& output, const TrainedModelSummary& model) {
  const SegmentationTraining& t = model.training;
  const std::optional<double> validation = t.validation_iou < 0 ? std::nullopt : std::optional<double>(t.validation_iou);
  const Json j = {{"model", output},
                  {"parameters", model.parameters},
                  {"input", {{"width", model.width}, {"height", model.height}}},
                  {"training_images", t.training_images},
                  {"validation_images", t.validation_images},
                  {"epochs", t.epochs},
                  {"seed", t.seed},
                  {"final_loss", figure(t.final_loss)},
                  {"validation_iou", figure(validation)}};
  return j.dump(2) + "\n";
}

}  // namespace mapnav
