// ScorePipeline: the region steps around a probability of the subclass's own (the learned
// pipeline's base), checked with a hand-made probability whose answer is known.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "eval_common.h"
#include "mapnav/core/error.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision/pipelines.h"

namespace mapnav {
namespace {

using visiontest::pinhole;

/// P(road) 0.9 on the ground cells of the columns [lo, hi) (fractions of the width), 0.1 elsewhere.
class ColumnBand : public ScorePipeline {
 public:
  ColumnBand(double lo, double hi) : ScorePipeline("column-band"), lo_(lo), hi_(hi) {}
  void configure(const std::string& json) override {
    options_ = scorePipelineOptionTable().parse(json, ScorePipelineOptions{}, "pipeline \"column-band\"");
  }
  int calls = 0;

 protected:
  std::vector<float> roadProbability(const std::uint8_t*, int width, int height, const std::uint8_t* ground) override {
    ++calls;
    std::vector<float> p(static_cast<std::size_t>(width) * height, 0.0f);
    for (int v = 0; v < height; ++v)
      for (int u = 0; u < width; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * width + u;
        if (ground[i] != 0) p[i] = u >= lo_ * width && u < hi_ * width ? 0.9f : 0.1f;
      }
    return p;
  }
  const ScorePipelineOptions& scoreOptions() const override { return options_; }

 private:
  double lo_, hi_;
  ScorePipelineOptions options_;
};

/// A predicted road straight ahead, 3-20 m, 4 m wide: it overlaps the left half of the view.
PredictedObject roadAhead() {
  PredictedObject view;
  PredictedRegion r;
  r.id = "R";
  r.surface = "asphalt";
  r.vehicle = {{{3, -2}, {20, -2}, {20, 2}, {3, 2}}};
  view.regions.push_back(r);
  return view;
}

TEST(ScorePipeline, RegionIsWhereTheProbabilityExceedsTheThresholdAndTheConfidenceIsTheProbability) {
  const Camera& cam = pinhole();
  Image rgb(cam.width(), cam.height(), 3);
  std::fill(rgb.data.begin(), rgb.data.end(), 128);  // mid-grey: the frame checks pass
  ColumnBand p(0, 0.5);  // the left half
  p.configure("{}");
  VisionFrame frame{rgb.width, rgb.height, rgb.data.data(), &cam, 0.0};
  frame.want_masks = true;
  const DetectedObject d = p.detect(frame, roadAhead());
  ASSERT_NE(d.status, DetectedObject::Status::Failed) << d.reason;
  EXPECT_EQ(p.calls, 1);
  ASSERT_FALSE(d.road_mask.empty());
  ASSERT_FALSE(d.road_confidence.empty());
  const Image ground = groundMask(cam);
  // Away from the middle column (the box filter and the region's morphology reach a few cells),
  // the left half of the ground is road and the right half is not.
  long left = 0, left_road = 0, right_road = 0;
  for (int v = 0; v < cam.height(); ++v)
    for (int u = 0; u < cam.width(); ++u) {
      if (ground.pixel(u, v)[0] == 0 || std::abs(u - cam.width() / 2) < 16) continue;
      const bool road = d.road_mask.pixel(u, v)[0] != 0;
      if (u < cam.width() / 2) left += 1, left_road += road;
      else right_road += road;
    }
  EXPECT_GT(left_road, 0.97 * left);
  EXPECT_EQ(right_road, 0);
  // The confidence maps threshold +- 0.5 onto 0..255, road from 129: 0.9 -> 129 + 126 * 0.8 = 229.8
  // -> 230, 0.1 -> 128 - 128 * 0.8 = 25.6 -> 26 (docs/eval.md).
  const int v = cam.height() - 20;
  EXPECT_EQ(d.road_confidence.pixel(60, v)[0], 230);
  EXPECT_EQ(d.road_confidence.pixel(cam.width() - 60, v)[0], 26);
}

TEST(ScorePipeline, NothingAboveTheThresholdFailsAsNoRoadRegion) {
  const Camera& cam = pinhole();
  Image rgb(cam.width(), cam.height(), 3);
  std::fill(rgb.data.begin(), rgb.data.end(), 128);  // mid-grey: the frame checks pass
  ColumnBand p(0, 0.5);  // the left half
  p.configure(R"({"threshold": 0.95})");
  const DetectedObject d = p.detect(VisionFrame{rgb.width, rgb.height, rgb.data.data(), &cam, 0.0}, roadAhead());
  EXPECT_EQ(d.status, DetectedObject::Status::Failed);
  EXPECT_NE(d.reason.find("no road-coloured region"), std::string::npos) << d.reason;
}

// The centre line of the region (centre_line, on by default): a band of the image's middle columns
// symmetric about the principal point is, on the ground of a camera with no roll or yaw, a wedge
// about the x axis: its centre line is the axis. The left half is cut by the image's side in every
// row and gives none; with centre_line off neither does the band.
TEST(ScorePipeline, TheRegionsCentreLineIsGivenUnlessTurnedOff) {
  const Camera& cam = pinhole();
  Image rgb(cam.width(), cam.height(), 3);
  std::fill(rgb.data.begin(), rgb.data.end(), 128);
  const VisionFrame frame{rgb.width, rgb.height, rgb.data.data(), &cam, 0.0};
  ColumnBand band(0.375, 0.625);
  band.configure("{}");
  const DetectedObject d = band.detect(frame, roadAhead());
  ASSERT_NE(d.status, DetectedObject::Status::Failed) << d.reason;
  ASSERT_TRUE(d.centerline_vehicle);
  const Segment2& c = *d.centerline_vehicle;
  EXPECT_NEAR(std::atan2(c.vector().y(), c.vector().x()), 0.0, degToRad(0.5));
  EXPECT_NEAR(c.a.y(), 0.0, 0.03);
  EXPECT_GT(c.length(), 5.0);
  ColumnBand left(0, 0.5);
  left.configure("{}");
  EXPECT_FALSE(left.detect(frame, roadAhead()).centerline_vehicle);
  band.configure(R"({"centre_line": false})");
  EXPECT_FALSE(band.detect(frame, roadAhead()).centerline_vehicle);
}

TEST(ScorePipeline, OptionsValidatedByName) {
  EXPECT_NO_THROW(ScorePipelineOptions{}.validate());
  ColumnBand p(0, 0.5);  // the left half
  try {
    p.configure(R"({"threshold": 1.5})");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("threshold"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mapnav
