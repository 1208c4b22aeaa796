// SegmentationModel: the network, its file and its inference (docs/learned.md).
#include "network.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"

namespace mapnav {

namespace {

constexpr const char* kMagic = "mapnav-segmentation-model 1";

namespace F = torch::nn::functional;

torch::Tensor upTo(const torch::Tensor& t, std::int64_t h, std::int64_t w) {
  return F::interpolate(t, F::InterpolateFuncOptions().size(std::vector<std::int64_t>{h, w}).mode(torch::kBilinear).align_corners(false));
}

}  // namespace

torch::Tensor maskedLoss(const torch::Tensor& logits, const torch::Tensor& label, const torch::Tensor& weight) {
  return torch::binary_cross_entropy_with_logits(logits, label, weight, {}, at::Reduction::Sum) / weight.sum().clamp_min(1);
}

SegNet::SegNet() {
  using O = torch::nn::Conv2dOptions;
  const std::vector<O> specs = {
      O(4, 16, 3).stride(2).padding(1),  O(16, 16, 3).padding(1),           // e1
      O(16, 32, 3).stride(2).padding(1), O(32, 32, 3).padding(1),           // e2
      O(32, 48, 3).stride(2).padding(1),                                    // e3
      O(48, 48, 3).padding(2).dilation(2), O(48, 48, 3).padding(4).dilation(4), O(48, 48, 3).padding(8).dilation(8),
      O(48 + 32, 32, 3).padding(1),                                         // d2
      O(32 + 16, 16, 3).padding(1), O(16, 1, 1)};                           // d1, logit
  for (std::size_t i = 0; i < specs.size(); ++i)
    convs.push_back(register_module("c" + std::to_string(i), torch::nn::Conv2d(specs[i])));
}

torch::Tensor SegNet::forward(const torch::Tensor& x) {
  auto& c = convs;
  const torch::Tensor e1 = torch::relu(c[1](torch::relu(c[0](x))));
  const torch::Tensor e2 = torch::relu(c[3](torch::relu(c[2](e1))));
  torch::Tensor e3 = torch::relu(c[4](e2));
  for (int i = 5; i <= 7; ++i) e3 = e3 + torch::relu(c[static_cast<std::size_t>(i)](e3));
  torch::Tensor d = torch::relu(c[8](torch::cat({upTo(e3, e2.size(2), e2.size(3)), e2}, 1)));
  d = torch::relu(c[9](torch::cat({upTo(d, e1.size(2), e1.size(3)), e1}, 1)));
  return upTo(c[10](d), x.size(2), x.size(3));
}

torch::Tensor SegmentationModel::Impl::input(const std::uint8_t* rgb, int w, int h, const std::uint8_t* ground) const {
  const cv::Mat frame(h, w, CV_8UC3, const_cast<std::uint8_t*>(rgb));
  cv::Mat small;
  cv::resize(frame, small, cv::Size(width, height), 0, 0, w > width ? cv::INTER_AREA : cv::INTER_LINEAR);
  cv::Mat g_small;
  if (ground != nullptr) {
    const cv::Mat g(h, w, CV_8UC1, const_cast<std::uint8_t*>(ground));
    cv::resize(g, g_small, cv::Size(width, height), 0, 0, cv::INTER_NEAREST);
  }
  // Channels last (N x H x W x C in memory): oneDNN's own layout, so that no convolution reorders
  // its input and output (about 2x faster on one thread than the planar layout, the same sums).
  torch::Tensor t = torch::empty({1, 4, height, width}, torch::TensorOptions().memory_format(torch::MemoryFormat::ChannelsLast));
  float* out = t.data_ptr<float>();
  const std::size_t pixels = static_cast<std::size_t>(width) * height;
  float scale[3], offset[3];
  for (int k = 0; k < 3; ++k) {
    scale[k] = static_cast<float>(1.0 / spread[static_cast<std::size_t>(k)]);
    offset[k] = static_cast<float>(mean[static_cast<std::size_t>(k)]);
  }
  for (std::size_t i = 0; i < pixels; ++i) {
    const std::uint8_t* p = small.data + 3 * i;
    float* o = out + 4 * i;
    for (int k = 0; k < 3; ++k) o[k] = (static_cast<float>(p[k]) - offset[k]) * scale[k];
    o[3] = ground == nullptr || g_small.data[i] != 0 ? 1.0f : 0.0f;
  }
  return t;
}

SegmentationModel::SegmentationModel(int width, int height, std::uint64_t seed, const std::vector<double>& mean,
                                     const std::vector<double>& spread) {
  if (width < 8 || height < 8 || width > 4096 || height > 4096)
    throw InvalidInput("SegmentationModel: input size " + std::to_string(width) + "x" + std::to_string(height) +
                       ": must be 8..4096 a side");
  if (mean.size() != 3 || spread.size() != 3)
    throw InvalidInput("SegmentationModel: mean and spread need one value per colour channel");
  for (double s : spread)
    if (!(s > 0) || !std::isfinite(s)) throw InvalidInput("SegmentationModel: a colour spread must be > 0");
  torch::manual_seed(seed);
  impl_ = std::make_unique<Impl>();
  impl_->width = width;
  impl_->height = height;
  impl_->mean = mean;
  impl_->spread = spread;
  impl_->net = std::make_shared<SegNet>();
  impl_->net->eval();
}

SegmentationModel::SegmentationModel(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SegmentationModel::SegmentationModel(SegmentationModel&&) noexcept = default;
SegmentationModel& SegmentationModel::operator=(SegmentationModel&&) noexcept = default;
SegmentationModel::~SegmentationModel() = default;

int SegmentationModel::inputWidth() const { return impl_->width; }
int SegmentationModel::inputHeight() const { return impl_->height; }
const SegmentationTraining& SegmentationModel::training() const { return impl_->training; }
void SegmentationModel::setTraining(SegmentationTraining training) { impl_->training = std::move(training); }

std::size_t SegmentationModel::parameterCount() const {
  std::size_t n = 0;
  for (const auto& p : impl_->net->parameters()) n += static_cast<std::size_t>(p.numel());
  return n;
}

void SegmentationModel::setThreads(int threads) {
  if (threads > 0) torch::set_num_threads(threads);
}

std::string SegmentationModel::bytes() const {
  nlohmann::ordered_json meta;
  meta["architecture"] = kSegNetArchitecture;
  meta["input"] = {{"width", impl_->width}, {"height", impl_->height}, {"channels", {"r", "g", "b", "ground"}}};
  meta["normalisation"] = {{"mean", impl_->mean}, {"spread", impl_->spread}};
  const SegmentationTraining& t = impl_->training;
  meta["training"] = {{"command", t.command},
                      {"seed", t.seed},
                      {"epochs", t.epochs},
                      {"training_images", t.training_images},
                      {"validation_images", t.validation_images},
                      {"final_loss", std::round(t.final_loss * 1e6) / 1e6},
                      {"validation_iou", t.validation_iou < 0 ? nlohmann::ordered_json(nullptr)
                                                              : nlohmann::ordered_json(std::round(t.validation_iou * 1e4) / 1e4)}};
  nlohmann::ordered_json params = nlohmann::ordered_json::array();
  std::string blob;
  for (const auto& item : impl_->net->named_parameters()) {
    const torch::Tensor& p = item.value();
    nlohmann::ordered_json entry;
    entry["name"] = item.key();
    entry["shape"] = p.sizes().vec();
    params.push_back(entry);
    const torch::Tensor c = p.detach().contiguous().to(torch::kFloat32);
    blob.append(reinterpret_cast<const char*>(c.data_ptr<float>()), static_cast<std::size_t>(c.numel()) * sizeof(float));
  }
  meta["parameters"] = params;
  static_assert(std::endian::native == std::endian::little, "model files are little-endian");
  return std::string(kMagic) + "\n" + meta.dump() + "\n" + blob;
}

void SegmentationModel::save(const std::filesystem::path& path) const { writeFileAtomic(path, bytes()); }

SegmentationModel SegmentationModel::load(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path.string() + ": cannot open the model file");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  const auto bad = [&](const std::string& why) { return InvalidInput(path.string() + ": " + why); };
  const std::size_t magic_end = text.find('\n');
  if (magic_end == std::string::npos || text.compare(0, magic_end, kMagic) != 0)
    throw bad("not a mapnav segmentation model (the first line is not \"" + std::string(kMagic) + "\")");
  const std::size_t json_end = text.find('\n', magic_end + 1);
  if (json_end == std::string::npos) throw bad("truncated: no end to the JSON header");
  nlohmann::json meta;
  try {
    meta = nlohmann::json::parse(text.substr(magic_end + 1, json_end - magic_end - 1));
  } catch (const nlohmann::json::exception& e) {
    throw bad(std::string("the JSON header: ") + e.what());
  }
  auto impl = std::make_unique<Impl>();
  try {
    if (meta.at("architecture").get<std::string>() != kSegNetArchitecture)
      throw bad("/architecture: \"" + meta.at("architecture").get<std::string>() + "\" is not \"" + kSegNetArchitecture + "\"");
    impl->width = meta.at("input").at("width").get<int>();
    impl->height = meta.at("input").at("height").get<int>();
    impl->mean = meta.at("normalisation").at("mean").get<std::vector<double>>();
    impl->spread = meta.at("normalisation").at("spread").get<std::vector<double>>();
    const auto& t = meta.at("training");
    impl->training.command = t.at("command").get<std::string>();
    impl->training.seed = t.at("seed").get<std::uint64_t>();
    impl->training.epochs = t.at("epochs").get<int>();
    impl->training.training_images = t.at("training_images").get<int>();
    impl->training.validation_images = t.at("validation_images").get<int>();
    impl->training.final_loss = t.at("final_loss").get<double>();
    impl->training.validation_iou = t.at("validation_iou").is_null() ? -1 : t.at("validation_iou").get<double>();
  } catch (const nlohmann::json::exception& e) {
    throw bad(std::string("the JSON header: ") + e.what());
  }
  if (impl->width < 8 || impl->height < 8 || impl->width > 4096 || impl->height > 4096)
    throw bad("/input: size " + std::to_string(impl->width) + "x" + std::to_string(impl->height) + " is not 8..4096 a side");
  if (impl->mean.size() != 3 || impl->spread.size() != 3 ||
      std::any_of(impl->spread.begin(), impl->spread.end(), [](double s) { return !(s > 0) || !std::isfinite(s); }))
    throw bad("/normalisation: three means and three positive spreads expected");
  impl->net = std::make_shared<SegNet>();
  impl->net->eval();
  const auto& listed = meta.at("parameters");
  const auto named = impl->net->named_parameters();
  if (!listed.is_array() || listed.size() != named.size())
    throw bad("/parameters: " + std::to_string(listed.is_array() ? listed.size() : 0) + " listed, the network has " +
              std::to_string(named.size()));
  std::size_t at = json_end + 1, i = 0;
  torch::NoGradGuard no_grad;
  for (const auto& item : named) {
    const std::string& name = item.key();
    torch::Tensor p = item.value();
    const std::string pointer = "/parameters/" + std::to_string(i);
    if (listed[i].value("name", std::string()) != name) throw bad(pointer + "/name: expected \"" + name + "\"");
    if (listed[i].value("shape", std::vector<std::int64_t>()) != p.sizes().vec()) throw bad(pointer + "/shape: not " + name + "'s shape");
    const std::size_t n = static_cast<std::size_t>(p.numel()) * sizeof(float);
    if (text.size() < at + n) throw bad("truncated: the weights end inside " + name);
    std::memcpy(p.data_ptr<float>(), text.data() + at, n);
    at += n;
    ++i;
  }
  if (at != text.size()) throw bad(std::to_string(text.size() - at) + " bytes after the last weight");
  for (auto& p : impl->net->parameters()) {
    if (!torch::isfinite(p).all().item<bool>()) throw bad("a weight is not finite");
    // The kernels in the layout of the frames' activations (input()): no reorder per call.
    if (p.dim() == 4) p.set_data(p.contiguous(torch::MemoryFormat::ChannelsLast));
  }
  return SegmentationModel(std::move(impl));
}

std::vector<float> SegmentationModel::roadProbability(const std::uint8_t* rgb, int width, int height,
                                                      const std::uint8_t* ground) const {
  if (rgb == nullptr || width <= 0 || height <= 0) throw InvalidInput("SegmentationModel: empty frame");
  torch::NoGradGuard no_grad;
  const torch::Tensor p = torch::sigmoid(impl_->net->forward(impl_->input(rgb, width, height, ground))).contiguous();
  const cv::Mat small(impl_->height, impl_->width, CV_32FC1, p.data_ptr<float>());
  std::vector<float> out(static_cast<std::size_t>(width) * height);
  cv::Mat full(height, width, CV_32FC1, out.data());
  cv::resize(small, full, full.size(), 0, 0, cv::INTER_LINEAR);
  if (ground != nullptr)
    for (std::size_t i = 0; i < out.size(); ++i)
      if (ground[i] == 0) out[i] = 0;
  return out;
}

double SegmentationModel::adapt(const std::uint8_t* rgb, int width, int height, const std::uint8_t* ground,
                                const std::uint8_t* labels, double learning_rate, int layers) {
  if (rgb == nullptr || labels == nullptr || width <= 0 || height <= 0) throw InvalidInput("SegmentationModel::adapt: empty frame");
  std::vector<torch::nn::Conv2d>& convs = impl_->net->convs;
  if (layers < 1 || layers > static_cast<int>(convs.size()))
    throw InvalidInput("SegmentationModel::adapt: layers " + std::to_string(layers) + ": must be 1.." + std::to_string(convs.size()));
  if (!(std::isfinite(learning_rate) && learning_rate > 0))
    throw InvalidInput("SegmentationModel::adapt: learning rate " + std::to_string(learning_rate) + ": must be > 0");
  // The labels at the network's input size (nearest, as the ground is).
  const cv::Mat full(height, width, CV_8UC1, const_cast<std::uint8_t*>(labels));
  cv::Mat small;
  cv::resize(full, small, cv::Size(impl_->width, impl_->height), 0, 0, cv::INTER_NEAREST);
  torch::Tensor target = torch::empty({1, 1, impl_->height, impl_->width});
  torch::Tensor weight = torch::empty({1, 1, impl_->height, impl_->width});
  float *t = target.data_ptr<float>(), *w = weight.data_ptr<float>();
  double labelled = 0;
  for (int i = 0; i < small.rows * small.cols; ++i) {
    const std::uint8_t l = small.data[i];
    t[i] = l == 1 ? 1.0f : 0.0f;
    w[i] = l <= 1 ? 1.0f : 0.0f;
    labelled += w[i];
  }
  if (labelled == 0) return -1;
  if (impl_->adapted_from.empty()) {
    for (const torch::Tensor& p : impl_->net->parameters()) impl_->adapted_from.push_back(p.detach().clone());
  }
  const std::size_t first = convs.size() - static_cast<std::size_t>(layers);
  std::vector<torch::Tensor> trained;
  for (std::size_t i = 0; i < convs.size(); ++i) {
    for (torch::Tensor& p : convs[i]->parameters()) {
      p.set_requires_grad(i >= first);
      if (i >= first) trained.push_back(p);
    }
  }
  const torch::Tensor logits = impl_->net->forward(impl_->input(rgb, width, height, ground));
  const torch::Tensor loss = maskedLoss(logits, target, weight);
  for (torch::Tensor& p : trained) p.mutable_grad() = torch::Tensor();
  loss.backward();
  {
    torch::NoGradGuard no_grad;
    for (torch::Tensor& p : trained) p.sub_(p.grad() * learning_rate);
  }
  for (torch::Tensor& p : impl_->net->parameters()) p.set_requires_grad(true);
  return loss.item<double>();
}

void SegmentationModel::resetAdaptation() {
  if (impl_->adapted_from.empty()) return;
  torch::NoGradGuard no_grad;
  std::vector<torch::Tensor> params = impl_->net->parameters();
  for (std::size_t i = 0; i < params.size(); ++i) params[i].copy_(impl_->adapted_from[i]);
}

}  // namespace mapnav
