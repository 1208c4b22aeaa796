#include "mapnav/vision/segmentation_eval.h"

#include <algorithm>
#include <array>
#include <string>

#include <opencv2/imgproc.hpp>

#include "mapnav/core/error.h"

namespace mapnav {

namespace {

// 0 non-road, 1 road, 2 ignored, for each label value.
using ClassTable = std::array<std::uint8_t, 256>;

ClassTable table(const LabelClasses& classes) {
  classes.validate();
  ClassTable t{};
  for (int v : classes.road) t[static_cast<std::size_t>(v)] = 1;
  for (int v : classes.ignore) t[static_cast<std::size_t>(v)] = 2;
  return t;
}

void checkPair(const Image& a, const char* a_name, const Image& label) {
  if (a.channels != 1) throw InvalidInput(std::string(a_name) + ": expected a 1-channel image");
  if (label.channels != 1) throw InvalidInput("label: expected a 1-channel image of class indices");
  if (a.width != label.width || a.height != label.height)
    throw InvalidInput(std::string(a_name) + " is " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                       " but the label is " + std::to_string(label.width) + "x" + std::to_string(label.height));
}

std::optional<double> ratio(std::uint64_t num, std::uint64_t den) {
  if (den == 0) return std::nullopt;
  return static_cast<double>(num) / static_cast<double>(den);
}

// Calls f(i) for each scored pixel index: every pixel, or the samples (checked against the image).
template <typename F>
void forEachSample(const Image& label, const PixelSamples* samples, F&& f) {
  if (samples == nullptr) {
    for (std::size_t i = 0; i < label.data.size(); ++i) f(i);
    return;
  }
  for (const std::uint32_t i : *samples) {
    if (i >= label.data.size())
      throw InvalidInput("samples: pixel index " + std::to_string(i) + " is outside the " + std::to_string(label.width) +
                         "x" + std::to_string(label.height) + " image");
    f(static_cast<std::size_t>(i));
  }
}

void checkValues(const std::vector<int>& values, const char* field) {
  for (int v : values)
    if (v < 0 || v > 255) throw InvalidInput(std::string(field) + ": label value " + std::to_string(v) + " is outside 0..255");
}

}  // namespace

void LabelClasses::validate() const {
  if (road.empty()) throw InvalidInput("road: at least one label value must be road");
  checkValues(road, "road");
  checkValues(ignore, "ignore");
  for (int v : road)
    if (std::find(ignore.begin(), ignore.end(), v) != ignore.end())
      throw InvalidInput("ignore: label value " + std::to_string(v) + " is also a road value");
}

PixelCounts& PixelCounts::operator+=(const PixelCounts& o) {
  tp += o.tp;
  fp += o.fp;
  fn += o.fn;
  tn += o.tn;
  return *this;
}
std::optional<double> PixelCounts::iou() const { return ratio(tp, tp + fp + fn); }
std::optional<double> PixelCounts::precision() const { return ratio(tp, tp + fp); }
std::optional<double> PixelCounts::recall() const { return ratio(tp, tp + fn); }

PixelCounts countPixels(const Image& predicted, const Image& label, const LabelClasses& classes,
                        const PixelSamples* samples) {
  checkPair(predicted, "prediction", label);
  const ClassTable t = table(classes);
  PixelCounts c;
  forEachSample(label, samples, [&](std::size_t i) {
    const std::uint8_t truth = t[label.data[i]];
    if (truth == 2) return;
    const bool road = predicted.data[i] != 0;
    if (truth == 1) {
      (road ? c.tp : c.fn) += 1;
    } else {
      (road ? c.fp : c.tn) += 1;
    }
  });
  return c;
}

void ScoreHistogram::add(const Image& score, const Image& label, const LabelClasses& classes,
                         const PixelSamples* samples) {
  checkPair(score, "score", label);
  const ClassTable t = table(classes);
  forEachSample(label, samples, [&](std::size_t i) {
    const std::uint8_t truth = t[label.data[i]];
    if (truth == 1) ++road[score.data[i]];
    if (truth == 0) ++non_road[score.data[i]];
  });
}

PixelCounts ScoreHistogram::at(int t) const {
  PixelCounts c;
  for (int s = 0; s < 256; ++s) {
    if (s >= t) {
      c.tp += road[static_cast<std::size_t>(s)];
      c.fp += non_road[static_cast<std::size_t>(s)];
    } else {
      c.fn += road[static_cast<std::size_t>(s)];
      c.tn += non_road[static_cast<std::size_t>(s)];
    }
  }
  return c;
}

std::optional<double> ScoreHistogram::maxF() const {
  if (at(0).tp == 0) return std::nullopt;
  double best = 0;
  for (int t = 1; t < 256; ++t) {
    const PixelCounts c = at(t);
    if (c.tp == 0) continue;
    const double p = *c.precision(), r = *c.recall();
    best = std::max(best, 2 * p * r / (p + r));
  }
  return best;
}

std::optional<double> ScoreHistogram::averagePrecision() const {
  if (at(0).tp == 0) return std::nullopt;
  std::vector<std::pair<double, double>> pr;  // (recall, precision) at each threshold predicting something
  for (int t = 1; t < 256; ++t) {
    const PixelCounts c = at(t);
    if (c.tp + c.fp > 0) pr.emplace_back(*c.recall(), *c.precision());
  }
  double sum = 0;
  for (int k = 0; k <= 10; ++k) {
    const double level = k / 10.0;
    double best = 0;
    for (const auto& [r, p] : pr)
      if (r >= level - 1e-12) best = std::max(best, p);
    sum += best;
  }
  return sum / 11.0;
}

SegmentationScores summarize(const std::vector<PixelCounts>& per_image, const ScoreHistogram* scores) {
  SegmentationScores s;
  s.images = static_cast<int>(per_image.size());
  std::vector<double> ious;
  for (const PixelCounts& c : per_image) {
    s.total += c;
    if (const auto i = c.iou()) ious.push_back(*i);
  }
  s.iou = s.total.iou();
  s.precision = s.total.precision();
  s.recall = s.total.recall();
  if (!ious.empty()) {
    std::sort(ious.begin(), ious.end());
    const std::size_t n = ious.size();
    s.iou_median = n % 2 == 1 ? ious[n / 2] : (ious[n / 2 - 1] + ious[n / 2]) / 2;
    s.iou_worst = ious.front();
  }
  if (scores != nullptr) {
    s.maxf = scores->maxF();
    s.ap = scores->averagePrecision();
  }
  return s;
}

Image drawSegmentationOverlay(const Image& photo, const Image& predicted, const Image& label,
                              const LabelClasses& classes) {
  checkPair(predicted, "prediction", label);
  if (photo.channels != 3 || photo.width != label.width || photo.height != label.height)
    throw InvalidInput("photo: expected an RGB image the size of the label");
  const ClassTable t = table(classes);
  static constexpr std::uint8_t kTp[3] = {0, 220, 0}, kFp[3] = {255, 0, 0}, kFn[3] = {0, 80, 255};
  Image out = photo;
  for (std::size_t i = 0; i < label.data.size(); ++i) {
    std::uint8_t* p = out.data.data() + 3 * i;
    const std::uint8_t truth = t[label.data[i]];
    if (truth == 2) {
      for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>(p[k] / 3);
      continue;
    }
    const bool road = predicted.data[i] != 0;
    const std::uint8_t* colour = truth == 1 ? (road ? kTp : kFn) : (road ? kFp : nullptr);
    if (colour == nullptr) continue;
    for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>((p[k] + colour[k]) / 2);
  }
  return out;
}

const OptionTable<TrapezoidOptions>& trapezoidOptionTable() {
  using O = TrapezoidOptions;
  static const OptionTable<O> table =
      OptionTable<O>("TrapezoidOptions")
          .field("bottom_width", &O::bottom_width, aboveUpTo(0, 1),
                 "the bottom edge's width, fraction of the image width")
          .field("top_width", &O::top_width, aboveUpTo(0, 1), "the top edge's width, fraction of the image width")
          .field("top", &O::top, inRange(0, 1), "the top edge's row, fraction of the image height from the top")
          .field("bottom", &O::bottom, aboveUpTo(0, 1),
                 "the bottom edge's row, fraction of the image height from the top")
          .check("top_width", [](const O& o) { return o.top_width <= o.bottom_width; }, "<= bottom_width")
          .check("top", [](const O& o) { return o.top < o.bottom; }, "< bottom");
  return table;
}

void TrapezoidOptions::validate() const { trapezoidOptionTable().validate(*this); }

Polygon2 bottomTrapezoid(int width, int height, const TrapezoidOptions& o) {
  o.validate();
  const double w = width, h = height, cx = w / 2;
  return {Vec2(cx - o.bottom_width * w / 2, o.bottom * h), Vec2(cx + o.bottom_width * w / 2, o.bottom * h),
          Vec2(cx + o.top_width * w / 2, o.top * h), Vec2(cx - o.top_width * w / 2, o.top * h)};
}

Polygon2 largestRegionOutline(const Image& mask) {
  if (mask.channels != 1) throw InvalidInput("mask: expected a 1-channel image");
  if (mask.empty()) return {};
  cv::Mat m(mask.height, mask.width, CV_8UC1, const_cast<std::uint8_t*>(mask.data.data()));
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(m.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  if (contours.empty()) return {};
  std::size_t pick = 0;
  double best = -1;
  for (std::size_t i = 0; i < contours.size(); ++i) {
    // Area of the pixels the outline encloses, boundary included: contourArea misses a thin strip.
    const double area = cv::contourArea(contours[i]) + static_cast<double>(contours[i].size());
    if (area > best) best = area, pick = i;
  }
  Polygon2 out;
  for (const cv::Point& p : contours[pick]) out.emplace_back(p.x, p.y);
  return out;
}

Image roadMask(const Image& label, const LabelClasses& classes) {
  if (label.channels != 1) throw InvalidInput("label: expected a 1-channel image of class indices");
  const ClassTable t = table(classes);
  Image out(label.width, label.height, 1);
  for (std::size_t i = 0; i < label.data.size(); ++i) out.data[i] = t[label.data[i]] == 1 ? 255 : 0;
  return out;
}

std::unique_ptr<Camera> assumedPhotoCamera(int width, int height) {
  CameraIntrinsics in;
  in.width = width;
  in.height = height;
  in.fx = in.fy = 0.9 * width;
  in.cx = (width - 1) / 2.0;
  in.cy = (height - 1) / 2.0;
  CameraMount mount;
  mount.height_m = 1.3;
  mount.tilt_rad = 0.0;
  return createCamera(LensModel::Pinhole, in, mount);
}

}  // namespace mapnav
