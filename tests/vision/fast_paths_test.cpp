// The sidewalk pipeline's fast paths (for the mission loop's latency) against their reference
// implementations: binary morphology against OpenCV's, the single-precision log-odds against the
// double-precision one, the pixel-chain simplification against CGAL's, the whole pipeline with
// option "reference" on and off over a drive of rendered frames, and the edge tracker's oriented
// operator against its first, per-sample-checked form.
#include <gtest/gtest.h>

#include <iostream>
#include <numbers>
#include <random>
#include <set>

#include <Eigen/Dense>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "../../vision/src/binary_morph.h"
#include "../../vision/src/cluster_perceptron_internal.h"
#include "../../vision/src/edge_tracker_internal.h"
#include "eval_common.h"
#include "mapnav/geometry/simplify.h"
#include "mapnav/map/predict.h"
#include "mapnav/sim/world.h"
#include "mapnav/vision/cluster_perceptron.h"
#include "mapnav/vision/color_classifier.h"
#include "mapnav/vision/pipelines.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {
namespace {

// Blobs (filled ellipses and rectangles) with salt-and-pepper noise: 0 / 255.
cv::Mat randomMask(int w, int h, std::uint32_t seed, double noise) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(0, w), y(0, h), r(2, 0.3 * std::min(w, h)), a(0, 180), u(0, 1);
  cv::Mat m = cv::Mat::zeros(h, w, CV_8UC1);
  for (int i = 0; i < 6; ++i) {
    const cv::Point c(static_cast<int>(x(rng)), static_cast<int>(y(rng)));
    if (i % 2 == 0) {
      cv::ellipse(m, c, cv::Size(static_cast<int>(r(rng)), static_cast<int>(r(rng))), a(rng), 0, 360, cv::Scalar(255),
                  cv::FILLED);
    } else {
      cv::rectangle(m, cv::Rect(c.x, c.y, static_cast<int>(r(rng)), static_cast<int>(r(rng))), cv::Scalar(255), cv::FILLED);
    }
  }
  for (int v = 0; v < h; ++v)
    for (int k = 0; k < w; ++k)
      if (u(rng) < noise) m.at<std::uint8_t>(v, k) ^= 255;
  return m;
}

bool same(const cv::Mat& a, const cv::Mat& b) { return a.size() == b.size() && cv::countNonZero(a != b) == 0; }

TEST(BinaryMorph, ErodeDilateAndCloseOpenEqualOpenCvs) {
  const std::vector<cv::Mat> kernels = {
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(13, 13)),
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)),
      cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)),
      cv::getStructuringElement(cv::MORPH_RECT, cv::Size(7, 5)),
      cv::getStructuringElement(cv::MORPH_CROSS, cv::Size(5, 5)),
      (cv::Mat_<std::uint8_t>(3, 3) << 1, 1, 0, 1, 1, 0, 0, 0, 0),  // not symmetric: OpenCV's path
  };
  int cases = 0;
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    const cv::Mat m = randomMask(seed % 2 ? 97 : 40, seed % 3 ? 61 : 130, seed, seed % 2 ? 0.02 : 0.0);
    for (const cv::Mat& k : kernels) {
      cv::Mat ours, theirs;
      detail::erodeBinary(m, ours, k);
      cv::erode(m, theirs, k, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
      EXPECT_TRUE(same(ours, theirs)) << "erode, seed " << seed << ", kernel " << k;
      detail::dilateBinary(m, ours, k);
      cv::dilate(m, theirs, k);
      EXPECT_TRUE(same(ours, theirs)) << "dilate, seed " << seed << ", kernel " << k;
      cv::Mat replicated;
      cv::dilate(m, replicated, k, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
      EXPECT_TRUE(same(ours, replicated)) << "dilate (replicated border), seed " << seed << ", kernel " << k;
      ours = m.clone();
      detail::closeOpenBinary(ours, k);
      cv::morphologyEx(m, theirs, cv::MORPH_CLOSE, k, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
      cv::morphologyEx(theirs, theirs, cv::MORPH_OPEN, k, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
      EXPECT_TRUE(same(ours, theirs)) << "close-open, seed " << seed << ", kernel " << k;
      ++cases;
    }
  }
  EXPECT_EQ(cases, 36);
  // All set and all clear: unchanged by both (the shortcut), as OpenCV has it.
  const cv::Mat disk = kernels.front();
  for (const int value : {0, 255}) {
    const cv::Mat flat(30, 40, CV_8UC1, cv::Scalar(value));
    cv::Mat ours, theirs;
    detail::erodeBinary(flat, ours, disk);
    cv::erode(flat, theirs, disk, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
    EXPECT_TRUE(same(ours, theirs)) << value;
    detail::dilateBinary(flat, ours, disk);
    cv::dilate(flat, theirs, disk);
    EXPECT_TRUE(same(ours, theirs)) << value;
    EXPECT_EQ(cv::countNonZero(ours), value == 0 ? 0 : 30 * 40);
  }
  // In place, into a view of other memory, as the pipeline calls it.
  const cv::Mat m = randomMask(64, 48, 9, 0.01);
  std::vector<std::uint8_t> pixels(64 * 48);
  cv::Mat view(48, 64, CV_8UC1, pixels.data());
  m.copyTo(view);
  const cv::Mat k = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(13, 13));
  detail::erodeBinary(view, view, k);
  cv::Mat theirs;
  cv::erode(m, theirs, k, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
  EXPECT_TRUE(same(cv::Mat(48, 64, CV_8UC1, pixels.data()), theirs));
}

TEST(ColorClassifierFastPath, LogOddsAgreesWithTheDoublePrecisionReference) {
  // Concrete-grey road and green grass with noise; then every 3rd value of each channel.
  const int w = 80, h = 40;
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0, 6);
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3), road(w * h, 0), non(w * h, 0);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const bool is_road = u < w / 2;
      const double c[3] = {is_road ? 170.0 : 75.0, is_road ? 168.0 : 125.0, is_road ? 160.0 : 55.0};
      for (int k = 0; k < 3; ++k)
        rgb[(static_cast<std::size_t>(v) * w + u) * 3 + k] = static_cast<std::uint8_t>(std::clamp(c[k] + n(rng), 0.0, 255.0));
      (is_road ? road : non)[v * w + u] = 255;
    }
  }
  std::vector<std::uint8_t> cube;
  for (int r = 0; r < 256; r += 3)
    for (int g = 0; g < 256; g += 3)
      for (int b = 0; b < 256; b += 3) cube.insert(cube.end(), {std::uint8_t(r), std::uint8_t(g), std::uint8_t(b)});
  const int cube_px = static_cast<int>(cube.size() / 3);
  // rg; rg with the log brightness (a table lookup on the fast path); log RGB (three lookups).
  const ColorClassifierOptions feature_sets[] = {
      {.space = ColorSpace::NormalizedRG, .min_pixels = 50},
      {.space = ColorSpace::NormalizedRG, .min_pixels = 50, .brightness_sigma = 0.1},
      {.space = ColorSpace::LogRGB, .min_pixels = 50}};
  for (const ColorClassifierOptions& options : feature_sets) {
    const std::string name =
        options.space == ColorSpace::LogRGB ? "log RGB" : (options.brightness_sigma > 0 ? "rg+brightness" : "rg");
    ColorClassifier c(options);
    c.update(rgb.data(), w, h, road.data(), non.data());
    ASSERT_TRUE(c.trained());
    EXPECT_EQ(c.brightnessUsed(), options.brightness_sigma > 0) << name;
    for (const auto& [pixels, count] : {std::pair{&rgb, w * h}, std::pair{&cube, cube_px}}) {
      const std::vector<float> fast = c.logOdds(pixels->data(), count, 1);
      const std::vector<float> ref = c.logOddsReference(pixels->data(), count, 1);
      int sign_flips = 0;
      double worst = 0;
      for (int i = 0; i < count; ++i) {
        worst = std::max(worst, std::abs(fast[i] - ref[i]) / (1.0 + std::abs(ref[i])));
        if (std::abs(ref[i]) > 1e-3 && (fast[i] > 0) != (ref[i] > 0)) ++sign_flips;
        EXPECT_EQ(c.logOdds(pixels->data() + 3 * i), fast[i]);  // one pixel = the vectorised row
      }
      // Log RGB's features are single-precision table values (rounded by up to 8e-6 of 255) where
      // rg's come from exact integer sums; the quadratic form amplifies that where the classes cancel.
      EXPECT_LT(worst, options.space == ColorSpace::LogRGB ? 3e-4 : 1e-4) << name;
      EXPECT_EQ(sign_flips, 0) << name;
    }
    // Only where asked.
    std::vector<std::uint8_t> where(w * h, 0);
    where[7] = 1;
    const std::vector<float> some = c.logOdds(rgb.data(), w, h, where.data());
    EXPECT_EQ(std::count(some.begin(), some.end(), 0.0f), w * h - 1);
    EXPECT_NE(some[7], 0.0f);
  }
}

TEST(SimplifyPixelChain, SameVerticesAsCgalOnTracedContours) {
  int rings = 0, distinct = 0;
  for (std::uint32_t seed = 1; seed <= 12; ++seed) {
    cv::Mat m = randomMask(160, 120, 100 + seed, seed % 3 == 0 ? 0.01 : 0.0);
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(m, contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
    for (const auto& c : contours) {
      if (c.size() < 3) continue;
      std::vector<Vec2> ring;
      for (const cv::Point& p : c) ring.emplace_back(p.x, p.y);
      std::set<std::pair<int, int>> seen;
      for (const cv::Point& p : c) seen.insert({p.x, p.y});
      distinct += seen.size() == c.size();
      const std::vector<Vec2> open = ring;
      ring.push_back(ring.front());
      for (double tol : {0.75, 1.5, 3.0}) {
        EXPECT_EQ(simplifyPixelChain(ring, tol), simplifyPolyline(ring, tol)) << "seed " << seed << " tol " << tol;
        EXPECT_EQ(simplifyPixelChain(open, tol), simplifyPolyline(open, tol)) << "seed " << seed << " tol " << tol;
      }
      // Several tolerances in one pass, in any order, each CGAL's answer at it (an invalid one: the input).
      for (const std::vector<Vec2>* chain : std::initializer_list<const std::vector<Vec2>*>{&ring, &open}) {
        const std::vector<double> tols = {3.0, 0.75, -1.0, 1.5, 0.75, 12.0};
        const std::vector<std::vector<Vec2>> at = simplifyPixelChainAt(*chain, tols);
        ASSERT_EQ(at.size(), tols.size());
        for (std::size_t k = 0; k < tols.size(); ++k)
          EXPECT_EQ(at[k], tols[k] < 0 ? *chain : simplifyPolyline(*chain, tols[k])) << "seed " << seed << " tol " << tols[k];
      }
      ++rings;
    }
  }
  EXPECT_GT(rings, 40);
  EXPECT_GT(distinct, 20);  // contours the fast path takes (no pixel visited twice)
  // What it does not take goes to CGAL: a repeated point, a non-integer one, a long step.
  const std::vector<Vec2> spike = {Vec2(0, 0), Vec2(1, 0), Vec2(2, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 0)};
  const std::vector<Vec2> halves = {Vec2(0, 0), Vec2(1, 0.5), Vec2(2, 0), Vec2(3, 0.5)};
  const std::vector<Vec2> jump = {Vec2(0, 0), Vec2(5, 1), Vec2(10, 0)};
  for (const auto* p : {&spike, &halves, &jump}) {
    EXPECT_EQ(simplifyPixelChain(*p, 0.8), simplifyPolyline(*p, 0.8));
    EXPECT_EQ(simplifyPixelChainAt(*p, {0.8, 0.3}),
              (std::vector<std::vector<Vec2>>{simplifyPolyline(*p, 0.8), simplifyPolyline(*p, 0.3)}));
  }
  // A square ring of side 4: the corners stay.
  std::vector<Vec2> square;
  for (int i = 0; i < 4; ++i) square.emplace_back(i, 0);
  for (int i = 0; i < 4; ++i) square.emplace_back(4, i);
  for (int i = 4; i > 0; --i) square.emplace_back(i, 4);
  for (int i = 4; i > 0; --i) square.emplace_back(0, i);
  square.push_back(square.front());
  EXPECT_EQ(simplifyPixelChain(square, 0.5),
            (std::vector<Vec2>{Vec2(0, 0), Vec2(4, 0), Vec2(4, 4), Vec2(0, 4), Vec2(0, 0)}));
}

// Compares every answer the pipeline gives.
void expectSameDetection(const DetectedObject& a, const DetectedObject& b, std::size_t frame) {
  EXPECT_EQ(a.status, b.status) << frame;
  EXPECT_EQ(a.reason, b.reason) << frame;
  EXPECT_NEAR(a.confidence, b.confidence, 1e-12) << frame;
  EXPECT_EQ(a.region_image, b.region_image) << frame;
  ASSERT_EQ(a.lines.size(), b.lines.size()) << frame;
  for (std::size_t i = 0; i < a.lines.size(); ++i) {
    EXPECT_EQ(a.lines[i].image.a, b.lines[i].image.a) << frame;
    EXPECT_EQ(a.lines[i].image.b, b.lines[i].image.b) << frame;
    EXPECT_EQ(a.lines[i].label, b.lines[i].label) << frame;
    EXPECT_EQ(a.lines[i].frame_edge, b.lines[i].frame_edge) << frame;
    EXPECT_EQ(a.lines[i].score, b.lines[i].score) << frame;
  }
}

// Consecutive frames 0.5 m apart down R1 and on through its intersection, with shadows, so that the
// adaptive models carry over from frame to frame in both pipelines; `compare` gets both detections.
template <typename Compare>
int driveBoth(VisionPipeline& fast, VisionPipeline& reference, Compare compare) {
  WorldOptions wo;
  wo.shadow_density = 0.2;
  const World world(visiontest::campus(), wo);
  const Camera& cam = visiontest::pinhole();
  const RayTable rays(cam);
  const Road& road = visiontest::campus().roads().front();
  const Polyline2& line = road.centerline;
  int ok = 0;
  std::size_t frame = 0;
  for (double s = 1.0; s < line.length() - 1.0 && frame < 24; s += 0.5, ++frame) {
    const Vec2 t = line.tangentAt(s);
    const Pose2 pose(line.pointAt(s) + 0.1 * std::sin(s) * Vec2(-t.y(), t.x()), std::atan2(t.y(), t.x()) + 0.03 * std::cos(s));
    const Prediction pred = predictView(visiontest::campus(), pose, cam);
    if (pred.empty()) continue;
    const Frame f = world.render(rays, pose, s);
    const VisionFrame vf{f.rgb.width, f.rgb.height, f.rgb.data.data(), &cam, s};
    const DetectedObject a = fast.detect(vf, pred.view);
    const DetectedObject b = reference.detect(vf, pred.view);
    compare(a, b, frame);
    ok += a.status == DetectedObject::Status::Ok;
  }
  return ok;
}

TEST(SidewalkFastPaths, EveryPixelGivesTheReferencesDetectionsAlongADrive) {
  registerBuiltinPipelines();
  auto fast = createPipeline("sidewalk", R"({"grid_px": 1})");
  auto reference = createPipeline("sidewalk", R"({"reference": true})");
  EXPECT_GE(driveBoth(*fast, *reference, expectSameDetection), 10);
}

TEST(SidewalkFastPaths, TheReducedGridKeepsTheLabelledLinesWithinAPixelOrTwo) {
  // The default classifies 2 x 2-pixel cells: the boundary moves by up to a cell. Tolerance: every
  // line the reference labels is labelled the same, and lies within 2.5 pixels (both ends, from the
  // reference's line: a cell and the half-pixel offset of the cells' centres) and 1 degree of it in the
  // image; on the ground, within 4 cm at its middle (the missions' lateral target is 5 cm RMS).
  registerBuiltinPipelines();
  auto fast = createPipeline("sidewalk", R"({"grid_px": 2})");
  auto reference = createPipeline("sidewalk", R"({"reference": true})");
  int compared = 0;
  double worst_px = 0, worst_deg = 0, worst_m = 0;
  const auto near = [&](const DetectedObject& a, const DetectedObject& b, std::size_t frame) {
    ASSERT_EQ(a.status, b.status) << frame;
    EXPECT_NEAR(a.confidence, b.confidence, 0.02) << frame;
    for (const DetectedLine& r : b.lines) {
      if (!r.label) continue;
      const DetectedLine* best = nullptr;
      double best_px = 1e9;
      for (const DetectedLine& l : a.lines) {
        if (l.label != r.label) continue;
        const Segment2 ref_line{r.image.a, r.image.b};
        const double px = std::max(std::abs(ref_line.signedDistance(l.image.a)), std::abs(ref_line.signedDistance(l.image.b)));
        if (px < best_px) best_px = px, best = &l;
      }
      ASSERT_NE(best, nullptr) << "frame " << frame << ": no line labelled " << *r.label;
      const double deg = angleBetweenLines(best->image, r.image) * 180.0 / std::numbers::pi;
      const double m = std::abs(r.vehicle.signedDistance(0.5 * (best->vehicle.a + best->vehicle.b)));
      worst_px = std::max(worst_px, best_px), worst_deg = std::max(worst_deg, deg), worst_m = std::max(worst_m, m);
      ++compared;
    }
  };
  EXPECT_GE(driveBoth(*fast, *reference, near), 10);
  EXPECT_GE(compared, 20);
  EXPECT_LE(worst_px, 2.5);
  EXPECT_LE(worst_deg, 1.0);
  EXPECT_LE(worst_m, 0.04);
  std::cout << "reduced grid against the reference: " << compared << " labelled lines, worst " << worst_px << " px, "
            << worst_deg << " deg, " << worst_m << " m\n";
}

// The mean signed offset, outward from the road, of both ends of every labelled grid_px 2 line from
// the every-pixel (grid_px 1) line with its label, over the drive; `options`: added to both.
double gridEdgeBias(const std::string& options) {
  registerBuiltinPipelines();
  auto grid = createPipeline("sidewalk", "{\"grid_px\": 2" + options + "}");
  auto pixel = createPipeline("sidewalk", "{\"grid_px\": 1" + options + "}");
  double sum = 0;
  int ends = 0;
  const auto offset = [&](const DetectedObject& a, const DetectedObject& b, std::size_t frame) {
    ASSERT_EQ(a.status, b.status) << frame;
    if (b.region_image.empty()) return;
    Vec2 inside = Vec2::Zero();
    for (const Vec2& p : b.region_image) inside += p;
    inside /= static_cast<double>(b.region_image.size());
    for (const DetectedLine& r : b.lines) {
      if (!r.label || r.frame_edge) continue;
      const Segment2 ref_line{r.image.a, r.image.b};
      const double out = ref_line.signedDistance(inside) > 0 ? -1.0 : 1.0;  // outward from the road
      for (const DetectedLine& l : a.lines) {
        if (l.label != r.label || angleBetweenLines(l.image, r.image) > 1.0 * std::numbers::pi / 180.0) continue;
        sum += out * (ref_line.signedDistance(l.image.a) + ref_line.signedDistance(l.image.b));
        ends += 2;
      }
    }
  };
  EXPECT_GE(driveBoth(*grid, *pixel, offset), 10);
  EXPECT_GE(ends, 40);
  const double bias = ends > 0 ? sum / ends : 0.0;
  std::cout << "grid_px 2 against every pixel (" << options << "): mean outward offset of " << ends << " line ends "
            << bias << " px\n";
  return bias;
}

TEST(SidewalkFastPaths, TheReducedGridPlacesTheRoadEdgeWhereEveryPixelDoes) {
  // A cell's centre lies half a cell inside the outermost pixel it stands for, so an outline traced
  // through boundary cells' centres sits (cell - 1) / 2 pixels further inside the road than one traced
  // through boundary pixels' centres (times max(|n.x|, |n.y|) for an edge of normal n); the outline is
  // moved out by that. Without the pixel-level morphology (which acts differently on 2-pixel cells)
  // the edges then nearly agree (docs/measurements.md); bound 0.35 px (the cells' noise averages out
  // over ~100 line ends, an offset does not).
  EXPECT_LE(std::abs(gridEdgeBias(R"(, "pixel_morph_px": 0)")), 0.35);
  // With the defaults the closing and opening on 1-cell discs (a 3 x 3 cross) leave the region
  // narrower than on 2-pixel discs; bound 0.9 px.
  EXPECT_LE(std::abs(gridEdgeBias("")), 0.9);
}

TEST(SidewalkFastPaths, AFrameThatWantsNoRegionGetsTheSameLinesWithoutTheOutline) {
  // The mission loop writes no trace: it asks for no region outline, and the lines and confidence
  // (what localisation uses) are those of a run that does.
  registerBuiltinPipelines();
  const World world(visiontest::campus(), WorldOptions{});
  const Camera& cam = visiontest::pinhole();
  const RayTable rays(cam);
  const Polyline2& line = visiontest::campus().roads().front().centerline;
  for (const std::string grid : {"1", "2"}) {
    auto with = createPipeline("sidewalk", "{\"grid_px\": " + grid + "}");
    auto without = createPipeline("sidewalk", "{\"grid_px\": " + grid + "}");
    int ok = 0;
    for (double s = 1.0; s < 6.0; s += 1.0) {
      const Pose2 pose(line.pointAt(s), std::atan2(line.tangentAt(s).y(), line.tangentAt(s).x()));
      const Prediction pred = predictView(visiontest::campus(), pose, cam);
      const Frame f = world.render(rays, pose, s);
      VisionFrame vf{f.rgb.width, f.rgb.height, f.rgb.data.data(), &cam, s};
      const DetectedObject a = with->detect(vf, pred.view);
      vf.want_region = false;
      const DetectedObject b = without->detect(vf, pred.view);
      ASSERT_EQ(a.status, DetectedObject::Status::Ok) << grid << " " << s;
      EXPECT_FALSE(a.region_image.empty());
      EXPECT_TRUE(b.region_image.empty());
      EXPECT_TRUE(b.region_vehicle.empty());
      DetectedObject b_with_region = b;
      b_with_region.region_image = a.region_image;
      expectSameDetection(a, b_with_region, static_cast<std::size_t>(s));
      ok += 1;
    }
    EXPECT_EQ(ok, 5);
  }
}

// The park finder's lookup table holds the reference's certainty for every colour: trained on a noisy
// road frame in each feature space (RGB, log colour, normalised colour), then frames that hold the
// colour cube (every red and green, every third blue) classified by both paths, pixel by pixel.
TEST(ParkFinderLookupTable, EveryColourGetsTheReferencesCertaintyInEveryFeatureSpace) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 28);
  const int w = 96, h = 64;
  Image train(w, h, 3), outline(w, h, 1);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const bool road = std::abs(u - 0.5 * w) <= w * (0.1 + 0.3 * v / h);
      const double c[3] = {road ? 125.0 : 70.0, road ? 122.0 : 125.0, road ? 130.0 : 50.0};
      for (int b = 0; b < 3; ++b)
        train.pixel(u, v)[b] = static_cast<std::uint8_t>(std::clamp(std::lround(c[b] + noise(rng)), 0L, 255L));
      outline.pixel(u, v)[0] = road ? 255 : 0;
    }
  for (const int space : {0, 1, 2}) {
    ClusterPerceptronOptions o;
    o.clusters = 7;
    o.log_color = space == 1;
    o.normalized_color = space == 2;
    ClusterPerceptron fast(o);
    fast.trainClusters(train.data.data(), w, h);
    fast.setRowWidths(trapezoidRowWidths(outline));
    fast.trainPerceptron(train.data.data(), w, h, outline.data.data());
    ClusterPerceptron reference = fast;
    reference.setFast(false);
    fast.setRowWidths(std::vector<double>(256, 100.0));
    reference.setRowWidths(std::vector<double>(256, 100.0));
    std::size_t road = 0, pixels = 0;
    for (int blue = 0; blue < 256; blue += 3) {
      Image cube(256, 256, 3);
      for (int g = 0; g < 256; ++g)
        for (int r = 0; r < 256; ++r) {
          std::uint8_t* p = cube.pixel(r, g);
          p[0] = static_cast<std::uint8_t>(r), p[1] = static_cast<std::uint8_t>(g), p[2] = static_cast<std::uint8_t>(blue);
        }
      const RoadFinding a = fast.find(cube.data.data(), 256, 256, true);
      const RoadFinding b = reference.find(cube.data.data(), 256, 256, true);
      ASSERT_EQ(a.certainty.data, b.certainty.data) << "space " << space << ", blue " << blue;
      road += static_cast<std::size_t>(std::count(a.mask.data.begin(), a.mask.data.end(), 255));
      pixels += a.mask.data.size();
    }
    EXPECT_GT(road, pixels / 50) << space;  // both classes in the cube: the comparison saw each
    EXPECT_LT(road, pixels - pixels / 50) << space;
  }
}

// The park finder's fast path (ClusterPerceptron: lookup table, and where the CPU has AVX2 or AVX-512
// (VBMI, GFNI) with blocks a multiple of 8 pixels, one vector pass per row for the certainties, block
// sums and road count) against the per-pixel reference, on noisy synthetic frames of widths that leave
// every kind of row tail (not a multiple of 16 or 64, a last row without 8 bytes beyond it) and block
// sizes of both paths: the same certainties, mask, Hough answer and confidence (which sums the block
// sums), to the bit. Run with the vector code capped at `cap` (each level the CPU has is tested).
void expectParkFastPathEqualsReference(ParkSimd cap) {
  setParkSimdCap(cap);
  struct Case {
    int width, height, block;
  };
  int found = 0, cases = 0;
  for (const Case k : {Case{64, 48, 8}, Case{100, 60, 8}, Case{131, 70, 16}, Case{203, 90, 8}, Case{67, 50, 6},
                       Case{19, 40, 8}}) {
    const auto frame = [&](std::uint32_t seed) {
      std::mt19937 rng(seed);
      std::normal_distribution<double> noise(0, 28);  // wide: many colours in the table's boundary cells
      Image rgb(k.width, k.height, 3), outline(k.width, k.height, 1);
      for (int v = 0; v < k.height; ++v) {
        const double half = k.width * (0.1 + 0.3 * v / k.height), centre = 0.5 * k.width + 0.1 * (v - k.height / 2.0);
        for (int u = 0; u < k.width; ++u) {
          const bool road = std::abs(u - centre) <= half;
          const double c[3] = {road ? 125.0 : 70.0, road ? 122.0 : 125.0, road ? 130.0 : 50.0};
          for (int b = 0; b < 3; ++b)
            rgb.pixel(u, v)[b] = static_cast<std::uint8_t>(std::clamp(std::lround(c[b] + noise(rng)), 0L, 255L));
          outline.pixel(u, v)[0] = road ? 255 : 0;
        }
      }
      return std::make_pair(rgb, outline);
    };
    ClusterPerceptronOptions o;
    o.block_size = k.block;
    ClusterPerceptron fast(o);
    const auto [train, outline] = frame(1);
    fast.trainClusters(train.data.data(), k.width, k.height);
    fast.setRowWidths(trapezoidRowWidths(outline));
    fast.trainPerceptron(train.data.data(), k.width, k.height, outline.data.data());
    ClusterPerceptron reference = fast;
    reference.setFast(false);
    for (std::uint32_t seed = 2; seed <= 4; ++seed) {
      const Image rgb = frame(seed).first;
      const RoadFinding a = fast.find(rgb.data.data(), k.width, k.height, true);
      const RoadFinding b = reference.find(rgb.data.data(), k.width, k.height, true);
      const std::string at = std::to_string(k.width) + " x " + std::to_string(k.height) + ", block " +
                             std::to_string(k.block) + ", seed " + std::to_string(seed);
      EXPECT_EQ(a.certainty, b.certainty) << at;
      EXPECT_EQ(a.mask, b.mask) << at;
      ASSERT_EQ(a.ok, b.ok) << at << ": " << a.reason << " / " << b.reason;
      EXPECT_EQ(a.confidence, b.confidence) << at;
      EXPECT_EQ(a.shift, b.shift) << at;
      EXPECT_EQ(a.intercept_col, b.intercept_col) << at;
      EXPECT_EQ(a.centerline_image.a, b.centerline_image.a) << at;
      EXPECT_EQ(a.centerline_image.b, b.centerline_image.b) << at;
      // Both classes present: the frames are no all-road or all-grass shortcut.
      const auto road = std::count(a.mask.data.begin(), a.mask.data.end(), 255);
      EXPECT_GT(road, static_cast<long>(a.mask.data.size() / 10)) << at;
      EXPECT_LT(road, static_cast<long>(a.mask.data.size() * 9 / 10)) << at;
      found += a.ok;
      ++cases;
    }
  }
  EXPECT_EQ(cases, 18);
  EXPECT_GE(found, 12);
  setParkSimdCap(ParkSimd::Avx512);
}

// Grey images with a step edge at a random angle and noise; windows centred anywhere from well inside
// to half outside the image, at the tracker's sizes and the start search's, any polarity and gate:
// the fast operator's match is the reference's bit for bit (NaN where the reference's is NaN).
TEST(EdgeOperatorFastPath, SameMatchAsTheReferenceBitForBit) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0, 1);
  std::normal_distribution<double> noise(0, 4);
  auto same = [](double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; };
  int compared = 0, found = 0, clipped = 0;
  for (int image_k = 0; image_k < 6; ++image_k) {
    GreyImage g;
    g.width = image_k % 2 == 0 ? 480 : 173;
    g.height = image_k % 2 == 0 ? 360 : 97;
    g.data.resize(static_cast<std::size_t>(g.width) * g.height);
    const double a = unit(rng) * std::numbers::pi, c = unit(rng) * g.width;
    for (int v = 0; v < g.height; ++v)
      for (int u = 0; u < g.width; ++u)
        g.data[static_cast<std::size_t>(v) * g.width + u] =
            static_cast<float>((std::cos(a) * (u - c) + std::sin(a) * v > 0 ? 120 : 80) + noise(rng));
    for (int trial = 0; trial < 60; ++trial) {
      OrientedEdgeParams p;
      p.along_px = 8 + static_cast<int>(unit(rng) * 60);
      p.across_px = 8 + static_cast<int>(unit(rng) * 120);
      p.step_half_width_px = 1 + static_cast<int>(unit(rng) * 6);
      p.angle_step_deg = trial % 3 == 0 ? 2.0 : 1.0;
      p.angle_search_deg = trial % 4 == 0 ? 0.0 : 10.0;
      if (trial % 5 == 0) p.max_offset_px = 10;
      Vec2 centre(-0.25 * g.width + 1.5 * g.width * unit(rng), -0.25 * g.height + 1.5 * g.height * unit(rng));
      double dir = (unit(rng) - 0.5) * std::numbers::pi;
      if (trial % 7 == 0) {  // upright windows at whole pixels: with an even size, samples at exact halves
        centre = centre.array().round();
        dir = 0;
        p.angle_search_deg = 0;
        p.across_px += p.across_px % 2;
        p.along_px += p.along_px % 2;
      }
      const int polarity = trial % 3 - 1;
      const EdgeMatch fast = orientedEdge(g, centre, Vec2(std::sin(dir), -std::cos(dir)), p, polarity);
      const EdgeMatch ref = orientedEdgeReference(g, centre, Vec2(std::sin(dir), -std::cos(dir)), p, polarity);
      ASSERT_EQ(fast.found, ref.found) << image_k << " " << trial;
      EXPECT_TRUE(fast.point == ref.point && fast.direction == ref.direction) << image_k << " " << trial;
      EXPECT_TRUE(same(fast.contrast, ref.contrast) && same(fast.correlation, ref.correlation) &&
                  same(fast.width_px, ref.width_px))
          << image_k << " " << trial;
      ASSERT_EQ(fast.profile.size(), ref.profile.size());
      for (std::size_t k = 0; k < ref.profile.size(); ++k) EXPECT_TRUE(same(fast.profile[k], ref.profile[k])) << k;
      ++compared;
      found += ref.found;
      clipped += std::any_of(ref.profile.begin(), ref.profile.end(), [](double v) { return std::isnan(v); });
    }
  }
  EXPECT_EQ(compared, 360);
  EXPECT_GT(found, 100);   // edges found, so the scores and sub-pixel positions were compared ...
  EXPECT_GT(clipped, 20);  // ... and windows over the image's border, where samples are checked
}

TEST(ParkFinderFastPath, SameCertaintiesSumsAndLineAsTheReferenceAtAnyWidthAndBlock) {
  for (const ParkSimd cap : {ParkSimd::Avx512, ParkSimd::Avx2, ParkSimd::Portable}) {
    SCOPED_TRACE("vector code at most " + std::to_string(static_cast<int>(cap)) + " (0 portable, 1 AVX2, 2 AVX-512)");
    expectParkFastPathEqualsReference(cap);
  }
}

// fitCentreModel() sums the weighted normal equations in plain arrays; here they are summed with Eigen's
// outer products as before that change (A += w·φφᵀ, rhs += w·φ·(u − fixed part), then LDLT): the
// same coefficients to the bit, for the line and the arc model (degree 1 and 2) and Huber weights
// that bite.
TEST(ParkFinderFastPath, CentreModelFitSumsAsEigensOuterProducts) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-3.0, 3.0);
  std::vector<double> row_x(400), row_b(400);
  for (int v = 0; v < 400; ++v) row_x[v] = 2.0 + 4000.0 / (v + 40.0), row_b[v] = 0.5 * (v + 40.0);
  for (const int degree : {1, 2}) {
    CentreModel start;
    start.v0 = 100;
    start.v1 = 399;
    start.arc = ArcBasis(row_x, row_b, start.v0, start.v1);
    start.p = Vec3(200.0, 15.0, 0.01);
    std::vector<Vec2> vu;
    for (int v = 100; v < 400; v += 2) vu.emplace_back(v, start.u(v) + noise(rng) + (v % 37 == 0 ? 40.0 : 0.0));
    CentreModel fast = start, eigen = start;
    ASSERT_TRUE(fitCentreModel(vu, degree, 0.6, fast));
    const int m = degree + 1;
    for (int it = 0; it < 8; ++it) {
      Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
      Vec3 rhs = Vec3::Zero();
      for (const Vec2& s : vu) {
        const double r = std::abs(s.y() - eigen.u(s.x()));
        const double w = r <= 0.6 ? 1.0 : 0.6 / r;
        const Vec3 phi = eigen.basis(s.x());
        A.topLeftCorner(m, m) += w * phi.head(m) * phi.head(m).transpose();
        rhs.head(m) += w * phi.head(m) * (s.y() - (m < 3 ? eigen.p[2] * phi[2] : 0.0));
      }
      Vec3 p = Vec3(0.0, 0.0, m < 3 ? eigen.p[2] : 0.0);
      p.head(m) = Eigen::LDLT<Eigen::MatrixXd>(A.topLeftCorner(m, m)).solve(rhs.head(m));
      const double change = (p - eigen.p).cwiseAbs().maxCoeff();
      eigen.p = p;
      if (change < 1e-3) break;
    }
    for (int i = 0; i < 3; ++i) EXPECT_EQ(fast.p[i], eigen.p[i]) << "degree " << degree << ", coefficient " << i;
  }
}

// rowCandidates() (32 pixels' road bits at a time) against its rule pixel by pixel: a candidate at
// u in [max(3, lo), min(width − 3, hi)] where pixels u − 3 … u − 1 are of one class and u … u + 2 of
// the other. Random rows of every width the 32-bit words split differently, runs of one class
// from 1 to 12 pixels (isolated pixels are no edge), random windows.
TEST(ParkFinderEdges, RowCandidatesFollowTheRulePixelByPixel) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> run(1, 12), value(0, 255);
  int differing = 0, found = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const int width = 6 + trial % 97;
    std::vector<std::uint8_t> row(static_cast<std::size_t>(width));
    bool road = rng() % 2 == 0;
    for (int u = 0; u < width;) {
      for (int k = run(rng); k > 0 && u < width; --k, ++u)
        row[static_cast<std::size_t>(u)] = static_cast<std::uint8_t>(road ? 128 + value(rng) / 2 : value(rng) / 2);
      road = !road;
    }
    const int lo = static_cast<int>(rng() % 8), hi = width - static_cast<int>(rng() % 8);
    std::vector<EdgeCandidate> got;
    rowCandidates(row.data(), width, trial, lo, hi, got);
    std::vector<EdgeCandidate> want;
    const auto isRoad = [&](int u) { return row[static_cast<std::size_t>(u)] > 127; };
    for (int u = std::max(3, lo); u <= std::min(width - 3, hi); ++u) {
      const bool now = isRoad(u);
      if (isRoad(u - 1) != now && isRoad(u - 2) != now && isRoad(u - 3) != now && isRoad(u + 1) == now &&
          (u + 2 >= width || isRoad(u + 2) == now))
        want.push_back({trial, u - 0.5, now});
    }
    found += static_cast<int>(want.size());
    bool same = got.size() == want.size();
    for (std::size_t i = 0; same && i < got.size(); ++i)
      same = got[i].v == want[i].v && got[i].u == want[i].u && got[i].left == want[i].left;
    if (!same && ++differing <= 3) ADD_FAILURE() << "row " << trial << " (width " << width << "): " << got.size()
                                                 << " candidates, " << want.size() << " by the rule";
  }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(found, 2000);  // the rows hold edges, not only runs too short to be one
}

// edgeSupportCount() (every candidate's test in one loop, then each row side counted once) against
// rowSideSupport() of CentreModel::u()'s test one candidate at a time, on random rows of 0 to 4
// candidates near and far from the edges, for the line and the arc model.
TEST(ParkFinderEdges, EdgeSupportCountsEachRowSideOnceAsRowSideSupport) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> off(-4.0, 4.0);
  std::vector<double> row_x(300), row_b(300), widths(300);
  for (int v = 0; v < 300; ++v) row_x[v] = 2.0 + 3000.0 / (v + 30.0), row_b[v] = 0.4 * (v + 30.0), widths[v] = 0.8 * v;
  int differing = 0, supported = 0;
  for (int trial = 0; trial < 400; ++trial) {
    CentreModel model;
    model.v0 = 60;
    model.v1 = 299;
    if (trial % 2 == 1) model.arc = ArcBasis(row_x, row_b, model.v0, model.v1);
    model.p = Vec3(150.0 + off(rng), 10.0 * off(rng), trial % 2 == 1 ? 0.02 * off(rng) : 0.0);
    std::vector<EdgeCandidate> cands;
    for (int v = 60; v < 300; v += 3)
      for (int k = static_cast<int>(rng() % 5); k > 0; --k) {
        const bool left = rng() % 2 == 0;
        cands.push_back({v, model.u(v) + (left ? -0.5 : 0.5) * widths[v] + off(rng), left});
      }
    const Vec3 p = model.p + Vec3(off(rng) / 4, off(rng) / 4, 0.0);
    CentreModel at = model;
    at.p = p;
    const int want = rowSideSupport(
        cands, [](const EdgeCandidate& e) { return e.left; },
        [&](const EdgeCandidate& e) { return !(std::abs(e.u - (at.u(e.v) + (e.left ? -0.5 : 0.5) * widths[e.v])) > 2.0); });
    const int got = edgeSupportCount(cands, widths, model, p, 2.0);
    supported += want;
    if (got != want && ++differing <= 3) ADD_FAILURE() << "trial " << trial << ": " << got << " vs " << want;
  }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(supported, 0);
}

}  // namespace
}  // namespace mapnav
