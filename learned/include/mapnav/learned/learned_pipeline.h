#pragma once
// The "learned" vision pipeline (docs/learned.md): a SegmentationModel's road probability per
// pixel, then the region, polygon, lines and their labels of every region pipeline (ScorePipeline).
// At its defaults it trains nothing on the prediction: the prediction only says which region is the
// road and which lines are which; with `adapt` it fine-tunes the network from it online.
#include <filesystem>
#include <string>

#include "mapnav/core/option_table.h"
#include "mapnav/vision/pipelines.h"

namespace mapnav {

/// What the learned pipeline's online adaptation trains the cells outside the predicted road as.
enum class AdaptOutside { NotRoad, Confident };

struct LearnedPipelineOptions : ScorePipelineOptions {
  /// A model file, or the name of a committed model: "camvid" (road and pavement, trained on
  /// ../shared/data/real/camvid_train) or "sim" (the simulator's paths, trained on its logs).
  std::string model = "camvid";
  int threads = 1;  ///< Torch's CPU threads for this process; 0 = Torch's default (every core)
  /// Online adaptation (the papers' adaptive classification, for the network): after each frame with
  /// a prediction (the Map's, or an eval's or log track's bootstrap), one gradient step on the last
  /// adapt_layers convolutions. Labels: the predicted road is road; the rest as adapt_outside says.
  /// Off by default: it pays where the model meets another domain (the camvid model in the
  /// simulator), not on CamVid's own unseen sequences (docs/learned.md, "Online adaptation").
  bool adapt = false;
  int adapt_layers = 2;           ///< the convolutions fine-tuned, counted from the logit; 1..11
  double adapt_rate = 0.01;       ///< the step's learning rate (plain gradient descent); (0, 1]
  /// What the cells outside the predicted road train as. NotRoad (default): not road, but where the
  /// network is confident of road (left out: the map may be off there) — for a prediction that is
  /// the road's whole extent, as a map's is. Confident: what the network says where it is confident,
  /// else left out — for a bootstrap that is only part of the road (eval segmentation's trapezoid,
  /// log track's lane); NotRoad would teach the rest of the road to be not road.
  AdaptOutside adapt_outside = AdaptOutside::NotRoad;
  /// Confident of road at P(road) >= this, of not road at P <= 1 - this. (0.5, 1)
  double adapt_confidence = 0.8;
  int adapt_every = 1;            ///< frames between steps (a rate limit); >= 1
  /// Back to the loaded weights when the region at P > 0.5 holds less than this share of the
  /// predicted road: the adaptation ran away (a prediction is often only part of the road: an eval's
  /// bootstrap, the near road on a map). [0, 1)
  double adapt_reset_cover = 0.5;

  /// Throws InvalidInput "LearnedPipelineOptions::FIELD = VALUE: must be ..." for a field out of range.
  void validate() const;
};

const OptionTable<LearnedPipelineOptions>& learnedPipelineOptionTable();

/// A model name or path to its file: an existing file as it is; a name ("camvid") to NAME.mnseg in
/// the installed models folder (<prefix>/share/mapnav/models, found from the running program) or
/// in the source tree's models/. Throws NotFound listing where it looked.
std::filesystem::path resolveSegmentationModel(const std::string& name_or_path);

/// Registers "learned" (once; thread-safe).
void registerLearnedPipeline();

}  // namespace mapnav
