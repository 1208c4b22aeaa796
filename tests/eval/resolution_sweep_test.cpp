// The region pipelines at their defaults on the shared CamVid photos (480 x 360) resized to a small
// robot's cameras and a larger one: every threshold held in pixels scales with the frame
// (pixelScale()), so each pipeline still finds the road on every photo and beats the trivial
// baseline ("everything below the horizon") at every size. Road = road and pavement, as docs/eval.md.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "mapnav/eval/segmentation_evaluation.h"
#include "mapnav/testing/support.h"
#include "mapnav/vision/pipelines.h"

namespace mapnav {
namespace {

TEST(ResolutionSweep, EveryRegionPipelineFindsTheRoadAndBeatsTheBaselineFrom240x180To640x480) {
  ASSERT_TRUE(testing::realDataPresent("camvid"));
  registerBuiltinPipelines();
  const std::filesystem::path camvid = testing::realDataPath("camvid");
  const LabelClasses classes{{3, 4}, {11}};
  for (const ImageSize size : {ImageSize{240, 180}, ImageSize{320, 240}, ImageSize{640, 480}}) {
    for (const std::string name : {"sidewalk", "color-rgb", "blue-band", "cluster-perceptron", "edge-tracker"}) {
      SegmentationEvalOptions options;
      options.resize_width = size.width;
      options.resize_height = size.height;
      auto pipeline = createPipeline(name, "{}");
      const SegmentationEvaluation e =
          evaluateSegmentation(*pipeline, camvid / "images", camvid / "labels", classes, options);
      ASSERT_TRUE(e.scores.iou && e.baseline_horizon.iou);
      const std::string what = name + " at " + std::to_string(size.width) + "x" + std::to_string(size.height);
      EXPECT_LE(e.failed, 1) << what;
      EXPECT_GE(*e.scores.iou - *e.baseline_horizon.iou, 0.05) << what;
      std::printf("%-34s IoU %.3f, baseline %.3f, %d of %zu failed\n", what.c_str(), *e.scores.iou,
                  *e.baseline_horizon.iou, e.failed, e.photos.size());
    }
  }
}

}  // namespace
}  // namespace mapnav
