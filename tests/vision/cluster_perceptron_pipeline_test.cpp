// The "cluster-perceptron" pipeline (registered, bootstrapped from the prediction, its options) and
// the grey frames' texture features that stand in for R, G, B.
// On simulator frames of maps/park_path.json (asphalt path between grass, dirt and gravel,
// shadow_density 0.4) seen by the Terregator pin-hole camera (512 x 480, 22 deg tilt) unless a test
// says otherwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <string>

#include "cluster_perceptron_test_util.h"
#include "mapnav/core/error.h"
#include "mapnav/map/predict.h"
#include "mapnav/image/image.h"
#include "mapnav/sim/world.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision/pipelines.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {
namespace {

using namespace visiontest;

TEST(ClusterPerceptron, ParkPipelineRegisteredAndFindsTheCentreLine) {
  registerBuiltinPipelines();
  bool found = false;
  for (const PipelineInfo& info : listPipelines())
    if (info.name == "cluster-perceptron") {
      found = true;
      EXPECT_GE(info.options.size(), 10u);
    }
  ASSERT_TRUE(found);
  auto p = createPipeline("cluster-perceptron", R"({"clusters": 5, "fast": true})");
  EXPECT_THROW(p->configure(R"({"clusters": 31})"), InvalidInput);
  EXPECT_THROW(p->configure(R"({"nope": 1})"), InvalidInput);
  EXPECT_NO_THROW(createPipeline("cluster-perceptron", R"({"arc": true, "subpixel_edges": true})"));
  EXPECT_THROW(p->configure(R"({"subpixel_edges": 2})"), InvalidInput);
  EXPECT_THROW(p->configure(R"({"normalized_color": 1})"), InvalidInput);
  const World world(parkScenery(), parkWorld());
  const auto poses = straightPoses(6.0);
  for (std::size_t i = 0; i < std::min<std::size_t>(poses.size(), 8); ++i) {
    const Frame f = world.render(cam(), poses[i].pose, static_cast<double>(i));
    const Prediction pred = predictView(park(), poses[i].pose, cam());
    VisionFrame vf{f.rgb.width, f.rgb.height, f.rgb.data.data(), &cam(), static_cast<double>(i)};
    const DetectedObject d = p->detect(vf, pred.view);
    ASSERT_EQ(d.status, DetectedObject::Status::Ok) << d.reason;
    ASSERT_TRUE(d.centerline_vehicle.has_value());
    ASSERT_GE(d.region_image.size(), 4u);
    // The truth on the ground: the road's centre line in the vehicle frame.
    const Segment2 truth{poses[i].pose.inverseTransform(poses[i].road->centerline.pointAt(poses[i].s - 2.0)),
                         poses[i].pose.inverseTransform(poses[i].road->centerline.pointAt(poses[i].s + 25.0))};
    EXPECT_LT(truth.distanceTo(d.centerline_vehicle->a) + 0, 0.15) << "frame " << i;
    EXPECT_LT(std::abs(std::sin(d.centerline_vehicle->heading() - truth.heading())), std::sin(2.0 * std::numbers::pi / 180))
        << "frame " << i;
    EXPECT_GT(d.confidence, 0.3);
  }
  // Without a predicted road: the default trapezoid bootstraps it.
  p->reset();
  const Frame f = world.render(cam(), poses.front().pose, 0.0);
  VisionFrame vf{f.rgb.width, f.rgb.height, f.rgb.data.data(), &cam(), 0.0};
  const DetectedObject d = p->detect(vf, PredictedObject{});
  EXPECT_EQ(d.status, DetectedObject::Status::Ok) << d.reason;
  // A grey frame is clustered on its texture features, which normalized_color leaves alone: the same
  // answer with it as without (normalised, R = G = B would be one grey and the texture gone).
  Image grey = f.rgb;
  for (std::size_t i = 0; i < grey.data.size(); i += 3) std::fill_n(&grey.data[i], 3, grey.data[i + 1]);
  const VisionFrame gf{grey.width, grey.height, grey.data.data(), &cam(), 0.0};
  const Prediction pred = predictView(park(), poses.front().pose, cam());
  const DetectedObject plain = createPipeline("cluster-perceptron", "{}")->detect(gf, pred.view);
  const DetectedObject normalised =
      createPipeline("cluster-perceptron", R"({"normalized_color": true})")->detect(gf, pred.view);
  ASSERT_EQ(plain.status, DetectedObject::Status::Ok) << plain.reason;
  ASSERT_EQ(normalised.status, DetectedObject::Status::Ok) << normalised.reason;
  EXPECT_EQ(plain.centerline_vehicle->a, normalised.centerline_vehicle->a);
  EXPECT_EQ(plain.centerline_vehicle->b, normalised.centerline_vehicle->b);
  EXPECT_EQ(plain.confidence, normalised.confidence);
}

// Grey frames: the feature image that stands in for R, G, B. A 40 x 20 frame, flat 100 on the left
// half, a checkerboard of 110 and 100 on the right half ((u + v) even: 110).
TEST(ClusterPerceptron, GreyTextureFeaturesMeasureMeanGrainAndTexture) {
  Image grey(40, 20, 3);
  for (int v = 0; v < 20; ++v)
    for (int u = 0; u < 40; ++u) {
      const std::uint8_t g = u < 20 ? 100 : ((u + v) % 2 == 0 ? 110 : 100);
      std::fill(grey.pixel(u, v), grey.pixel(u, v) + 3, g);
    }
  EXPECT_TRUE(isGreyFrame(grey.data.data(), 40, 20));
  const Image f = greyTextureFeatures(grey.data.data(), 40, 20, 7);
  ASSERT_EQ(f.channels, 3);
  // Deep in the flat half: mean 100, no grain, no texture.
  EXPECT_EQ(f.pixel(5, 10)[0], 100);
  EXPECT_EQ(f.pixel(5, 10)[1], 0);
  EXPECT_EQ(f.pixel(5, 10)[2], 0);
  // In the checkerboard, (30, 10) is even: its 7 x 7 box holds 25 of 110 and 24 of 100, mean
  // 5150 / 49 = 105.1, standard deviation sqrt(11071.43 − 105.10²) = 5.0, times 4 = 20; every
  // pixel's 4-neighbour Laplacian is ±40, times 4 = 160.
  EXPECT_EQ(f.pixel(30, 10)[0], 105);
  EXPECT_EQ(f.pixel(30, 10)[1], 160);
  EXPECT_EQ(f.pixel(30, 10)[2], 20);
  EXPECT_THROW(greyTextureFeatures(grey.data.data(), 40, 20, 6), InvalidInput);
  grey.pixel(3, 4)[1] = 101;  // one pixel with colour: not a grey frame
  EXPECT_FALSE(isGreyFrame(grey.data.data(), 40, 20));
}

// Hand-made frames for the pipeline's region and confidence (beyond the paper), seen by the pin-hole
// camera: the road is the ground within 2 m of the vehicle's axis from 2 m to 60 m ahead, painted
// `road`; the rest of the frame `rest`. The prediction (the bootstrap) is a narrower part of it: 4 to
// 20 m ahead, within 1.2 m; or, `whole`, the road itself.
struct HandFrame {
  Image rgb;
  Image truth;  ///< 255 = road
  PredictedObject prediction;
};
HandFrame handFrame(const std::array<std::uint8_t, 3>& road, const std::array<std::uint8_t, 3>& rest, bool whole = false) {
  const auto project = [](double x0, double x1, double y) {
    const Polygon2 ground{Vec2(x0, y), Vec2(x1, y), Vec2(x1, -y), Vec2(x0, -y)};
    PredictedObject p;
    p.regions.push_back(PredictedRegion{"R", "straight road", "asphalt", Vec3::Zero(), {ground}, {}});
    return p;
  };
  HandFrame f{Image(cam().width(), cam().height(), 3), predictedRoadMask(project(2, 60, 2), cam()),
              whole ? project(2, 60, 2) : project(4, 20, 1.2)};
  for (std::size_t i = 0; i < f.truth.data.size(); ++i)
    std::copy_n((f.truth.data[i] != 0 ? road : rest).data(), 3, &f.rgb.data[3 * i]);
  return f;
}

std::unique_ptr<VisionPipeline> clusterPerceptron(const std::string& options) {
  registerBuiltinPipelines();
  return createPipeline("cluster-perceptron", options);
}

DetectedObject detectMasks(VisionPipeline& p, const HandFrame& f) {
  VisionFrame vf{f.rgb.width, f.rgb.height, f.rgb.data.data(), &cam(), 0.0};
  vf.want_masks = true;
  return p.detect(vf, f.prediction);
}

/// Whether every pixel of the (2 r + 1)^2 box around (u, v) has the same truth as (u, v).
bool deepInside(const Image& truth, int u, int v, int r) {
  for (int dv = -r; dv <= r; ++dv)
    for (int du = -r; du <= r; ++du) {
      const int x = std::clamp(u + du, 0, truth.width - 1), y = std::clamp(v + dv, 0, truth.height - 1);
      if ((truth.pixel(x, y)[0] != 0) != (truth.pixel(u, v)[0] != 0)) return false;
    }
  return true;
}

// Grey asphalt (90, 90, 90) on green grass (60, 140, 60): two colours, two clusters, which the
// perceptron tells apart at |y| > 0.93, i.e. certainty 240 on the road and 0 on the grass. Where the
// smoothing box (smooth_px 8: 17 x 17) holds one colour the confidence is then 129 + 126 = 255 on the
// road and 0 elsewhere (and 0 above the horizon, where the camera sees no ground); the region is the
// confidence above 128 exactly, and it is the road where the camera sees the ground.
TEST(ClusterPerceptron, PipelineConfidenceIsHighOnTheRoadLowElsewhereAndItsThresholdIsTheRegion) {
  const HandFrame f = handFrame({90, 90, 90}, {60, 140, 60});
  auto p = clusterPerceptron(R"({"clusters": 2})");
  const DetectedObject d = detectMasks(*p, f);
  ASSERT_EQ(d.status, DetectedObject::Status::Ok) << d.reason;
  ASSERT_EQ(d.road_confidence.width, f.rgb.width);
  ASSERT_EQ(d.road_mask.width, f.rgb.width);
  const Image ground = groundMask(cam());
  Image truth = f.truth;
  std::size_t road_deep = 0, rest_deep = 0;
  for (int v = 0; v < f.rgb.height; ++v)
    for (int u = 0; u < f.rgb.width; ++u) {
      const std::uint8_t c = d.road_confidence.pixel(u, v)[0];
      EXPECT_EQ(c > 128, d.road_mask.pixel(u, v)[0] != 0) << u << " " << v;
      if (ground.pixel(u, v)[0] == 0) {
        EXPECT_EQ(c, 0) << u << " " << v;
        truth.pixel(u, v)[0] = 0;
      } else if (deepInside(f.truth, u, v, 8)) {
        const bool road = f.truth.pixel(u, v)[0] != 0;
        EXPECT_EQ(c, road ? 255 : 0) << u << " " << v;
        (road ? road_deep : rest_deep) += 1;
      }
    }
  EXPECT_GT(road_deep, 2000u);
  EXPECT_GT(rest_deep, 2000u);
  // The region against the road in view: the box rounds its corners and drops its far tip, where the
  // road is narrower than the box.
  EXPECT_GT(maskIoU(d.road_mask, truth), 0.95);
}

// Retraining: a frame whose colours change gets its own road. The second frame swaps the colours (a
// green road between grey verges). Retrained on it (retrain_each_frame), the road is found. So it is
// by default when the first frame's perceptron was trained under the non-road gate: its prediction
// is the narrow one, less than half of the grey pixels, which the paper's bootstrap then calls not
// road. Frozen on the first frame (its prediction the whole road, which the paper's bootstrap
// separates; or without the gate), the perceptron still calls grey road, which is now the verges.
TEST(ClusterPerceptron, PipelineRetrainsOnAFrameWhoseColoursChanged) {
  Image truth = handFrame({60, 140, 60}, {90, 90, 90}).truth;
  const Image ground = groundMask(cam());
  for (std::size_t i = 0; i < truth.data.size(); ++i)
    if (ground.data[i] == 0) truth.data[i] = 0;
  struct Case {
    std::string options;
    bool whole, found;
  };
  for (const Case& c : {Case{R"({"clusters": 2, "retrain_each_frame": true})", true, true},
                        Case{R"({"clusters": 2})", false, true}, Case{R"({"clusters": 2})", true, false},
                        Case{R"({"clusters": 2, "nonroad_gate_sigma": 0})", true, false}}) {
    auto p = clusterPerceptron(c.options);
    ASSERT_EQ(detectMasks(*p, handFrame({90, 90, 90}, {60, 140, 60}, c.whole)).status, DetectedObject::Status::Ok)
        << c.options;
    const DetectedObject d = detectMasks(*p, handFrame({60, 140, 60}, {90, 90, 90}, c.whole));
    if (c.found) {
      ASSERT_EQ(d.status, DetectedObject::Status::Ok) << d.reason;
      EXPECT_GT(maskIoU(d.road_mask, truth), 0.95) << c.options;
    } else {
      EXPECT_TRUE(d.status != DetectedObject::Status::Ok || d.road_mask.empty() || maskIoU(d.road_mask, truth) < 0.1)
          << c.options << " " << c.whole;
    }
  }
}

}  // namespace
}  // namespace mapnav
