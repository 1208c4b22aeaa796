// The cluster-perceptron's grey-frame features and the "cluster-perceptron" pipeline (the finder's
// bootstrap, training and runtime per frame of a mission). The finder itself (Jochem & Baluja 1993)
// is in cluster_perceptron_*.cpp, the options' tables in cluster_perceptron_config.cpp; see
// cluster_perceptron.h.
#include "mapnav/vision/cluster_perceptron.h"

#include "cluster_perceptron_internal.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "mapnav/core/error.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {

// --- Grey frames -----------------------------------------------------------------------------------

Image greyTextureFeatures(const std::uint8_t* rgb, int width, int height, int window) {
  if (rgb == nullptr || width <= 0 || height <= 0) throw InvalidInput("greyTextureFeatures: empty frame");
  if (window < 3 || window > 63 || window % 2 == 0)
    throw InvalidInput("greyTextureFeatures: window " + std::to_string(window) + " is not odd in [3, 63]");
  cv::Mat grey(height, width, CV_32F);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) grey.at<float>(v, u) = rgb[3 * (static_cast<std::size_t>(v) * width + u)];
  const cv::Size box(window, window);
  cv::Mat mean, mean_sq, lap, grain;
  cv::blur(grey, mean, box, cv::Point(-1, -1), cv::BORDER_REPLICATE);
  cv::blur(grey.mul(grey), mean_sq, box, cv::Point(-1, -1), cv::BORDER_REPLICATE);
  cv::Laplacian(grey, lap, CV_32F, 1, 1.0, 0.0, cv::BORDER_REPLICATE);
  cv::blur(cv::abs(lap), grain, box, cv::Point(-1, -1), cv::BORDER_REPLICATE);
  Image out(width, height, 3);
  auto level = [](double x) { return static_cast<std::uint8_t>(std::clamp(std::lround(x), 0L, 255L)); };
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const double m = mean.at<float>(v, u);
      const double sd = std::sqrt(std::max(0.0, mean_sq.at<float>(v, u) - m * m));
      std::uint8_t* p = out.pixel(u, v);
      p[0] = level(m);
      p[1] = level(4.0 * grain.at<float>(v, u));
      p[2] = level(4.0 * sd);
    }
  return out;
}

// --- The "cluster-perceptron" pipeline ----------------------------------------------------------------

namespace {

/// The centre line of a road outline mask: the middle of each row's extent, over the rows whose extent
/// does not touch the image's sides (a clipped row's middle is not the road's), fitted by a line
/// (least squares); nothing when fewer than 8 rows qualify.
std::optional<Segment2> maskCentreLine(const Image& mask) {
  std::vector<Vec2> vu;
  for (int v = 0; v < mask.height; ++v) {
    int lo = mask.width, hi = -1;
    for (int u = 0; u < mask.width; ++u)
      if (mask.pixel(u, v)[0] != 0) {
        lo = std::min(lo, u);
        hi = std::max(hi, u);
      }
    if (hi >= 0 && lo > 0 && hi < mask.width - 1) vu.emplace_back(v, 0.5 * (lo + hi));
  }
  if (vu.size() < 8) return std::nullopt;
  CentreModel line;
  line.v0 = vu.front().x();
  line.v1 = std::max(line.v0 + 1.0, vu.back().x());
  if (!fitCentreModel(vu, 1, std::numeric_limits<double>::max(), line)) return std::nullopt;
  return Segment2{Vec2(line.u(line.v0), line.v0), Vec2(line.u(line.v1), line.v1)};
}

/// The smallest distance, in normalised colour (255 (R, G, B) / (R + G + B)), between the mean colour
/// of a paved region in `prediction` and that of a surface beside one of its interest segments that
/// is not paved there; infinity when the prediction names no such pair.
double normalisedSeparation(const PredictedObject& prediction) {
  const auto normalised = [](const Vec3& rgb) { return Vec3(255.0 * rgb / std::max(1.0, rgb.sum())); };
  std::set<std::string> paved;
  for (const PredictedRegion& r : prediction.regions) paved.insert(r.surface);
  double best = std::numeric_limits<double>::infinity();
  for (const PredictedRegion& r : prediction.regions) {
    for (const InterestSegment& s : prediction.segments) {
      for (const auto& [surface, rgb] : {std::pair{&s.left_surface, &s.left_rgb}, std::pair{&s.right_surface, &s.right_rgb}}) {
        if (!paved.contains(*surface)) best = std::min(best, (normalised(*rgb) - normalised(r.rgb)).norm());
      }
    }
  }
  return best;
}

/// The arc model's centre line for the Map, which takes a detected centre line for straight: the
/// chord from the curve's nearest point on the ground (`curve` in the image, far to near) to its
/// farthest point such that the curve between them stays within `tolerance_m` of the chord. The whole
/// curve's chord (2 to 12 m ahead) is a chord of the bend, not the tangent piece the Map compares
/// with its own near chord: in R2's 15 m hairpin of park_loop it turned the estimate's heading 7-29
/// degrees off (docs/measurements.md, park loop). Nothing when under two points reach the ground.
std::optional<Segment2> nearChord(const Camera& cam, const std::vector<Vec2>& curve, double tolerance_m) {
  std::vector<Vec2> ground;
  for (auto it = curve.rbegin(); it != curve.rend(); ++it)
    if (const auto g = cam.backproject(*it)) ground.push_back(*g);
  if (ground.size() < 2) return std::nullopt;
  std::size_t far = 1;
  for (std::size_t j = 2; j < ground.size(); ++j) {
    const Segment2 chord{ground.front(), ground[j]};
    bool within = true;
    for (std::size_t k = 1; k < j && within; ++k) within = chord.distanceTo(ground[k]) <= tolerance_m;
    if (!within) break;
    far = j;
  }
  return Segment2{ground.front(), ground[far]};
}

class ClusterPerceptronPipeline : public VisionPipeline {
 public:
  ClusterPerceptronPipeline() { reset(); }
  std::string name() const override { return "cluster-perceptron"; }
  void configure(const std::string& text) override {
    opts_ = clusterPerceptronPipelineOptionTable().parse(text, opts_, "pipeline \"cluster-perceptron\"");
    reset();
  }
  void reset() override {
    street_ = false;
    trained_surfaces_.clear();
    finder_ = ClusterPerceptron(opts_);
    ground_camera_ = nullptr;
  }

  DetectedObject detect(const VisionFrame& frame, const PredictedObject& prediction) override {
    if (frame.camera == nullptr) throw InvalidInput("pipeline \"cluster-perceptron\": the frame has no camera");
    if (frame.rgb == nullptr || frame.width <= 0 || frame.height <= 0)
      throw InvalidInput("pipeline \"cluster-perceptron\": the frame has no pixels");
    if (frame.width != frame.camera->width() || frame.height != frame.camera->height())
      throw InvalidInput("pipeline \"cluster-perceptron\": frame size differs from the camera's image size");
    const Camera& cam = *frame.camera;
    const int w = frame.width, h = frame.height;
    // Grey frames: texture features in place of the colours (both runtime paths see the same image).
    Image features;
    const std::uint8_t* pixels = frame.rgb;
    if (opts_.grey_features && isGreyFrame(frame.rgb, w, h)) {
      features = greyTextureFeatures(frame.rgb, w, h, opts_.texture_window);
      pixels = features.data.data();
    }
    // The bootstrap (§4): the predicted road outline, else the default trapezoid; drawn only for a
    // training or the scoring's region, not on every frame of the loop.
    std::set<std::string> surfaces = surfacesInView(prediction);
    const bool retrain = retrainOn(h, surfaces);
    Image outline = retrain || frame.want_masks ? bootstrapOutline(prediction, cam) : Image();
    if (retrain) trainOn(pixels, frame, prediction, outline, surfaces);
    std::optional<Segment2> prior;
    if (opts_.prior_px > 0) prior = maskCentreLine(predictedRoadMask(prediction, cam));
    RoadFinding f = finder_.track(pixels, w, h, frame.want_masks, prior);
    // Beyond the paper: a frame that the model of an earlier frame fails on is trained on and tried
    // again, rather than failed (a halted vehicle sees the same frame again and again).
    if (!f.ok && !retrain && opts_.retrain_on_failure) {
      if (outline.data.empty()) outline = bootstrapOutline(prediction, cam);
      trainOn(pixels, frame, prediction, outline, surfaces);
      f = finder_.track(pixels, w, h, frame.want_masks, prior);
    }
    if (!f.ok) {
      DetectedObject d = DetectedObject::failed(f.reason);
      d.timestamp = frame.timestamp;
      return d;
    }
    DetectedObject d;
    d.timestamp = frame.timestamp;
    d.confidence = f.confidence;
    // The road region: the bootstrap trapezoid's widths around the centre line (the arc model's
    // curve), clipped to the image.
    const Segment2& cl = f.centerline_image;
    std::vector<Vec2> centre;
    if (opts_.road_model == RoadModel::Arc) {
      centre = f.centerline_curve;
    } else {
      const double v0 = cl.a.y(), v1 = cl.b.y();
      const int steps = 16;
      for (int k = 0; k <= steps; ++k) {
        const double v = v0 + (v1 - v0) * k / steps;
        const double t = (v - v0) / std::max(1e-9, v1 - v0);
        centre.emplace_back(cl.a.x() + t * (cl.b.x() - cl.a.x()), v);
      }
    }
    d.region_image = roadBand(centre, finder_.rowWidths(), w);
    // Scoring (want_masks): the perceptron's own road region. The mission loop and `log track` keep
    // the centre line's band, which they carry into the next frame's prediction: carrying the
    // perceptron's region (the verges and the next lane where they share the road's colour) let the
    // prior drift off the lane on kitti_vo_seq1 (balance_classes, prior_px 20: 45 of 51 frames on the
    // lane and 3 failed, instead of 51 and none).
    if (frame.want_masks) regionFromPerceptron(cam, f, outline, d);
    Polygon2 rv;
    for (const Vec2& p : d.region_image)
      if (const auto g = cam.backproject(p)) rv.push_back(*g);
    if (rv.size() == d.region_image.size()) d.region_vehicle = rv;
    if (opts_.road_model == RoadModel::Arc) {
      d.centerline_vehicle = nearChord(cam, f.centerline_curve, opts_.chord_tolerance_m);
      return d;
    }
    // The centre line on the ground: its far end moved down to the first row below the horizon.
    std::optional<Vec2> ga, gb = cam.backproject(cl.b);
    for (int k = 0; k <= 64 && !ga; ++k) ga = cam.backproject(cl.a + (cl.b - cl.a) * (k / 64.0));
    if (ga && gb) d.centerline_vehicle = Segment2{*ga, *gb};
    return d;
  }

 private:
  // Clusters and perceptron trained on the frame's `pixels` (its colours, or a grey frame's texture
  // features) from the bootstrap `outline`; `surfaces` (surfacesInView()) are what it was trained with.
  void trainOn(const std::uint8_t* pixels, const VisionFrame& frame, const PredictedObject& prediction,
               const Image& outline, const std::set<std::string>& surfaces) {
    const int w = frame.width, h = frame.height;
    const Camera& cam = *frame.camera;
    ClusterPerceptronOptions o = opts_;
    // Grey frames' texture features are not colours: normalised, their texture would be gone (and
    // a log would squeeze the high texture levels that part asphalt from grass), and the gate's
    // feature distance barely parts them: the classes are balanced instead.
    if (pixels != frame.rgb) {
      o.normalized_color = false;
      o.log_color = false;
      o.balance_classes = o.balance_classes || opts_.grey_balance_classes;
    } else if (o.normalized_color && normalisedSeparation(prediction) < opts_.min_normalised_separation) {
      // A shoulder the road's chromaticity (gravel beside asphalt): in log colour, which keeps brightness.
      o.normalized_color = false;
      o.log_color = true;
    }
    train(o, pixels, w, h, outline, cam);
    trained_surfaces_ = surfaces;
    // A street (the paper's bootstrap could not part the road from the rest): again in log colour.
    street_ = opts_.log_color_when_gated && finder_.nonroadGated() && pixels == frame.rgb && !o.normalized_color &&
              !o.log_color;
    if (street_) {
      o.log_color = true;
      train(o, pixels, w, h, outline, cam);
    }
  }

  // A new finder with options `o`, its clusters and perceptron trained on the frame's pixels.
  void train(const ClusterPerceptronOptions& o, const std::uint8_t* pixels, int w, int h, const Image& outline,
             const Camera& cam) {
    finder_ = ClusterPerceptron(o);
    finder_.trainClusters(pixels, w, h);
    finder_.setRowWidths(trapezoidRowWidths(outline));
    finder_.setCamera(cam);
    finder_.trainPerceptron(pixels, w, h, outline.data.data());
  }

  /// Whether to train on this frame: the first, one of another size, every one with
  /// retrain_each_frame, and the next one after a perceptron that the non-road gate trained (a model
  /// of one frame's colours, trained where the paper's bootstrap could not separate), in RGB or,
  /// on a street, in log colour (which may separate without the gate).
  /// With retrain_on_new_surface, also the first whose prediction names a surface the last
  /// training's did not (`surfaces`, surfacesInView()).
  bool retrainOn(int h, const std::set<std::string>& surfaces) const {
    const bool new_surface = opts_.retrain_on_new_surface &&
                             !std::includes(trained_surfaces_.begin(), trained_surfaces_.end(), surfaces.begin(), surfaces.end());
    return opts_.retrain_each_frame || !finder_.trained() || static_cast<int>(finder_.rowWidths().size()) != h ||
           finder_.nonroadGated() || street_ || new_surface;
  }

  /// The surfaces the prediction names: its regions' and, on either side of each interest segment,
  /// the shoulders'.
  static std::set<std::string> surfacesInView(const PredictedObject& prediction) {
    std::set<std::string> out;
    for (const PredictedRegion& r : prediction.regions) out.insert(r.surface);
    for (const InterestSegment& s : prediction.segments) {
      out.insert(s.left_surface);
      out.insert(s.right_surface);
    }
    out.erase("");
    return out;
  }

  /// The bootstrap outline of a frame (1 channel, 255 inside): the prediction's road region in the
  /// image, else (under 100 pixels of it) the default trapezoid of the options.
  Image bootstrapOutline(const PredictedObject& prediction, const Camera& cam) const {
    Image outline = predictedRoadMask(prediction, cam);
    std::size_t count = 0;
    for (std::uint8_t m : outline.data) count += m != 0;
    if (count >= 100) return outline;
    const int w = cam.width(), h = cam.height();
    const double top = opts_.trapezoid_top * h, tw = opts_.trapezoid_top_width * w, bw = opts_.trapezoid_bottom_width * w,
                 cx = (w - 1) / 2.0;
    return fillPolygonMask(
        {{Vec2(cx - tw / 2, top), Vec2(cx + tw / 2, top), Vec2(cx + bw / 2, h - 1.0), Vec2(cx - bw / 2, h - 1.0)}}, w, h);
  }

  /// The road region of the perceptron's pixels that the frame's bootstrap `outline` overlaps most,
  /// else the centre line's band (d.region_image on entry) (perceptronRegion()), replacing the band,
  /// with its mask and the per-pixel confidence. The band stays when neither holds road.
  void regionFromPerceptron(const Camera& cam, const RoadFinding& f, const Image& outline, DetectedObject& d) {
    if (ground_camera_ != &cam || ground_.width != cam.width() || ground_.height != cam.height()) {
      ground_ = groundMask(cam);
      ground_camera_ = &cam;
    }
    const Image cert = smoothCertainty(f.certainty, opts_.smooth_px);
    std::optional<PerceptronRegion> region = perceptronRegion(cert, ground_, outline);
    if (!region) region = perceptronRegion(cert, ground_, fillPolygonMask({d.region_image}, cam.width(), cam.height()));
    if (!region) return;
    d.region_image = std::move(region->outline);
    d.road_confidence = perceptronConfidence(cert, ground_, region->mask);
    d.road_mask = std::move(region->mask);
  }

  ClusterPerceptronPipelineOptions opts_;
  ClusterPerceptron finder_;
  bool street_ = false;  // the last training needed the gate in RGB and was redone in log colour
  std::set<std::string> trained_surfaces_;  ///< surfacesInView() of the last training's frame
  const Camera* ground_camera_ = nullptr;  ///< the camera ground_ was computed for
  Image ground_;                           ///< where it sees the ground (groundMask())
};

}  // namespace

std::unique_ptr<VisionPipeline> createClusterPerceptronPipeline() {
  return std::make_unique<ClusterPerceptronPipeline>();
}

}  // namespace mapnav
