// Training a SegmentationModel (docs/learned.md).
#include "mapnav/learned/train_segmentation.h"

#include "network.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "mapnav/core/error.h"

namespace mapnav {


namespace {

/// The photos at the input size as tensors: x (N x 4 x H x W, colours in levels), label and weight
/// (N x 1 x H x W: 1 road / 0 not; 0 where left out).
struct Tensors {
  torch::Tensor x, label, weight;
};

Tensors toTensors(const std::vector<const TrainingPhoto*>& photos, int w, int h) {
  const auto n = static_cast<std::int64_t>(photos.size());
  Tensors t{torch::empty({n, 4, h, w}), torch::empty({n, 1, h, w}), torch::empty({n, 1, h, w})};
  const std::size_t plane = static_cast<std::size_t>(w) * h;
  for (std::int64_t k = 0; k < n; ++k) {
    const TrainingPhoto& p = *photos[static_cast<std::size_t>(k)];
    const cv::Mat rgb(p.rgb.height, p.rgb.width, CV_8UC3, const_cast<std::uint8_t*>(p.rgb.data.data()));
    const cv::Mat road(p.road.height, p.road.width, CV_8UC1, const_cast<std::uint8_t*>(p.road.data.data()));
    const cv::Mat ground(p.ground.height, p.ground.width, CV_8UC1, const_cast<std::uint8_t*>(p.ground.data.data()));
    cv::Mat rgb_s, road_s, ground_s;
    cv::resize(rgb, rgb_s, cv::Size(w, h), 0, 0, rgb.cols > w ? cv::INTER_AREA : cv::INTER_LINEAR);
    cv::resize(road, road_s, cv::Size(w, h), 0, 0, cv::INTER_NEAREST);
    cv::resize(ground, ground_s, cv::Size(w, h), 0, 0, cv::INTER_NEAREST);
    float* x = t.x[k].data_ptr<float>();
    float* l = t.label[k].data_ptr<float>();
    float* m = t.weight[k].data_ptr<float>();
    for (std::size_t i = 0; i < plane; ++i) {
      for (int c = 0; c < 3; ++c) x[c * plane + i] = rgb_s.data[3 * i + c];
      x[3 * plane + i] = ground_s.data[i] != 0 ? 1.0f : 0.0f;
      l[i] = road_s.data[i] == 1 ? 1.0f : 0.0f;
      m[i] = road_s.data[i] == 255 ? 0.0f : 1.0f;
    }
  }
  return t;
}

/// Colours normalised in place: (level - mean) / spread per channel.
void normalise(torch::Tensor& x, const std::vector<double>& mean, const std::vector<double>& spread) {
  for (int c = 0; c < 3; ++c) {
    auto ch = x.select(1, c);
    ch.sub_(mean[static_cast<std::size_t>(c)]).div_(spread[static_cast<std::size_t>(c)]);
  }
}

void checkPhoto(const TrainingPhoto& p) {
  if (p.rgb.channels != 3 || p.rgb.empty()) throw InvalidInput(p.name + ": expected an RGB photo");
  for (const auto& [what, img] : {std::pair{"label", &p.road}, std::pair{"ground mask", &p.ground}}) {
    if (img->channels != 1 || img->width != p.rgb.width || img->height != p.rgb.height)
      throw InvalidInput(p.name + ": the " + std::string(what) + " must be 1 channel and " + std::to_string(p.rgb.width) +
                         "x" + std::to_string(p.rgb.height));
  }
}

/// Road IoU at logit > 0 inside the ground over prepared tensors (colours already normalised).
std::optional<double> iouOf(SegNet& net, const Tensors& t) {
  torch::NoGradGuard no_grad;
  double tp = 0, fp = 0, fn = 0;
  for (std::int64_t k = 0; k < t.x.size(0); ++k) {
    const torch::Tensor x = t.x.slice(0, k, k + 1);
    const torch::Tensor road = (net.forward(x) > 0).logical_and(x.select(1, 3).unsqueeze(1) > 0.5);
    const torch::Tensor truth = t.label.slice(0, k, k + 1) > 0.5, used = t.weight.slice(0, k, k + 1) > 0.5;
    tp += (road & truth & used).sum().item<double>();
    fp += (road & ~truth & used).sum().item<double>();
    fn += (~road & truth & used).sum().item<double>();
  }
  if (tp + fp + fn == 0) return std::nullopt;
  return tp / (tp + fp + fn);
}

// The distributions of the brightness gain and the tint, as every model before the other
// augmentations was trained with (with those off, the same draws in the same order).
struct Jitter {
  std::uniform_real_distribution<double> gain{0.75, 1.25}, tint{0.94, 1.06}, unit{0, 1};
};

// Photo k of a batch (colours normalised: x = (level - mean) / spread) augmented in place, its label
// and weight with it (SegmentationTrainOptions): grey, contrast, blur and noise (on the levels; each
// drawn only when its option is on), the brightness gain and tint, zoom, flip, from `rng` (the noise
// from `noise`) in that order.
void augment(torch::Tensor& x, torch::Tensor& y, torch::Tensor& w, std::int64_t k, const std::vector<double>& mean,
             const std::vector<double>& spread, const SegmentationTrainOptions& o, std::mt19937_64& rng,
             at::Generator& noise, Jitter& jitter) {
  const bool grey = o.grey_fraction > 0 && jitter.unit(rng) < o.grey_fraction;
  const double contrast = o.contrast > 0 ? 1 + o.contrast * (2 * jitter.unit(rng) - 1) : 1;
  const bool blur = o.blur_fraction > 0 && jitter.unit(rng) < o.blur_fraction;
  const double sigma = o.noise_levels > 0 ? o.noise_levels * jitter.unit(rng) : 0;
  if (grey || contrast != 1 || blur || sigma > 0) {
    torch::Tensor levels = torch::empty({3, x.size(2), x.size(3)});
    for (int c = 0; c < 3; ++c) {
      const auto cu = static_cast<std::size_t>(c);
      levels[c] = x[k][c] * spread[cu] + mean[cu];
    }
    if (grey) {
      const torch::Tensor l = 0.299 * levels[0] + 0.587 * levels[1] + 0.114 * levels[2];
      for (int c = 0; c < 3; ++c) levels[c] = l;
    }
    if (contrast != 1) levels = (levels - levels.mean()) * contrast + levels.mean();
    if (blur) levels = torch::avg_pool2d(levels.unsqueeze(0), {3, 3}, {1, 1}, {1, 1}, false, false).squeeze(0);
    if (sigma > 0) levels += sigma * torch::randn(levels.sizes(), noise);
    for (int c = 0; c < 3; ++c) {
      const auto cu = static_cast<std::size_t>(c);
      x[k][c] = (levels[c] - mean[cu]) / spread[cu];
    }
  }
  // A brightness gain and a slight tint per photo (on the levels: x' = x g + mean / spread (g - 1)).
  const double g = jitter.gain(rng);
  for (int c = 0; c < 3; ++c) {
    const double gc = g * jitter.tint(rng);
    const auto cu = static_cast<std::size_t>(c);
    x[k][c].mul_(gc).add_(mean[cu] / spread[cu] * (gc - 1));
  }
  if (o.zoom > 1 && jitter.unit(rng) < 0.5) {
    const double z = 1 + (o.zoom - 1) * jitter.unit(rng);
    const std::int64_t h = x.size(2), wd = x.size(3);
    const auto ch = static_cast<std::int64_t>(std::lround(static_cast<double>(h) / z));
    const auto cw = static_cast<std::int64_t>(std::lround(static_cast<double>(wd) / z));
    const auto y0 = static_cast<std::int64_t>(jitter.unit(rng) * static_cast<double>(h - ch));
    const auto x0 = static_cast<std::int64_t>(jitter.unit(rng) * static_cast<double>(wd - cw));
    const auto window = [&](const torch::Tensor& t, bool nearest) {
      namespace F = torch::nn::functional;
      const torch::Tensor cut = t.slice(1, y0, y0 + ch).slice(2, x0, x0 + cw).unsqueeze(0);
      auto opts = F::InterpolateFuncOptions().size(std::vector<std::int64_t>{h, wd});
      opts = nearest ? opts.mode(torch::kNearest) : opts.mode(torch::kBilinear).align_corners(false);
      return F::interpolate(cut, opts).squeeze(0);
    };
    const torch::Tensor colours = window(x[k].slice(0, 0, 3), false), ground = window(x[k].slice(0, 3, 4), true);
    x[k] = torch::cat({colours, ground}, 0);
    y[k] = window(y[k], true);
    w[k] = window(w[k], true);
  }
  if (rng() % 2 == 1) {
    x[k] = x[k].flip({2});
    y[k] = y[k].flip({2});
    w[k] = w[k].flip({2});
  }
}

}  // namespace

SegmentationModel trainSegmentation(const std::vector<TrainingPhoto>& photos, const SegmentationTrainOptions& options,
                                    const std::function<void(const EpochReport&)>& progress, const std::string& command) {
  options.validate();
  for (const TrainingPhoto& p : photos) checkPhoto(p);
  std::vector<const TrainingPhoto*> train, held;
  // Every `every`-th photo is held apart (the last of each run of `every`); at least one of two or more.
  const int every = options.validation_fraction > 0 && photos.size() >= 2
                        ? std::min(static_cast<int>(photos.size()), std::max(2, static_cast<int>(std::lround(1 / options.validation_fraction))))
                        : 0;
  for (std::size_t i = 0; i < photos.size(); ++i)
    (every > 0 && static_cast<int>(i % every) == every - 1 ? held : train).push_back(&photos[i]);
  if (train.empty()) throw InvalidInput("train segmentation: no photo left to train on (" + std::to_string(photos.size()) + " given)");
  SegmentationModel::setThreads(options.threads);

  Tensors tr = toTensors(train, options.width, options.height);
  Tensors va = toTensors(held, options.width, options.height);
  // The normalisation: the training colours' mean and spread per channel.
  std::vector<double> mean(3), spread(3);
  for (int c = 0; c < 3; ++c) {
    const torch::Tensor ch = tr.x.select(1, c).to(torch::kFloat64);
    mean[static_cast<std::size_t>(c)] = std::round(ch.mean().item<double>() * 1e3) / 1e3;
    spread[static_cast<std::size_t>(c)] = std::round(std::max(1.0, ch.std().item<double>()) * 1e3) / 1e3;
  }
  normalise(tr.x, mean, spread);
  normalise(va.x, mean, spread);

  SegmentationModel model(options.width, options.height, options.seed, mean, spread);
  SegNet& net = *model.impl().net;
  net.train();
  torch::optim::Adam adam(net.parameters(), torch::optim::AdamOptions(options.learning_rate));
  std::mt19937_64 rng(options.seed);
  at::Generator noise = at::detail::createCPUGenerator(options.seed + 1);
  Jitter jitter;
  const auto n = static_cast<std::int64_t>(train.size());
  std::vector<std::int64_t> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  SegmentationTraining record;
  for (int epoch = 1; epoch <= options.epochs; ++epoch) {
    double lr = options.learning_rate;
    if (epoch > 0.6 * options.epochs) lr *= 0.5;
    if (epoch > 0.85 * options.epochs) lr *= 0.5;
    for (auto& group : adam.param_groups()) static_cast<torch::optim::AdamOptions&>(group.options()).lr(lr);
    std::shuffle(order.begin(), order.end(), rng);
    double loss_sum = 0;
    int steps = 0;
    for (std::int64_t b0 = 0; b0 < n; b0 += options.batch) {
      const std::int64_t b1 = std::min(n, b0 + options.batch);
      const torch::Tensor idx = torch::tensor(std::vector<std::int64_t>(order.begin() + b0, order.begin() + b1));
      torch::Tensor x = tr.x.index_select(0, idx).clone(), y = tr.label.index_select(0, idx),
                    w = tr.weight.index_select(0, idx);
      for (std::int64_t k = 0; k < b1 - b0; ++k) augment(x, y, w, k, mean, spread, options, rng, noise, jitter);
      const torch::Tensor logits = net.forward(x);
      const torch::Tensor loss = maskedLoss(logits, y, w);
      adam.zero_grad();
      loss.backward();
      adam.step();
      loss_sum += loss.item<double>();
      ++steps;
    }
    net.eval();
    EpochReport report{epoch, options.epochs, loss_sum / std::max(1, steps), held.empty() ? std::nullopt : iouOf(net, va)};
    net.train();
    record.final_loss = report.loss;
    record.validation_iou = report.validation_iou.value_or(-1);
    if (progress) progress(report);
  }
  net.eval();
  record.command = command;
  record.seed = options.seed;
  record.epochs = options.epochs;
  record.training_images = static_cast<int>(train.size());
  record.validation_images = static_cast<int>(held.size());
  model.setTraining(record);
  return model;
}

std::optional<double> segmentationIou(const SegmentationModel& model, const std::vector<TrainingPhoto>& photos) {
  double tp = 0, fp = 0, fn = 0;
  for (const TrainingPhoto& p : photos) {
    checkPhoto(p);
    const std::vector<float> prob = model.roadProbability(p.rgb.data.data(), p.rgb.width, p.rgb.height, p.ground.data.data());
    for (std::size_t i = 0; i < prob.size(); ++i) {
      if (p.road.data[i] == 255) continue;
      const bool road = prob[i] > 0.5f, truth = p.road.data[i] == 1;
      tp += road && truth;
      fp += road && !truth;
      fn += !road && truth;
    }
  }
  if (tp + fp + fn == 0) return std::nullopt;
  return tp / (tp + fp + fn);
}

}  // namespace mapnav
