#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <set>
#include <utility>

#include "eval_common.h"
#include "mapnav/core/error.h"
#include "mapnav/map/predict.h"
#include "mapnav/sim/world.h"
#include "mapnav/testing/maps.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision/pipelines.h"
#include "mapnav/vision/segmentation_eval.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {
namespace {

using visiontest::campus;
using visiontest::pinhole;

const Pose2 kOnRoad(60, 40, 0);  // on R1, looking along it

DetectedObject run(const std::string& name, const Image& rgb, const PredictedObject& view,
                   const std::string& options = "{}") {
  registerBuiltinPipelines();
  auto p = createPipeline(name, options);
  VisionFrame f{rgb.width, rgb.height, rgb.data.data(), &pinhole(), 0.0};
  return p->detect(f, view);
}

TEST(Pipeline, BuiltinsRegisteredIdempotentlyWithDocumentedOptions) {
  registerBuiltinPipelines();
  registerBuiltinPipelines();
  std::set<std::string> names;
  for (const PipelineInfo& info : listPipelines()) {
    names.insert(info.name);
    if (info.name == "sidewalk" || info.name == "color-rgb" || info.name == "blue-band") {
      EXPECT_FALSE(info.options.empty());
      for (const OptionInfo& o : info.options) EXPECT_FALSE(o.default_json.empty()) << o.name;
    }
  }
  EXPECT_TRUE(names.contains("sidewalk"));
  EXPECT_TRUE(names.contains("color-rgb"));
  EXPECT_TRUE(names.contains("blue-band"));
  EXPECT_EQ(std::string(kDefaultPipeline), "sidewalk");
}

TEST(Pipeline, ConfigureRejectsBadOptions) {
  registerBuiltinPipelines();
  EXPECT_NO_THROW(createPipeline("sidewalk", R"({"blend": 0.3, "adaptive": false})"));
  EXPECT_THROW(createPipeline("sidewalk", R"({"blend": 2})"), InvalidInput);
  EXPECT_THROW(createPipeline("sidewalk", R"({"no_such": 1})"), InvalidInput);
  EXPECT_THROW(createPipeline("sidewalk", R"({"adaptive": 1})"), InvalidInput);
  EXPECT_THROW(createPipeline("blue-band", R"([1])"), InvalidInput);
  try {
    createPipeline("sidewalk", R"({"block_size": 0})");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("block_size"), std::string::npos);
  }
}

TEST(Pipeline, AllThreeFindTheRoadOnASunnyFrame) {
  WorldOptions wo;
  wo.shadow_density = 0;
  const Frame frame = World(campus(), wo).render(pinhole(), kOnRoad, 0.0);
  const Prediction pred = predictView(campus(), kOnRoad, pinhole());
  for (const std::string name : {"sidewalk", "color-rgb", "blue-band"}) {
    const DetectedObject d = run(name, frame.rgb, pred.view);
    ASSERT_EQ(d.status, DetectedObject::Status::Ok) << name << ": " << d.reason;
    EXPECT_GT(d.confidence, 0.9) << name;
    EXPECT_GE(d.region_image.size(), 3u);
    int labelled = 0;
    for (const DetectedLine& l : d.lines) {
      if (l.frame_edge) {
        EXPECT_FALSE(l.label.has_value());
      }
      labelled += l.label.has_value();
    }
    EXPECT_GE(labelled, 2) << name;  // both edges of R1
  }
}

// The per-pixel mask and confidence: only when the frame wants them; the frame's size; 0 where the camera sees
// no ground; and on a sunny frame it separates the true road (the renderer's mask) from the rest
// almost perfectly, while thresholding it at 129 agrees with the region on nearly every pixel.
TEST(Pipeline, RegionPipelinesGiveAPerPixelMaskAndConfidenceWhenAsked) {
  WorldOptions wo;
  wo.shadow_density = 0;
  const Frame frame = World(campus(), wo).render(pinhole(), kOnRoad, 0.0);
  const Prediction pred = predictView(campus(), kOnRoad, pinhole());
  const Image ground = groundMask(pinhole());
  registerBuiltinPipelines();
  for (const std::string name : {"sidewalk", "color-rgb", "blue-band"}) {
    auto p = createPipeline(name);
    VisionFrame f{frame.rgb.width, frame.rgb.height, frame.rgb.data.data(), &pinhole(), 0.0};
    const DetectedObject unasked = p->detect(f, pred.view);
    EXPECT_TRUE(unasked.road_confidence.empty()) << name;
    EXPECT_TRUE(unasked.road_mask.empty()) << name;
    f.want_masks = true;
    const DetectedObject d = p->detect(f, pred.view);
    ASSERT_EQ(d.status, DetectedObject::Status::Ok) << name << ": " << d.reason;
    const Image& c = d.road_confidence;
    ASSERT_EQ(c.width, frame.rgb.width) << name;
    ASSERT_EQ(c.height, frame.rgb.height) << name;
    ASSERT_EQ(c.channels, 1) << name;
    // The mask is the region, per pixel: regionMask gives it, and on this frame (no holes) it is the
    // outline filled but for the outline's sub-cell rounding.
    ASSERT_EQ(d.road_mask.width, c.width) << name;
    ASSERT_EQ(d.road_mask.height, c.height) << name;
    const Image region = regionMask(d, c.width, c.height);
    EXPECT_EQ(region.data, d.road_mask.data) << name;
    const Image outline = regionMask(d.region_image, c.width, c.height);
    std::size_t agree = 0, same = 0, ground_px = 0;
    for (std::size_t i = 0; i < c.data.size(); ++i) {
      if (ground.data[i] == 0) {
        ASSERT_EQ(c.data[i], 0) << name << " pixel " << i;
        ASSERT_EQ(region.data[i], 0) << name << " pixel " << i;
        continue;
      }
      ++ground_px;
      agree += (c.data[i] >= 129) == (region.data[i] != 0);
      same += (outline.data[i] != 0) == (region.data[i] != 0);
    }
    EXPECT_GT(static_cast<double>(agree) / static_cast<double>(ground_px), 0.97) << name;
    EXPECT_GT(static_cast<double>(same) / static_cast<double>(ground_px), 0.99) << name;
    ScoreHistogram scores;
    scores.add(c, frame.mask, LabelClasses{{255}, {}});
    EXPECT_GT(*scores.maxF(), 0.95) << name;
    EXPECT_GT(*scores.averagePrecision(), 0.9) << name;
  }
}

TEST(BlueBand, FixedThresholdOption) {
  WorldOptions wo;
  wo.shadow_density = 0;
  const Frame frame = World(campus(), wo).render(pinhole(), kOnRoad, 0.0);
  const Prediction pred = predictView(campus(), kOnRoad, pinhole());
  registerBuiltinPipelines();
  auto p = createPipeline("blue-band", R"({"threshold": 110})");
  VisionFrame f{frame.rgb.width, frame.rgb.height, frame.rgb.data.data(), &pinhole(), 0.0};
  EXPECT_EQ(p->detect(f, pred.view).status, DetectedObject::Status::Ok);
}

// Where the detected road region's outline crosses the vehicle-frame line on which coordinate `axis`
// (0: x, ahead; 1: y, left) is `at`: the least and the greatest of the other coordinate there, or
// nothing when the region does not reach that line.
std::optional<std::pair<double, double>> regionCrossings(const DetectedObject& d, int axis, double at) {
  std::optional<std::pair<double, double>> span;
  const Polygon2& ring = d.region_vehicle;
  const int other = 1 - axis;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Vec2 a = ring[i], b = ring[(i + 1) % ring.size()];
    if ((a[axis] > at) == (b[axis] > at)) continue;
    const double c = a[other] + (at - a[axis]) / (b[axis] - a[axis]) * (b[other] - a[other]);
    span = span ? std::make_pair(std::min(span->first, c), std::max(span->second, c)) : std::make_pair(c, c);
  }
  return span;
}

TEST(ConcreteRoadPastABrickBranch, TheBrickRoadIsRoadAndItsEdgesAreLabelled) {
  // campus_tour at I15 on its way back: west along the 2 m concrete R23 (y = 120, heading 180°)
  // past the T where the 3 m brick R22 (x = 98.5 .. 101.5) leaves to the left. The pipeline learns
  // concrete on the way; the brick is road too, and its two edges are the lines across the road
  // that fix the along-road position. The world is the mission's (seed 2, shadows 0.10, leaves 0.03).
  WorldOptions wo;
  wo.seed = 2;
  wo.shadow_density = 0.10;
  wo.leaf_density = 0.03;
  const World world(campus(), wo);
  registerBuiltinPipelines();
  auto pipeline = createPipeline("sidewalk", R"({"max_distance_m": 1.0})");  // the mission's
  DetectedObject d;
  for (int x = 125; x >= 107; --x) {
    const Pose2 pose(x, 120, degToRad(180));
    const Frame frame = world.render(pinhole(), pose, 125.0 - x);
    const Prediction pred = predictView(campus(), pose, pinhole());
    VisionFrame f{frame.rgb.width, frame.rgb.height, frame.rgb.data.data(), &pinhole(), 125.0 - x};
    d = pipeline->detect(f, pred.view);
    ASSERT_EQ(d.status, DetectedObject::Status::Ok) << "at x = " << x << ": " << d.reason;
  }
  // From x = 107, 1.5 m to the left (y = 118.5) is brick only, from R22's east edge (x = 101.5,
  // 5.5 m ahead) to its west edge (x = 98.5, 8.5 m ahead). A concrete-only road class saw none of it.
  const auto span = regionCrossings(d, 1, 1.5);
  ASSERT_TRUE(span.has_value());
  EXPECT_NEAR(span->first, 5.5, 0.1);
  EXPECT_NEAR(span->second, 8.5, 0.1);
  std::set<std::string> labels;
  for (const DetectedLine& l : d.lines) {
    if (l.label) labels.insert(*l.label);
  }
  EXPECT_TRUE(labels.contains("R22.left.0"));
  EXPECT_TRUE(labels.contains("R22.right.0"));
}

// A 2 m brick path between dirt shoulders (random campus 18's S3): in rg the brick's grey mortar
// spreads the road class over the dirt's colour, within 8 sigma of the road, so beyond the gate of a
// prediction from a guessed pose (an eval's photo, no pose covariance: nonroad_gate_sigma) nothing
// trains non-road and the dirt is taken for road. From the Map's estimate (a pose covariance: the
// mission's case, nonroad_gate_sigma_mapped) the dirt trains non-road and the region is the path.
// Ten frames 1 m apart along the path, the sidewalk pipeline adaptive as in a mission.
TEST(SidewalkNonroadGate, ABrickPathBetweenDirtShouldersIsFoundFromTheMapsEstimate) {
  MapData data = testing::straightRoad("brick between dirt", 60, 2.0, "brick", "dirt");
  data.surfaces = {{"brick", {Vec3(150, 84, 62), Vec3(14, 14, 14)}},
                   {"dirt", {Vec3(122, 96, 66), Vec3(16, 16, 16)}},
                   {"grass", {Vec3(72, 122, 52), Vec3(16, 16, 16)}}};
  const Map map(std::move(data), "brick between dirt");
  WorldOptions wo;  // the random-campus suite's world
  wo.seed = 18;
  wo.shadow_density = 0.05;
  wo.leaf_density = 0.02;
  wo.noise_sigma = 2.0;
  const World world(map, wo);
  registerBuiltinPipelines();
  for (const bool mapped : {false, true}) {
    SCOPED_TRACE(mapped ? "from the Map's estimate" : "from a guessed pose");
    auto pipeline = createPipeline("sidewalk");
    DetectedObject d;
    for (int k = 0; k < 10; ++k) {
      const Pose2 pose(5 + k, 0, 0);
      const Frame frame = world.render(pinhole(), pose, k);
      Prediction pred = predictView(map, pose, pinhole());
      if (mapped) pred.view.pose_covariance = Vec3(0.05 * 0.05, 0.02 * 0.02, degToRad(0.3) * degToRad(0.3)).asDiagonal();
      VisionFrame f{frame.rgb.width, frame.rgb.height, frame.rgb.data.data(), &pinhole(), static_cast<double>(k)};
      d = pipeline->detect(f, pred.view);
      ASSERT_EQ(d.status, DetectedObject::Status::Ok) << k << ": " << d.reason;
    }
    const auto width = regionCrossings(d, 0, 6.0);  // the path spans y = -1 .. 1
    ASSERT_TRUE(width.has_value());
    std::set<std::string> labels;
    for (const DetectedLine& l : d.lines) {
      if (l.label) labels.insert(l.label->substr(0, l.label->rfind('.')));
    }
    if (mapped) {
      EXPECT_NEAR(width->first, -1.0, 0.1);
      EXPECT_NEAR(width->second, 1.0, 0.1);
      EXPECT_TRUE(labels.contains("R1.left"));
      EXPECT_TRUE(labels.contains("R1.right"));
    } else {
      // The dirt on one side at least (in this world the right one, out to the view's edge at -1.73).
      EXPECT_GT(std::max(-1.0 - width->first, width->second - 1.0), 0.5) << width->first << " .. " << width->second;
      EXPECT_FALSE(labels.contains("R1.left") && labels.contains("R1.right"));
    }
  }
}

// Blue-band takes road to be on the predicted road's side of its threshold: the sunny frame with its
// blue band inverted (road now dark in blue, lawn bright, as a dark road between bright pavements)
// gives the same region, to the pixels the threshold's rounding moves.
TEST(Pipeline, BlueBandFindsARoadDarkInBlue) {
  WorldOptions wo;
  wo.shadow_density = 0;
  const Frame frame = World(campus(), wo).render(pinhole(), kOnRoad, 0.0);
  Image inverted = frame.rgb;
  for (std::size_t i = 2; i < inverted.data.size(); i += 3) inverted.data[i] = static_cast<std::uint8_t>(255 - inverted.data[i]);
  const Prediction pred = predictView(campus(), kOnRoad, pinhole());
  const DetectedObject bright = run("blue-band", frame.rgb, pred.view);
  const DetectedObject dark = run("blue-band", inverted, pred.view);
  ASSERT_EQ(bright.status, DetectedObject::Status::Ok) << bright.reason;
  ASSERT_EQ(dark.status, DetectedObject::Status::Ok) << dark.reason;
  const int w = pinhole().width(), h = pinhole().height();
  const Image a = regionMask(bright, w, h), b = regionMask(dark, w, h);
  std::size_t both = 0, either = 0;
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    both += a.data[i] != 0 && b.data[i] != 0;
    either += a.data[i] != 0 || b.data[i] != 0;
  }
  ASSERT_GT(either, 0u);
  EXPECT_GT(static_cast<double>(both) / static_cast<double>(either), 0.98);
}

// A city street in blue: a dark road (the sunny frame's blue inverted) with bright lawn to its left
// and something darker than the road to its right (a car's shadow, a dark shopfront: blue 0). One
// Otsu cut puts the dark thing on the road's side and the region takes it; the band about the
// predicted road's blue level (band_sigma, default 4) leaves it out.
TEST(Pipeline, BlueBandLeavesOutWhatIsDarkerThanTheRoad) {
  WorldOptions wo;
  wo.shadow_density = 0;
  const Frame frame = World(campus(), wo).render(pinhole(), kOnRoad, 0.0);
  const int w = pinhole().width(), h = pinhole().height();
  Image street = frame.rgb;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      std::uint8_t& blue = street.pixel(u, v)[2];
      blue = frame.mask.pixel(u, v)[0] == 0 && u >= w / 2 ? 0 : static_cast<std::uint8_t>(255 - blue);
    }
  }
  const Prediction pred = predictView(campus(), kOnRoad, pinhole());
  const Image ground = groundMask(pinhole());
  // The region's IoU with the true road, and the share of the dark ground it takes.
  auto score = [&](const DetectedObject& d) {
    EXPECT_EQ(d.status, DetectedObject::Status::Ok) << d.reason;
    const Image region = regionMask(d, w, h);
    std::size_t both = 0, either = 0, dark = 0, dark_taken = 0;
    for (int v = 0; v < h; ++v) {
      for (int u = 0; u < w; ++u) {
        if (ground.pixel(u, v)[0] == 0) continue;
        const bool found = region.pixel(u, v)[0] != 0, road = frame.mask.pixel(u, v)[0] != 0;
        both += found && road;
        either += found || road;
        if (!road && u >= w / 2) ++dark, dark_taken += found;
      }
    }
    EXPECT_GT(dark, 2000u);
    return std::make_pair(static_cast<double>(both) / static_cast<double>(either),
                          static_cast<double>(dark_taken) / static_cast<double>(dark));
  };
  const auto [band_iou, band_dark] = score(run("blue-band", street, pred.view));
  EXPECT_GT(band_iou, 0.95);
  EXPECT_LT(band_dark, 0.05);
  const auto [cut_iou, cut_dark] = score(run("blue-band", street, pred.view, R"({"band_sigma": 0})"));
  EXPECT_GT(cut_dark, 0.95);  // all of it: it touches the road
  EXPECT_LT(cut_iou, 0.95);
}

class FailedFrames : public ::testing::TestWithParam<std::string> {};

// A first frame of lawn only, the prediction for the road. Nothing in view is confidently off the
// "road" (the non-road gate), so non-road is flat and all the lawn is road-coloured: the region is
// the whole ground in view (nothing in one colour can say otherwise; the next frames' models, as in
// AllGrassFrameAfterGoodFrames, can). Without the gate the two classes are both lawn and do not
// separate: the frame fails.
TEST_P(FailedFrames, AllGrassFrame) {
  WorldOptions wo;
  wo.shadow_density = 0;
  const World world(campus(), wo);
  // The camera at (25, 20), far from any road, sees only lawn; the prediction is for the road.
  const Frame grass = world.render(pinhole(), Pose2(25, 20, 0), 0.0);
  const Prediction pred = predictView(campus(), kOnRoad, pinhole());
  const DetectedObject d = run(GetParam(), grass.rgb, pred.view);
  ASSERT_EQ(d.status, DetectedObject::Status::Ok) << d.reason;
  const Image ground = groundMask(pinhole());
  const Image region = regionMask(d, pinhole().width(), pinhole().height());
  const auto count = [](const Image& m) { return std::count_if(m.data.begin(), m.data.end(), [](auto x) { return x != 0; }); };
  EXPECT_GT(count(region), 0.95 * count(ground));
  const DetectedObject plain = run(GetParam(), grass.rgb, pred.view, R"({"nonroad_gate_sigma": 0})");
  EXPECT_EQ(plain.status, DetectedObject::Status::Failed);
  EXPECT_EQ(plain.reason.rfind("no road-coloured region (road and non-road colours do not separate", 0), 0u) << plain.reason;
}

TEST_P(FailedFrames, AllGrassFrameAfterGoodFrames) {
  WorldOptions wo;
  wo.shadow_density = 0;
  const World world(campus(), wo);
  const Prediction pred = predictView(campus(), kOnRoad, pinhole());
  registerBuiltinPipelines();
  auto p = createPipeline(GetParam());
  const Frame good = world.render(pinhole(), kOnRoad, 0.0);
  VisionFrame f{good.rgb.width, good.rgb.height, good.rgb.data.data(), &pinhole(), 0.0};
  ASSERT_EQ(p->detect(f, pred.view).status, DetectedObject::Status::Ok);
  const Frame grass = world.render(pinhole(), Pose2(25, 20, 0), 0.0);
  f.rgb = grass.rgb.data.data();
  const DetectedObject d = p->detect(f, pred.view);
  EXPECT_EQ(d.status, DetectedObject::Status::Failed);
  EXPECT_EQ(d.reason.rfind("no road-coloured region (", 0), 0u) << d.reason;
}

TEST_P(FailedFrames, BlackFrame) {
  const Prediction pred = predictView(campus(), kOnRoad, pinhole());
  Image black(pinhole().width(), pinhole().height(), 3);
  const DetectedObject d = run(GetParam(), black, pred.view);
  EXPECT_EQ(d.status, DetectedObject::Status::Failed);
  EXPECT_EQ(d.reason, "frame too dark");
}

TEST_P(FailedFrames, OverExposedFrame) {
  WorldOptions wo;
  wo.shadow_density = 0;
  Frame frame = World(campus(), wo).render(pinhole(), kOnRoad, 0.0);
  for (std::uint8_t& c : frame.rgb.data) c = static_cast<std::uint8_t>(std::min(255, c * 6));
  const Prediction pred = predictView(campus(), kOnRoad, pinhole());
  const DetectedObject d = run(GetParam(), frame.rgb, pred.view);
  EXPECT_EQ(d.status, DetectedObject::Status::Failed);
  EXPECT_EQ(d.reason, "frame over-exposed");
}

TEST_P(FailedFrames, NothingPredictedInView) {
  WorldOptions wo;
  const Frame frame = World(campus(), wo).render(pinhole(), kOnRoad, 0.0);
  const DetectedObject d = run(GetParam(), frame.rgb, PredictedObject{});
  EXPECT_EQ(d.status, DetectedObject::Status::Failed);
  EXPECT_EQ(d.reason, "nothing predicted in view");
}

INSTANTIATE_TEST_SUITE_P(Pipelines, FailedFrames, ::testing::Values("sidewalk", "color-rgb"),
                         [](const auto& info) { return info.param == "sidewalk" ? "sidewalk" : "color_rgb"; });

}  // namespace
}  // namespace mapnav
