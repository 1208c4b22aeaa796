#include "train_command.h"

#include <algorithm>
#include <cmath>
#include <ostream>
#include <sstream>

#include "cli.h"
#include "command_line.h"
#include "command_support.h"
#include "json_numbers.h"
#include "learned_module.h"
#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/eval/labelled_photos.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/learned/learned_api.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision/segmentation_eval.h"

namespace mapnav::cli {

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

std::string bar(int done, int total) {
  const int width = 24, filled = total > 0 ? done * width / total : width;
  return "[" + std::string(static_cast<std::size_t>(filled), '#') + std::string(static_cast<std::size_t>(width - filled), '.') + "]";
}

}  // namespace

int runTrainSegmentation(const TrainSegmentationConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    config.classes.validate();
    config.options.validate();
    if (config.output.empty()) throw UsageError("-o: the model file to write is required");
    if (config.images.empty() != config.labels.empty()) throw UsageError("--images and --labels go together");
    if (config.images.empty() && config.logs.empty()) throw UsageError("nothing to train on: give --images and --labels, or --log");
    if (config.log_stride < 1) throw InvalidInput("--log-stride " + std::to_string(config.log_stride) + ": must be >= 1");
    std::vector<TrainingPhoto> photos;
    if (!config.images.empty()) {
      for (const LabelledPhoto& s : readLabelledPhotos(config.images, config.labels, false)) {
        const std::unique_ptr<Camera> camera =
            config.camera.empty() ? assumedPhotoCamera(s.image.width, s.image.height) : loadCamera(config.camera);
        if (camera->width() != s.image.width || camera->height() != s.image.height)
          throw InvalidInput(s.image_file.string() + ": the photo is " + std::to_string(s.image.width) + "x" +
                             std::to_string(s.image.height) + " but the camera's image " + std::to_string(camera->width()) +
                             "x" + std::to_string(camera->height()));
        photos.push_back({s.image_file.string(), s.image, trainingLabel(s.label, config.classes), groundMask(*camera)});
      }
    }
    for (const std::string& dir : config.logs) appendLogFrames(dir, config.log_stride, photos);
    const TrainedModelSummary model = learnedModule().train(
        photos, config.options,
        [&](const EpochReport& r) {
          std::ostringstream line;
          line << "epoch " << r.epoch << "/" << r.epochs << " " << bar(r.epoch, r.epochs) << " loss "
               << fixedOr(r.loss, 4, "-") << "  validation IoU " << fixedOr(r.validation_iou, 4, "-");
          err << "\r" << line.str() << (r.epoch == r.epochs ? "\n" : "") << std::flush;
        },
        config.command, config.output);
    const SegmentationTraining& t = model.training;
    const std::optional<double> validation = t.validation_iou < 0 ? std::nullopt : std::optional<double>(t.validation_iou);
    if (config.json) {
      Json j = {{"model", config.output},
                {"parameters", model.parameters},
                {"input", {{"width", model.width}, {"height", model.height}}},
                {"training_images", t.training_images},
                {"validation_images", t.validation_images},
                {"epochs", t.epochs},
                {"seed", t.seed},
                {"final_loss", roundedOrNull(t.final_loss, 4)},
                {"validation_iou", roundedOrNull(validation, 4)}};
      out << j.dump(2) << "\n";
    } else {
      out << "wrote " << config.output << ": " << model.parameters << " weights, input " << model.width << "x"
          << model.height << ", trained on " << t.training_images << " photos ("
          << t.validation_images << " held apart: validation IoU " << fixedOr(validation, 4, "-") << ")\n";
    }
    return static_cast<int>(kOk);
  });
}

void registerTrainCommand(CLI::App& app, Commands& commands) {
  auto* config = commands.hold<TrainSegmentationConfig>();
  struct Texts {
    std::string road = "3", ignore, size = "240x180";
  };
  auto* text = commands.hold<Texts>();
  CLI::App* train = app.add_subcommand("train", "Train the learned vision pipeline's network (docs/learned.md)");
  train->require_subcommand(1);
  CLI::App* ts = train->add_subcommand(
      "segmentation", "Train a small fully-convolutional road segmentation network on labelled photos, on CPU; "
                      "every tenth photo is held apart for the validation IoU shown after each epoch");
  ts->add_option("--images", config->images, "Folder of RGB photos (PNG)");
  ts->add_option("--labels", config->labels, "Folder of 1-channel class-index PNGs, one per photo, same file stem");
  ts->add_option("--log", config->logs,
                 "Replay log (mapnav simulate) whose frames and ground-truth road masks are trained on too; repeatable "
                 "(the simulator's world has a model of its own: train it on logs of other seeds than the missions')");
  ts->add_option("--log-stride", config->log_stride, "Every n-th frame of each log")->default_val(config->log_stride);
  ts->add_option("--road-values", text->road, "Label values that are road, comma-separated (CamVid: 3 road, 4 pavement)")
      ->default_val("3");
  ts->add_option("--ignore-values", text->ignore, "Label values left out of the loss (CamVid: 11 unlabelled)");
  ts->add_option("--camera", config->camera,
                 "Camera file of the photos (where it sees the ground is an input of the network; default: the "
                 "assumed level pin-hole of docs/eval.md)")
      ->check(CLI::ExistingFile);
  ts->add_option("--epochs", config->options.epochs, "Passes over the training photos")->capture_default_str();
  ts->add_option("--seed", config->options.seed, "Seed of the initial weights, the order and the augmentation")
      ->capture_default_str();
  ts->add_option("--size", text->size, "The network's input size WxH, pixels (photos are resized to it)")->default_val("240x180");
  ts->add_option("--threads", config->options.threads, "CPU threads (the model is the same for the same count)")
      ->capture_default_str();
  ts->add_option("--grey-fraction", config->options.grey_fraction,
                 "Augmentation: the fraction of photos turned grey (0 = none)")->capture_default_str();
  ts->add_option("--contrast", config->options.contrast, "Augmentation: the contrast scaled by 1 +- up to this (0 = none)")
      ->capture_default_str();
  ts->add_option("--blur-fraction", config->options.blur_fraction,
                 "Augmentation: the fraction of photos blurred, 3 x 3 box (0 = none)")->capture_default_str();
  ts->add_option("--noise-levels", config->options.noise_levels,
                 "Augmentation: Gaussian noise of a sigma up to this, grey levels (0 = none)")->capture_default_str();
  ts->add_option("--zoom", config->options.zoom, "Augmentation: zoomed by up to this half the time (1 = never)")
      ->capture_default_str();
  ts->add_option("-o,--output", config->output, "Model file to write")->required();
  ts->add_flag("--json", config->json, "Print the result as JSON");
  ts->footer("Exit codes: 0 trained and written, 1 invalid input (an image without its label, a label of another "
             "size, a corrupt PNG), 2 usage or I/O error (a missing folder). Nothing is written unless training ends.");
  ts->callback(commands.choose([config, text](std::ostream& out, std::ostream& err) {
    config->classes.road = parseLabelValues("--road-values", text->road);
    config->classes.ignore = parseLabelValues("--ignore-values", text->ignore);
    std::string size_text = text->size;
    std::replace(size_text.begin(), size_text.end(), 'x', ',');
    const std::vector<double> size = parseNumbers("--size", size_text, 2, 2, "WxH (pixels)");
    config->options.width = static_cast<int>(size[0]);
    config->options.height = static_cast<int>(size[1]);
    std::ostringstream cmd;
    cmd << "mapnav train segmentation";
    if (!config->images.empty())
      cmd << " --images " << config->images << " --labels " << config->labels << " --road-values " << text->road
          << (text->ignore.empty() ? "" : " --ignore-values " + text->ignore);
    for (const std::string& log : config->logs) cmd << " --log " << log;
    if (!config->logs.empty()) cmd << " --log-stride " << config->log_stride;
    cmd << " --epochs "
        << config->options.epochs << " --seed " << config->options.seed << " --size " << text->size << " --threads "
        << config->options.threads << " --grey-fraction " << config->options.grey_fraction << " --contrast "
        << config->options.contrast << " --blur-fraction " << config->options.blur_fraction << " --noise-levels "
        << config->options.noise_levels << " --zoom " << config->options.zoom << " -o " << config->output;
    config->command = cmd.str();
    return runTrainSegmentation(*config, out, err);
  }));
}

}  // namespace mapnav::cli
