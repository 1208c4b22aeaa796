// The "learned" pipeline: a SegmentationModel behind ScorePipeline (docs/learned.md).
#include "mapnav/learned/learned_pipeline.h"

#include <mutex>
#include <unistd.h>

#include "mapnav/core/error.h"
#include "mapnav/learned/learned_api.h"
#include "mapnav/learned/segmentation_model.h"
#include "mapnav/learned/train_segmentation.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {

std::filesystem::path resolveSegmentationModel(const std::string& name_or_path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_regular_file(name_or_path, ec)) return name_or_path;
  std::vector<fs::path> tried;
  if (name_or_path.find('/') == std::string::npos && name_or_path.find('.') == std::string::npos) {
    const std::string file = name_or_path + ".mnseg";
    char exe[4096];
    const ssize_t len = ::readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (len > 0) tried.push_back(fs::path(std::string(exe, static_cast<std::size_t>(len))).parent_path().parent_path() /
                                 "share/mapnav/models" / file);
    tried.push_back(fs::path(MAPNAV_SOURCE_DIR) / "models" / file);
    for (const fs::path& p : tried)
      if (fs::is_regular_file(p, ec)) return p;
  }
  std::string where;
  for (const fs::path& p : tried) where += (where.empty() ? "" : ", ") + p.string();
  throw NotFound("model \"" + name_or_path + "\": no such file" + (where.empty() ? "" : " (looked for " + where + ")"));
}

namespace {

class LearnedPipeline : public ScorePipeline {
 public:
  LearnedPipeline() : ScorePipeline("learned") {}
  void configure(const std::string& options_json) override {
    LearnedPipelineOptions o = learnedPipelineOptionTable().parse(options_json, LearnedPipelineOptions{}, "pipeline \"learned\"");
    if (!model_ || o.model != options_.model) model_ = std::make_unique<SegmentationModel>(SegmentationModel::load(resolveSegmentationModel(o.model)));
    options_ = std::move(o);
    SegmentationModel::setThreads(options_.threads);
  }

 protected:
  std::vector<float> roadProbability(const std::uint8_t* rgb, int width, int height, const std::uint8_t* ground) override {
    if (!model_) configure("{}");  // never configured: the defaults
    return model_->roadProbability(rgb, width, height, ground);
  }
  const ScorePipelineOptions& scoreOptions() const override { return options_; }

  // Online adaptation (LearnedPipelineOptions::adapt): the predicted road is road, the rest as
  // adapt_outside says; one gradient step on those labels. A region that no longer holds the
  // predicted road puts the loaded weights back.
  void learnFrom(const std::uint8_t* rgb, int width, int height, const std::uint8_t* ground,
                 const std::vector<float>& probability, const std::uint8_t* predicted) override {
    if (!options_.adapt || !model_) return;
    const std::size_t n = static_cast<std::size_t>(width) * height;
    std::vector<std::uint8_t> labels(n, 2);  // 2: left out
    double held = 0, mapped_cells = 0;
    const double c = options_.adapt_confidence;
    const bool confident_outside = options_.adapt_outside == AdaptOutside::Confident;
    for (std::size_t i = 0; i < n; ++i) {
      if (ground[i] == 0) continue;
      const bool road = probability[i] > 0.5, mapped = predicted[i] != 0;
      held += road && mapped;
      mapped_cells += mapped;
      if (mapped) labels[i] = 1;
      else if (probability[i] >= c) labels[i] = confident_outside ? 1 : 2;
      else if (probability[i] <= 1 - c || !confident_outside) labels[i] = 0;
    }
    if (mapped_cells > 0 && held / mapped_cells < options_.adapt_reset_cover) {
      model_->resetAdaptation();
      frames_ = 0;
      return;
    }
    if (frames_++ % options_.adapt_every != 0) return;
    model_->adapt(rgb, width, height, ground, labels.data(), options_.adapt_rate, options_.adapt_layers);
  }

 public:
  void reset() override {
    if (model_) model_->resetAdaptation();
    frames_ = 0;
  }

 private:
  LearnedPipelineOptions options_;
  std::unique_ptr<SegmentationModel> model_;
  std::size_t frames_ = 0;  // frames adapted from since the loaded weights
};

}  // namespace

void registerLearnedPipeline() {
  static std::once_flag once;
  std::call_once(once, [] {
    registerPipeline({"learned",
                      "A small fully-convolutional network's road probability per pixel (docs/learned.md; mapnav train "
                      "segmentation makes one), needing no bootstrap; then region reproduction (2.2.1) and line labelling "
                      "(2.2.2) as the other region pipelines",
                      learnedPipelineOptionTable().list(), [] { return std::make_unique<LearnedPipeline>(); },
                      learnedPipelineOptionTable().presets()});
  });
}

}  // namespace mapnav

namespace {

mapnav::TrainedModelSummary trainAndSave(const std::vector<mapnav::TrainingPhoto>& photos,
                                         const mapnav::SegmentationTrainOptions& options,
                                         const std::function<void(const mapnav::EpochReport&)>& progress,
                                         const std::string& command, const std::string& output) {
  const mapnav::SegmentationModel model = mapnav::trainSegmentation(photos, options, progress, command);
  model.save(output);
  return {model.parameterCount(), model.inputWidth(), model.inputHeight(), model.training()};
}

}  // namespace

/// Loaded as a plug-in (`--plugin libmapnav_learned.so`, or by the CLI when a command needs it) by a
/// program that does not link it: registers "learned".
extern "C" int mapnav_register_pipelines() {
  mapnav::registerLearnedPipeline();
  return 1;
}

/// The training entry for such a program (learned_api.h).
extern "C" const mapnav::LearnedApi* mapnav_learned_api() {
  static const mapnav::LearnedApi api{&trainAndSave};
  return &api;
}
