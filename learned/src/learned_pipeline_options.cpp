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
          .include(scorePipelineOptionTable());
  return table;
}

void LearnedPipelineOptions::validate() const { learnedPipelineOptionTable().validate(*this); }

}  // namespace mapnav
