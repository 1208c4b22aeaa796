#pragma once
// The network behind SegmentationModel (internal: the one place that sees Torch besides the .cpp
// files of learned/). An encoder-decoder at a quarter of the input resolution and below:
//   input (R, G, B normalised; ground 0/1), W x H
//   e1: 3x3 stride 2 -> 16, 3x3 -> 16           W/2
//   e2: 3x3 stride 2 -> 32, 3x3 -> 32           W/4
//   e3: 3x3 stride 2 -> 48, then 3x3 dilated 2, 4 and 8 with residual sums (context over ~70 % of the frame)
//   d2: up to W/4, concat e2, 3x3 -> 32
//   d1: up to W/2, concat e1, 3x3 -> 16, 1x1 -> 1 logit, up to W (bilinear)
// ReLU after every convolution but the last. About 120 000 weights.
#include <torch/torch.h>

#include <string>
#include <vector>

#include "mapnav/learned/segmentation_model.h"

namespace mapnav {

struct SegNet : torch::nn::Module {
  SegNet();
  /// Logits (N x 1 x H x W) of a batch N x 4 x H x W.
  torch::Tensor forward(const torch::Tensor& x);

  std::vector<torch::nn::Conv2d> convs;  ///< in registration order (their names: c0, c1, ...)
};

/// The binary cross-entropy of `logits` against `label` (1 road, 0 not) summed over the cells
/// `weight` counts (1 counted, 0 left out) and divided by their count (at least 1): the loss that
/// training and SegmentationModel::adapt() descend.
torch::Tensor maskedLoss(const torch::Tensor& logits, const torch::Tensor& label, const torch::Tensor& weight);

/// The name of the architecture the file records.
inline constexpr const char* kSegNetArchitecture = "encoder-decoder 16-32-48, dilations 2-4-8";

struct SegmentationModel::Impl {
  int width = 0, height = 0;
  std::vector<double> mean, spread;  ///< per colour channel, levels
  SegmentationTraining training;
  std::shared_ptr<SegNet> net;
  std::vector<torch::Tensor> adapted_from;  ///< the weights before the first adapt(), for resetAdaptation()

  /// The batch's input tensor (1 x 4 x height x width) for one frame, resized and normalised.
  torch::Tensor input(const std::uint8_t* rgb, int w, int h, const std::uint8_t* ground) const;
};

}  // namespace mapnav
