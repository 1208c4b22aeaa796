// The "cluster-perceptron" pipeline (registered, bootstrapped from the prediction, its options) and
// the grey frames' texture features that stand in for R, G, B.
// On simulator frames of maps/park_path.json (asphalt path between grass, dirt and gravel,
// shadow_density 0.4) seen by the Terregator pin-hole camera (512 x 480, 22 deg tilt) unless a test
// says otherwise.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "cluster_perceptron_test_util.h"
#include "mapnav/core/error.h"
#include "mapnav/map/predict.h"
#include "mapnav/image/image.h"
#include "mapnav/sim/world.h"
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
  const World world(park(), parkWorld());
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

}  // namespace
}  // namespace mapnav
