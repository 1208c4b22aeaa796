#include "train_command.h"

#include <algorithm>
#include <optional>
#include <ostream>
#include <sstream>

#include "cli.h"
#include "command_line.h"
#include "command_support.h"
#include "mapnav/learned/learned_api.h"

namespace mapnav::cli {

namespace {

std::string bar(int done, int total) {
  const int width = 24, filled = total > 0 ? done * width / total : width;
  return "[" + std::string(static_cast<std::size_t>(filled), '#') + std::string(static_cast<std::size_t>(width - filled), '.') + "]";
}

}  // namespace

int runTrainSegmentation(const TrainSegmentationConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    // In the flags' words first (a usage error); trainSegmentationModel checks the set again.
    if (config.set.images.empty() != config.set.labels.empty()) throw UsageError("--images and --labels go together");
    if (config.set.images.empty() && config.set.logs.empty())
      throw UsageError("nothing to train on: give --images and --labels, or --log");
    const TrainedModelSummary model = trainSegmentationModel(
        config.set, config.options,
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
      out << trainedModelJson(config.output, model);
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
  ts->add_option("--images", config->set.images, "Folder of RGB photos (PNG)");
  ts->add_option("--labels", config->set.labels, "Folder of 1-channel class-index PNGs, one per photo, same file stem");
  ts->add_option("--log", config->set.logs,
                 "Replay log (mapnav simulate) whose frames and ground-truth road masks are trained on too; repeatable "
                 "(the simulator's world has a model of its own: train it on logs of other seeds than the missions')");
  ts->add_option("--log-stride", config->set.log_stride, "Every n-th frame of each log")->default_val(config->set.log_stride);
  ts->add_option("--road-values", text->road, "Label values that are road, comma-separated (CamVid: 3 road, 4 pavement)")
      ->default_val("3");
  ts->add_option("--ignore-values", text->ignore, "Label values left out of the loss (CamVid: 11 unlabelled)");
  ts->add_option("--camera", config->set.camera,
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
    config->set.classes.road = parseLabelValues("--road-values", text->road);
    config->set.classes.ignore = parseLabelValues("--ignore-values", text->ignore);
    std::string size_text = text->size;
    std::replace(size_text.begin(), size_text.end(), 'x', ',');
    const std::vector<double> size = parseNumbers("--size", size_text, 2, 2, "WxH (pixels)");
    config->options.width = static_cast<int>(size[0]);
    config->options.height = static_cast<int>(size[1]);
    std::ostringstream cmd;
    cmd << "mapnav train segmentation";
    if (!config->set.images.empty())
      cmd << " --images " << config->set.images << " --labels " << config->set.labels << " --road-values " << text->road
          << (text->ignore.empty() ? "" : " --ignore-values " + text->ignore);
    for (const std::string& log : config->set.logs) cmd << " --log " << log;
    if (!config->set.logs.empty()) cmd << " --log-stride " << config->set.log_stride;
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
