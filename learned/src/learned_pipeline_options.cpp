// The learned pipeline's options' table (learned_pipeline.h). Without Torch, in mapnav_learned_options:
// every build lists and checks them (`mapnav options`), with or without the learned module.
#include "mapnav/learned/learned_pipeline.h"

namespace mapnav {

const OptionTable<LearnedPipelineOptions>& learnedPipelineOptionTable() {
  using O = LearnedPipelineOptions;
  static const OptionTable<O> table =
      OptionTable<O>("LearnedPipelineOptions")
          .field("model", &O::model,
                 "a model file (mapnav train segmentation), or a committed model's name: camvid (real streets: road "
                 "and pavement, trained on CamVid photos) or sim (the simulator's paths, trained on its logs)")
          .field("threads", &O::threads, inRange(0, 256), "Torch's CPU threads for the process; 0 = every core")
          .field("adapt", &O::adapt,
                 "online adaptation: after each frame with a prediction, one gradient step on the last adapt_layers "
                 "convolutions, the predicted road as road and the rest as adapt_outside says")
          .field("adapt_layers", &O::adapt_layers, inRange(1, 11), "the convolutions adapt fine-tunes, from the logit back")
          .field("adapt_rate", &O::adapt_rate, aboveUpTo(0, 1), "adapt's learning rate (plain gradient descent)")
          .choice("adapt_outside", &O::adapt_outside,
                  {{AdaptOutside::NotRoad, "not-road"}, {AdaptOutside::Confident, "confident"}},
                  "adapt: the cells outside the predicted road train as not road unless the network is confident of "
                  "road there (not-road: the prediction is the road's whole extent, a map's), or as the network says "
                  "where it is confident and not at all elsewhere (confident: a bootstrap that is part of the road)")
          .field("adapt_confidence", &O::adapt_confidence, OptionRule{.min = 0.5, .max = 1, .min_open = true, .max_open = true},
                 "adapt: outside the predicted road, confident of road at P >= this, of not road at P <= 1 - this")
          .field("adapt_every", &O::adapt_every, atLeast(1), "adapt: frames between steps")
          .field("adapt_reset_cover", &O::adapt_reset_cover, OptionRule{.min = 0, .max = 1, .max_open = true},
                 "adapt: back to the loaded weights when the region at P > 0.5 holds less than this share of the "
                 "predicted road")
          .include(scorePipelineOptionTable());
  return table;
}

void LearnedPipelineOptions::validate() const { learnedPipelineOptionTable().validate(*this); }

}  // namespace mapnav
