// The built-in pipelines: "sidewalk" (normalised rg), "color-rgb" and "blue-band".
#include "mapnav/vision/pipelines.h"

#include "binary_morph.h"
#include "cv_view.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <optional>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "mapnav/core/error.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/vision/centre_line.h"
#include "mapnav/vision/cluster_perceptron.h"  // cluster-perceptron
#include "mapnav/vision/color_classifier.h"
#include "mapnav/vision/edge_tracker.h"  // edge-tracker
#include "mapnav/vision/ground_step.h"
#include "mapnav/vision/landmarks.h"
#include "mapnav/vision/line_labelling.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision/region.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {

namespace {

// --- Frame geometry ---------------------------------------------------------------------------------

using cvview::view;

/// A length in pixels on a grid of `scale`-pixel cells (at least `least`).
int onGrid(double px, int scale, int least = 0) { return std::max(least, static_cast<int>(std::lround(px / scale))); }

/// A point on the grid of `scale`-pixel cells to image pixels: cell (0, 0) covers pixels 0..scale-1.
Vec2 gridToPixel(const Vec2& p, int scale) { return scale * p + Vec2::Constant(0.5 * (scale - 1)); }

/// A region's outline traced through its boundary cells' centres (a closed ring on the grid of
/// `scale`-pixel cells, no repeat) to image pixels, where tracing through the boundary pixels' centres
/// would put it: a cell's centre lies (scale - 1) / 2 pixels inside its outermost pixel along an axis,
/// so an edge of unit normal n moves out by (scale - 1) / 2 * max(|n.x|, |n.y|) (the spacing of the
/// lattice rows along n). Each vertex goes where its two edges, so moved, meet.
std::vector<Vec2> outlineToPixels(const std::vector<Vec2>& ring, int scale) {
  std::vector<Vec2> out(ring.size());
  for (std::size_t i = 0; i < ring.size(); ++i) out[i] = gridToPixel(ring[i], scale);
  const std::size_t n = ring.size();
  if (scale == 1 || n < 3) return out;
  double area2 = 0;  // twice the signed area: > 0 counter-clockwise in (u, v)
  for (std::size_t i = 0; i < n; ++i) area2 += ring[i].x() * ring[(i + 1) % n].y() - ring[(i + 1) % n].x() * ring[i].y();
  const double side = area2 > 0 ? 1.0 : -1.0;
  const double half = 0.5 * (scale - 1);
  // Edge i runs from vertex i to vertex i + 1; its outward normal and shift.
  std::vector<Vec2> normal(n);
  std::vector<double> shift(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 d = ring[(i + 1) % n] - ring[i];
    const double len = d.norm();
    normal[i] = len > 0 ? Vec2(Vec2(side * d.y(), -side * d.x()) / len) : Vec2(Vec2::Zero());
    shift[i] = half * normal[i].cwiseAbs().maxCoeff();
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t e = (i + n - 1) % n;  // the edge into vertex i, then edge i out of it
    const Vec2 a = normal[e], b = normal[i];
    const double det = a.x() * b.y() - a.y() * b.x();
    Vec2 v;
    if (std::abs(det) > 0.25) {  // v . a = shift[e], v . b = shift[i]
      v = Vec2(shift[e] * b.y() - shift[i] * a.y(), a.x() * shift[i] - b.x() * shift[e]) / det;
    } else {  // nearly straight on (or a spike): along the mean normal
      const Vec2 m = a + b;
      v = m.norm() > 1e-9 ? Vec2(0.5 * (shift[e] + shift[i]) * m.normalized()) : Vec2(Vec2::Zero());
    }
    if (v.norm() > 2 * half) v *= 2 * half / v.norm();
    out[i] += v;
  }
  return out;
}

/// The ring (vehicle frame) in the image, on the grid of `scale`-pixel cells: edges densified so that
/// curved lenses bend them.
std::vector<cv::Point> projectRing(const Polygon2& ring, const Camera& camera, int scale) {
  std::vector<cv::Point> out;
  const double shift = 0.5 * (scale - 1);
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Vec2 a = ring[i], b = ring[(i + 1) % ring.size()];
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / 0.05)));
    for (int k = 0; k < steps; ++k) {
      const auto p = camera.projectGround(a + (b - a) * (static_cast<double>(k) / steps));
      if (p)
        out.emplace_back(cvRound(std::clamp((p->x() - shift) / scale, -1e5, 1e5)),
                         cvRound(std::clamp((p->y() - shift) / scale, -1e5, 1e5)));
    }
  }
  return out;
}

/// The rings filled on the grid of `scale`-pixel cells, w × h cells.
Image fillRings(const std::vector<Polygon2>& rings, const Camera& camera, int scale, int w, int h) {
  Image out(w, h, 1);
  cv::Mat m = view(out);
  for (const Polygon2& r : rings) {
    const auto pts = projectRing(r, camera, scale);
    if (pts.size() >= 3) cv::fillPoly(m, std::vector<std::vector<cv::Point>>{pts}, cv::Scalar(255));
  }
  return out;
}

/// Where the camera sees the ground, per pixel and per grid cell (a cell when all its pixels do).
struct GroundCache {
  const Camera* camera = nullptr;
  CameraIntrinsics intrinsics;
  CameraMount mount;
  Image valid;
  int scale = 0;
  Image grid_valid;
};

/// What the pipelines classify: the frame on the grid (its cells' mean colours) and the camera.
struct GridFrame {
  int width = 0, height = 0;   ///< cells
  const std::uint8_t* rgb = nullptr;  ///< width × height × 3
  const Camera* camera = nullptr;     ///< the full-resolution camera
  int scale = 1;                      ///< cell side, pixels
};

/// The ground cells' exposure: how many, the sum of their channels, how many saturated.
struct Exposure {
  std::uint64_t sum = 0;
  std::size_t count = 0, saturated = 0;
};

/// Exposure over the cells of `rgb` (w × h × 3) where `valid` is set; a cell is saturated when all its
/// channels are at least `sat`. Integer sums (no division per cell) with byte masks and 32-bit sums per
/// row, which the compiler vectorises; built for AVX2 too where the processor has it.
__attribute__((target_clones("avx2", "default"))) Exposure exposure(const std::uint8_t* rgb, const std::uint8_t* valid,
                                                                    int w, int h, std::uint8_t sat) {
  Exposure e;
  for (int v = 0; v < h; ++v) {
    const std::uint8_t* __restrict p = rgb + 3 * static_cast<std::size_t>(v) * w;
    const std::uint8_t* __restrict in = valid + static_cast<std::size_t>(v) * w;
    std::uint32_t sum = 0, count = 0, saturated = 0;
    for (int u = 0; u < w; ++u) {
      const std::uint8_t m = in[u] != 0 ? 0xff : 0;
      const std::uint8_t r = p[3 * u], g = p[3 * u + 1], b = p[3 * u + 2];
      sum += static_cast<std::uint32_t>(r & m) + (g & m) + (b & m);
      count += m & 1;
      saturated += (std::min(r, std::min(g, b)) >= sat) & m & 1;
    }
    e.sum += sum, e.count += count, e.saturated += saturated;
  }
  return e;
}

// --- The pipelines ---------------------------------------------------------------------------------

class BasePipeline : public VisionPipeline {
 public:
  explicit BasePipeline(std::string name) : name_(std::move(name)) {}
  std::string name() const override { return name_; }

  DetectedObject detect(const VisionFrame& frame, const PredictedObject& prediction) override {
    if (frame.camera == nullptr) throw InvalidInput("pipeline \"" + name_ + "\": the frame has no camera");
    if (frame.rgb == nullptr || frame.width <= 0 || frame.height <= 0)
      throw InvalidInput("pipeline \"" + name_ + "\": the frame has no pixels");
    if (frame.width != frame.camera->width() || frame.height != frame.camera->height())
      throw InvalidInput("pipeline \"" + name_ + "\": frame size differs from the camera's image size");
    const Camera& cam = *frame.camera;
    pixel_scale_ = pixelScale(frame.width, frame.height);
    const int scale = gridScale();
    const Image& full_valid = ground(cam, scale);
    const Image& valid = cache_.grid_valid;
    const GridFrame grid = gridFrame(frame, scale);
    const int w = grid.width, h = grid.height;

    const auto sat = static_cast<std::uint8_t>(static_cast<int>(common().saturated_level));  // 0..255
    const Exposure exposed = exposure(grid.rgb, valid.data.data(), w, h, sat);
    if (exposed.count == 0) return fail(frame, "no ground in view");
    if (static_cast<double>(exposed.sum) / 3.0 / static_cast<double>(exposed.count) < common().dark_level)
      return fail(frame, "frame too dark");
    if (static_cast<double>(exposed.saturated) / exposed.count > common().overexposed_fraction)
      return fail(frame, "frame over-exposed");

    // The prediction in the image.
    std::vector<Polygon2> road_rings;
    for (const PredictedRegion& r : prediction.regions)
      for (const Polygon2& p : r.vehicle) road_rings.push_back(p);
    Image predicted = fillRings(road_rings, cam, scale, w, h);
    cv::bitwise_and(view(predicted), view(valid), view(predicted));
    const int predicted_px = cv::countNonZero(view(predicted)) * scale * scale;
    if (predicted_px < pxCount(common().min_predicted_px)) return fail(frame, "nothing predicted in view");

    // Per-cell road decision.
    std::string why;
    want_masks_ = frame.want_masks;
    cell_confidence_ = Image();
    std::optional<Image> road = classify(grid, prediction, valid, predicted, why);
    if (!road) return fail(frame, why);

    RegionOptions ro = common().region;  // on the grid: its lengths in cells
    ro.block_size = onGrid(px(ro.block_size), scale, 1);
    ro.pixel_morph_px = onGrid(px(ro.pixel_morph_px), scale);
    ro.reference = common().reference;
    RegionResult region = reproduceRegion(*road, valid, predicted, ro);
    const double area_px = region.area_px * scale * scale;
    if (!region.found || area_px < common().min_region_fraction * predicted_px)
      return fail(frame, strprintf("no road-coloured region (the region is %.0f %% of the predicted road's area, "
                                   "under min_region_fraction %g)",
                                   100 * area_px / predicted_px, common().min_region_fraction));

    // The boundary is simplified on the grid (the tolerances divided by the cell side: the same
    // fit), its vertices mapped to pixels.
    const auto toPixels = [scale](const std::vector<Vec2>& poly) { return outlineToPixels(poly, scale); };
    DetectedObject d;
    d.timestamp = frame.timestamp;
    LineOptions lo = common().lines;
    lo.reference = common().reference;
    lo.simplify_tolerance_px = px(lo.simplify_tolerance_px);
    lo.min_length_px = px(lo.min_length_px);
    lo.frame_edge_px = px(lo.frame_edge_px);
    // Only the trace and the report read the outline (want_region).
    const ContourPolygons polys =
        contourPolygons(region.contour, lo.simplify_tolerance_px / scale,
                        frame.want_region ? std::optional(px(common().region_tolerance_px) / scale) : std::nullopt,
                        common().reference);
    if (frame.want_region) {
      d.region_image = toPixels(polys.outline);
      for (const Vec2& p : d.region_image)
        if (const auto g = cam.backproject(p)) d.region_vehicle.push_back(*g);
    }
    d.lines = polygonLines(toPixels(polys.lines), cam, full_valid, lo);
    labelLines(d.lines, prediction, lo);

    cv::Mat inter;
    cv::bitwise_and(view(region.mask), view(predicted), inter);
    const double i = cv::countNonZero(inter) * scale * scale;
    d.confidence = std::clamp(i / (area_px + predicted_px - i), 0.0, 1.0);
    if (centreLine()) d.centerline_vehicle = regionCentreLine(region.mask, predicted, cam, scale);
    if (frame.want_masks) d.road_mask = cellsToPixels(region.mask, full_valid, scale);
    if (!cell_confidence_.empty()) d.road_confidence = cellsToPixels(cell_confidence_, full_valid, scale);
    return d;
  }

 protected:
  /// Road cells of the grid (1 channel, 255 = road) or nothing with `why` set. `valid`: the cells
  /// that see the ground; `predicted`: the predicted road, on the grid.
  virtual std::optional<Image> classify(const GridFrame& grid, const PredictedObject& prediction,
                                        const Image& valid, const Image& predicted, std::string& why) = 0;

  /// The side of the grid's cells, pixels: 1 for the reference; grid_px at the frame's size (px()).
  int gridScale() const { return common().reference ? 1 : std::max(1, static_cast<int>(std::lround(px(common().grid_px)))); }

  /// A length in pixels of the options (at kReferenceFramePixels) at this frame's size, and a count
  /// of pixels (pixelScale(): smaller frames scale them down, larger ones keep them).
  double px(double length) const { return length * pixel_scale_; }
  double pxCount(double count) const { return count * pixel_scale_ * pixel_scale_; }

  /// Smooths a per-cell score (box filter of radius smooth_px) and thresholds it inside `valid`.
  /// `reach`: how far from `t` the score means "surely" one way or the other, for the confidence
  /// (kept when the frame wants it).
  Image threshold(std::vector<float>& score, int w, int h, const Image& valid, double t, double reach, int scale) {
    cv::Mat s(h, w, CV_32FC1, score.data());
    const int r = onGrid(px(common().smooth_px), scale);
    if (r > 0 && common().reference) {
      cv::blur(s, s, cv::Size(2 * r + 1, 2 * r + 1), cv::Point(-1, -1), cv::BORDER_REPLICATE);
    } else if (r > 0) {  // the same box filter as two passes of single-precision taps, ~3 times faster (to ~1e-6)
      const cv::Mat k = cv::Mat::ones(2 * r + 1, 1, CV_32F) / static_cast<float>(2 * r + 1);
      cv::sepFilter2D(s, s, CV_32F, k, k, cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
    }
    Image out(w, h, 1);
    const std::uint8_t* __restrict in = valid.data.data();
    const float* __restrict v = score.data();
    std::uint8_t* __restrict o = out.data.data();
    for (std::size_t i = 0; i < out.data.size(); ++i) o[i] = (in[i] != 0) & (v[i] > t) ? 255 : 0;
    if (want_masks_) cell_confidence_ = cellConfidence(score, valid, t, reach);
    return out;
  }

  /// The options every region pipeline has (the subclass's struct).
  virtual const RegionPipelineOptions& common() const = 0;
  virtual bool centreLine() const { return false; }  ///< the detection carries its region's centre line (regionCentreLine)
  /// Who configure()'s errors name: `pipeline "sidewalk"`.
  std::string who() const { return "pipeline \"" + name_ + "\""; }

  std::string name_;

 private:
  /// The smoothed score as 8-bit confidence per cell: t ± reach onto 0..255, above t at 129 or more
  /// (so thresholding at 129 gives back the per-cell decision), 0 where the cell sees no ground.
  static Image cellConfidence(const std::vector<float>& score, const Image& valid, double t, double reach) {
    Image out(valid.width, valid.height, 1);
    for (std::size_t i = 0; i < out.data.size(); ++i) {
      if (valid.data[i] == 0) continue;
      const double x = std::clamp((score[i] - t) / reach, -1.0, 1.0);
      out.data[i] = static_cast<std::uint8_t>(score[i] > t ? 129 + std::lround(126 * x) : std::lround(128 + 128 * x));
    }
    return out;
  }

  /// Per-cell values at full resolution: each pixel its cell's (the right and bottom pixels that fill
  /// no cell, the nearest cell's), 0 where the pixel sees no ground.
  static Image cellsToPixels(const Image& cells, const Image& full_valid, int scale) {
    Image out(full_valid.width, full_valid.height, 1);
    for (int v = 0; v < out.height; ++v) {
      const int row = std::min(v / scale, cells.height - 1);
      for (int u = 0; u < out.width; ++u) {
        if (full_valid.pixel(u, v)[0] == 0) continue;
        out.pixel(u, v)[0] = cells.pixel(std::min(u / scale, cells.width - 1), row)[0];
      }
    }
    return out;
  }

  bool want_masks_ = false;
  Image cell_confidence_;  ///< threshold()'s, when want_masks_
  double pixel_scale_ = 1;  ///< pixelScale() of the frame being detected

  DetectedObject fail(const VisionFrame& frame, const std::string& why) {
    DetectedObject d = DetectedObject::failed(why);
    d.timestamp = frame.timestamp;
    return d;
  }
  /// Where `cam` sees the ground, per pixel (returned) and per cell of the grid (cache_.grid_valid).
  const Image& ground(const Camera& cam, int scale) {
    if (cache_.camera != &cam || !(cache_.intrinsics == cam.intrinsics()) || !(cache_.mount == cam.mount()) ||
        cache_.valid.empty()) {
      cache_.camera = &cam;
      cache_.intrinsics = cam.intrinsics();
      cache_.mount = cam.mount();
      cache_.valid = groundMask(cam);
      cache_.scale = 0;
    }
    if (cache_.scale != scale) {
      cache_.scale = scale;
      if (scale == 1) {
        cache_.grid_valid = cache_.valid;
      } else {
        cv::Mat mean;
        cv::resize(view(cache_.valid)(cv::Rect(0, 0, cam.width() / scale * scale, cam.height() / scale * scale)), mean,
                   cv::Size(cam.width() / scale, cam.height() / scale), 0, 0, cv::INTER_AREA);
        cache_.grid_valid = Image(mean.cols, mean.rows, 1);
        cv::Mat all = view(cache_.grid_valid);
        cv::threshold(mean, all, 254, 255, cv::THRESH_BINARY);  // every pixel of the cell sees the ground
      }
    }
    return cache_.valid;
  }
  /// The frame on the grid: itself (scale 1), else each cell's mean colour (the right and bottom
  /// pixels that do not fill a cell are left out).
  GridFrame gridFrame(const VisionFrame& frame, int scale) {
    GridFrame g{frame.width / scale, frame.height / scale, frame.rgb, frame.camera, scale};
    if (scale == 1) return g;
    const cv::Mat full(frame.height, frame.width, CV_8UC3, const_cast<std::uint8_t*>(frame.rgb));
    grid_rgb_.resize(static_cast<std::size_t>(g.width) * g.height * 3);
    cv::Mat cells(g.height, g.width, CV_8UC3, grid_rgb_.data());
    cv::resize(full(cv::Rect(0, 0, g.width * scale, g.height * scale)), cells, cells.size(), 0, 0, cv::INTER_AREA);
    g.rgb = grid_rgb_.data();
    return g;
  }
  GroundCache cache_;
  std::vector<std::uint8_t> grid_rgb_;  ///< the last frame on the grid (reused)
};

class ClassifierPipeline : public BasePipeline {
 public:
  ClassifierPipeline(std::string name, ColorSpace space)
      : BasePipeline(std::move(name)), space_(space) {
    reset();
  }
  void configure(const std::string& options_json) override {
    options_ = colorPipelineOptionTable().parse(options_json, options_, who());
    reset();
  }
  void reset() override { classifiers_.clear(); }

 protected:
  // One road class per paved surface the prediction has in view (Wallace 1985, 3.4: several
  // classes), each against the non-road class: a brick road meeting a concrete one is road in
  // both colours, and a model learnt on one surface is not dragged onto the other. A pixel is road
  // by the best of the surfaces' log-odds.
  std::optional<Image> classify(const GridFrame& frame, const PredictedObject& prediction, const Image& valid,
                                const Image& predicted, std::string& why) override {
    const int w = frame.width, h = frame.height;
    const Camera& cam = *frame.camera;
    // Conservative labels: the predicted road eroded, and the rest of the predicted view eroded.
    Image view_mask =
        prediction.footprint.size() >= 3 ? fillRings({prediction.footprint}, cam, frame.scale, w, h) : valid;
    cv::Mat vm = view(view_mask);
    cv::bitwise_and(vm, view(valid), vm);
    Image non_lab(w, h, 1);
    const int e = onGrid(px(options_.label_erosion_px), frame.scale);
    const cv::Mat k = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * e + 1, 2 * e + 1));
    cv::Mat pm(h, w, CV_8UC1, const_cast<std::uint8_t*>(predicted.data.data()));
    const bool reference = options_.reference;
    auto erode = [&](const cv::Mat& in, cv::Mat& out) {
      if (reference) cv::erode(in, out, k, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
      else detail::erodeBinary(in, out, k);  // the same mask, a fraction of the cost
    };
    cv::Mat grown, vm_eroded;
    if (reference) cv::dilate(pm, grown, k);
    else detail::dilateBinary(pm, grown, k);
    erode(vm, vm_eroded);
    cv::bitwise_and(vm_eroded, ~grown, view(non_lab));

    std::map<std::string, std::vector<Polygon2>> by_surface;
    for (const PredictedRegion& r : prediction.regions) {
      auto& rings = by_surface[r.surface];
      rings.insert(rings.end(), r.vehicle.begin(), r.vehicle.end());
    }
    if (!options_.adaptive) reset();
    // The map's paving seen from an estimated pose (a mission) leaves less road outside it than a
    // guessed outline on a photo (an eval, no pose covariance).
    const bool mapped = !prediction.pose_covariance.isZero();
    const double gate = mapped ? options_.nonroad_gate_sigma_mapped : options_.classifier.nonroad_gate_sigma;
    std::vector<float> best;
    std::string unusable;  // why the last surface's classifier was not used
    for (const auto& [surface, rings] : by_surface) {
      // The surface's training pixels: its own predicted area, less where another surface's overlaps it.
      Image own = predicted;
      if (by_surface.size() > 1) {
        own = fillRings(rings, cam, frame.scale, w, h);
        cv::bitwise_and(view(own), pm, view(own));
        for (const auto& [other, other_rings] : by_surface) {
          if (other == surface) continue;
          Image theirs = fillRings(other_rings, cam, frame.scale, w, h);
          cv::bitwise_and(view(own), ~view(theirs), view(own));
        }
      }
      Image road_lab(w, h, 1);
      cv::Mat road_view = view(road_lab);
      erode(view(own), road_view);
      ColorClassifier& classifier = classifiers_.try_emplace(surface, classifierOptions()).first->second;
      const std::string note = train(classifier, frame, road_lab, non_lab, gate);
      if (!classifier.trained()) {
        unusable = "no colour model: " + note;
        continue;
      }
      if (classifier.separation() < options_.min_separation) {
        unusable = strprintf("road and non-road colours do not separate: Bhattacharyya distance %.2f < min_separation %g",
                             classifier.separation(), options_.min_separation);
        continue;
      }
      std::vector<float> llr = reference ? classifier.logOddsReference(frame.rgb, w, h, valid.data.data())
                                         : classifier.logOdds(frame.rgb, w, h, valid.data.data());
      if (best.empty()) best = std::move(llr);
      else for (std::size_t i = 0; i < best.size(); ++i) best[i] = std::max(best[i], llr[i]);
    }
    if (best.empty()) {
      why = "no road-coloured region (" + unusable + ")";
      return std::nullopt;
    }
    // A bound symmetric about the threshold, near enough that both classes reach it: the box filter
    // of threshold() then leaves a straight boundary where it is. With +-20, grass (far from the
    // narrow road class: -20) outweighed concrete (a few units) and moved every road/grass boundary
    // about 2 px into the road; 2 px is 15 cm on the ground for a side road's edge 10 m ahead, the
    // along-road error at campus_tour's I8 and I9. (5 localised better still, I8/I9 0.01/0.10 m
    // against 0.14/0.14 m with 8, but put grid_px 2's labelled lines up to 7 px from the reference's.)
    constexpr double kLogOddsReach = 8.0;
    const double t = options_.llr_threshold;
    const auto lo = static_cast<float>(t - kLogOddsReach), hi = static_cast<float>(t + kLogOddsReach);
    for (float& v : best) v = std::clamp(v, lo, hi);
    return threshold(best, w, h, valid, t, kLogOddsReach, frame.scale);
  }

 private:
  ColorClassifierOptions classifierOptions() const {
    ColorClassifierOptions co = options_.classifier;
    co.space = space_;
    co.stride = 1;  // train() gathers the training cells
    return co;
  }

  // Updates one surface's classifier from its labels, read at every kTrainingStride-th cell of every
  // kTrainingStride-th row (gathered first, so that the outlier test and the update touch only those);
  // adaptive: keeping only the labelled cells the current model does not strongly contradict.
  // Non-road beyond `nonroad_gate_sigma` of the road's colour. Returns the update's note (why an
  // estimate was refused).
  std::string train(ColorClassifier& classifier, const GridFrame& frame, const Image& road_lab, const Image& non_lab,
                    double nonroad_gate_sigma) {
    const int w = frame.width, h = frame.height, s = kTrainingStride;
    const int sw = (w + s - 1) / s, sh = (h + s - 1) / s;
    const std::size_t m = static_cast<std::size_t>(sw) * sh;
    sample_rgb_.resize(3 * m);
    sample_road_.resize(m);
    sample_non_.resize(m);
    std::size_t j = 0;
    for (int v = 0; v < h; v += s) {
      for (int u = 0; u < w; u += s, ++j) {
        const std::size_t i = static_cast<std::size_t>(v) * w + u;
        std::copy_n(frame.rgb + 3 * i, 3, sample_rgb_.data() + 3 * j);
        sample_road_[j] = road_lab.data[i];
        sample_non_[j] = non_lab.data[i];
      }
    }
    if (classifier.trained()) {
      const float out = static_cast<float>(options_.outlier_llr);
      const bool reference = options_.reference;
      // The fast path evaluates all labelled samples at once (vectorised; the same values as one by one).
      std::vector<float> before;
      if (!reference) {
        std::vector<std::uint8_t> labelled(m);
        for (std::size_t i = 0; i < m; ++i) labelled[i] = sample_road_[i] | sample_non_[i];
        before = classifier.logOdds(sample_rgb_.data(), sw, sh, labelled.data());
      }
      for (std::size_t i = 0; i < m; ++i) {
        if (sample_road_[i] == 0 && sample_non_[i] == 0) continue;
        const float l = reference ? classifier.logOddsReference(sample_rgb_.data() + 3 * i) : before[i];
        if (sample_road_[i] != 0 && l < -out) sample_road_[i] = 0;
        if (sample_non_[i] != 0 && l > out) sample_non_[i] = 0;
      }
    }
    return classifier.update(sample_rgb_.data(), sw, sh, sample_road_.data(), sample_non_.data(), nonroad_gate_sigma).note;
  }

  /// Training reads one cell in four (about one pixel in 16 at grid_px 2; the reference, one in four).
  static constexpr int kTrainingStride = 2;
  std::vector<std::uint8_t> sample_rgb_, sample_road_, sample_non_;  ///< the training cells (reused)
  const RegionPipelineOptions& common() const override { return options_; }

  ColorPipelineOptions options_;
  ColorSpace space_;
  std::map<std::string, ColorClassifier> classifiers_;  ///< by road surface name
};

class BlueBandPipeline : public BasePipeline {
 public:
  BlueBandPipeline() : BasePipeline("blue-band") {}
  void configure(const std::string& options_json) override {
    options_ = blueBandOptionTable().parse(options_json, options_, who());
  }
  void reset() override {}

 protected:
  // Road is on the side of the threshold where most of the predicted road is: bright in blue against
  // grass (the Warp runs), but dark against a city's pavements, walls and sky-lit windows. With
  // band_sigma, the far side is bounded too: road is no more than band_sigma of the predicted road's
  // spread beyond its median (not the dark trees and cars below a grey road, nor the bright walls
  // above it), and no nearer than the threshold on the threshold's side (a dark slab joint in a
  // bright pavement stays road).
  std::optional<Image> classify(const GridFrame& frame, const PredictedObject&, const Image& valid,
                                const Image& predicted, std::string& why) override {
    const std::size_t n = static_cast<std::size_t>(frame.width) * frame.height;
    double t = options_.threshold;
    const bool otsu = t < 0;
    std::vector<std::uint8_t> ground;  // the blue levels of the ground in view, for Otsu's threshold
    if (otsu) ground.reserve(n);
    std::array<std::size_t, 256> road{};  // the predicted road's histogram of them
    for (std::size_t i = 0; i < n; ++i) {
      if (valid.data[i] == 0) continue;
      const std::uint8_t b = frame.rgb[3 * i + 2];
      if (otsu) ground.push_back(b);
      if (predicted.data[i] != 0) ++road[b];
    }
    if (otsu && !ground.empty()) {
      cv::Mat levels(1, static_cast<int>(ground.size()), CV_8UC1, ground.data()), unused;
      t = cv::threshold(levels, unused, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
    }
    std::size_t road_px = 0, road_bright = 0;
    for (int b = 0; b < 256; ++b) road_px += road[b], road_bright += b >= t ? road[b] : 0;
    if (road_px == 0) {
      why = "no predicted road on the ground in view";
      return std::nullopt;
    }
    const bool bright = 2 * road_bright >= road_px;
    // Road from lo to hi, blue levels: b >= t on the bright side, b <= t on the dark side.
    constexpr double kOpen = std::numeric_limits<double>::infinity();
    double lo = bright ? t - 0.5 : -kOpen, hi = bright ? kOpen : t + 0.5;
    if (options_.band_sigma > 0) {
      const double median = quantile(road, road_px, 0.5);
      const double sigma = std::max(2.0, 0.5 * (quantile(road, road_px, 0.84) - quantile(road, road_px, 0.16)));
      const double half = options_.band_sigma * sigma;
      if (bright) hi = median + half, lo = std::min(lo, median - half);
      else lo = median - half, hi = std::max(hi, median + half);
    }
    std::vector<float> score(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double b = frame.rgb[3 * i + 2];
      score[i] = static_cast<float>(std::min(b - lo, hi - b));
    }
    return threshold(score, frame.width, frame.height, valid, 0.0, 128.0, frame.scale);  // blue levels
  }

 private:
  // The q-quantile of a histogram of `count` samples: the first level whose cumulative count exceeds q count.
  static double quantile(const std::array<std::size_t, 256>& hist, std::size_t count, double q) {
    std::size_t seen = 0;
    for (int b = 0; b < 256; ++b)
      if (static_cast<double>(seen += hist[b]) > q * static_cast<double>(count)) return b;
    return 255;
  }

  const RegionPipelineOptions& common() const override { return options_; }

  BlueBandOptions options_;
};

}  // namespace

// --- ScorePipeline: the region steps around a subclass's probability --------------------------------

class ScorePipeline::Impl : public BasePipeline {
 public:
  Impl(std::string name, ScorePipeline& owner) : BasePipeline(std::move(name)), owner_(owner) {}
  void configure(const std::string&) override {}
  void reset() override {}

 protected:
  std::optional<Image> classify(const GridFrame& frame, const PredictedObject&, const Image& valid, const Image& predicted,
                                std::string& why) override {
    std::vector<float> p = owner_.roadProbability(frame.rgb, frame.width, frame.height, valid.data.data());
    if (p.size() != static_cast<std::size_t>(frame.width) * frame.height) {
      why = strprintf("the road probability has %zu values for %dx%d cells", p.size(), frame.width, frame.height);
      return std::nullopt;
    }
    if (!predicted.data.empty()) owner_.learnFrom(frame.rgb, frame.width, frame.height, valid.data.data(), p, predicted.data.data());
    // The confidence maps threshold +- 0.5 onto 0..255: the probability itself where the threshold is 0.5.
    return threshold(p, frame.width, frame.height, valid, common().threshold, 0.5, frame.scale);
  }
  const ScorePipelineOptions& common() const override { return owner_.scoreOptions(); }
  bool centreLine() const override { return owner_.scoreOptions().centre_line; }

 private:
  ScorePipeline& owner_;
};

ScorePipeline::ScorePipeline(std::string name) : impl_(std::make_unique<Impl>(std::move(name), *this)) {}
ScorePipeline::~ScorePipeline() = default;
std::string ScorePipeline::name() const { return impl_->name(); }
DetectedObject ScorePipeline::detect(const VisionFrame& frame, const PredictedObject& prediction) {
  return impl_->detect(frame, prediction);
}

void registerBuiltinPipelines() {
  static std::once_flag once;
  std::call_once(once, [] {
    registerLandmarkFinder([](const VisionFrame& frame, const PredictedObject& prediction) { return findLandmarks(frame, prediction); });
    registerStepMeasurer([](const VisionFrame& previous, const VisionFrame& current, const MotionIncrement& predicted) {
      return measureGroundStep(previous, current, predicted);
    });
    registerPipeline({"blue-band",
                      "Threshold on the blue band (Wallace 1985, 3.6.3, the Warp runs): road is on the predicted road's side of "
                      "Otsu's threshold (bright against grass, dark against pavements) and within band_sigma of the predicted "
                      "road's blue level on the other side; then region reproduction and line labelling",
                      blueBandOptionTable().list(), [] { return std::make_unique<BlueBandPipeline>(); },
                      blueBandOptionTable().presets()});
    registerPipeline({"color-rgb",
                      "Gaussian road/non-road classes in log RGB (3.4; a shadow moves a colour along the grey axis), one "
                      "road class per surface in view, trained from the prediction, adaptive; region reproduction (2.2.1) and line labelling (2.2.2)",
                      colorPipelineOptionTable().list(),
                      [] { return std::make_unique<ClassifierPipeline>("color-rgb", ColorSpace::LogRGB); },
                      colorPipelineOptionTable().presets()});
    registerPipeline({"sidewalk",
                      "The default: Gaussian classes in normalised colour rg (3.4.3, robust to shadows), one road class per "
                      "surface in view, trained from the prediction, adaptive with a drift guard; region reproduction (2.2.1) and line labelling (2.2.2)",
                      colorPipelineOptionTable().list(),
                      [] { return std::make_unique<ClassifierPipeline>("sidewalk", ColorSpace::NormalizedRG); },
                      colorPipelineOptionTable().presets()});

    // --- cluster-perceptron (Jochem & Baluja 1993; vision/src/cluster_perceptron.cpp) ---
    registerPipeline({"cluster-perceptron",
                      "Park-mode road finder (Jochem & Baluja 1993): colour clusters by competitive learning, a "
                      "tanh perceptron road/non-road combiner bootstrapped from the predicted road outline in the "
                      "first frame, block road certainty and a Hough over (top-row column x angle) for the centre "
                      "line; frozen after the first frame (reset() retrains)",
                      clusterPerceptronPipelineOptionTable().list(), [] { return createClusterPerceptronPipeline(); },
                      clusterPerceptronPipelineOptionTable().presets()});
    // --- end cluster-perceptron ---

    // --- edge-tracker (Wallace 1985, 3.1-3.2; vision/src/edge_tracker.cpp) ---
    registerPipeline({"edge-tracker",
                      "Oriented step-edge tracker (3.1-3.2): traces the road's left and right edges up the image "
                      "from the predicted interest segments (or the previous frame's edges, or option start "
                      "points), checks them on the ground for parallelism and width",
                      edgeTrackerOptionTable().list(), [] { return createEdgeTrackerPipeline(); },
                      edgeTrackerOptionTable().presets()});
    // --- end edge-tracker ---
  });
}

}  // namespace mapnav
