// regionCentreLine: the centre line of a road region drawn on the ground through the camera, where
// the answer is the band's own centre line.
#include "mapnav/vision/centre_line.h"

#include <gtest/gtest.h>

#include <cmath>

#include "eval_common.h"
#include "mapnav/core/error.h"
#include "mapnav/vision/region.h"

namespace mapnav {
namespace {

using visiontest::pinhole;

// The ground polygon (vehicle frame) as the camera sees it, filled: 255 inside, on the pixel grid.
Image seen(const std::vector<Vec2>& ground, const Camera& cam) {
  Polygon2 ring;
  for (const Vec2& g : ground) ring.push_back(*cam.projectGround(g));
  return rasterizePolygon(ring, cam.width(), cam.height());
}

// A band `width` m wide whose centre line is y = offset + tan(angle) x, from x0 to x1 ahead.
std::vector<Vec2> band(double offset, double angle_deg, double width, double x0, double x1) {
  const double t = std::tan(degToRad(angle_deg)), h = 0.5 * width / std::cos(degToRad(angle_deg));
  return {{x0, offset + t * x0 - h}, {x1, offset + t * x1 - h}, {x1, offset + t * x1 + h}, {x0, offset + t * x0 + h}};
}

double angleDeg(const Segment2& s) { return radToDeg(std::atan2(s.vector().y(), s.vector().x())); }
double yAt(const Segment2& s, double x) { return s.a.y() + s.vector().y() * (x - s.a.x()) / s.vector().x(); }

// Each row of a pinhole's image is a line of one range on the ground, mapped to it affinely: the
// middle of a row's run is the middle of the band there, so the fit gives the band's centre line
// back to the pixels' rounding.
TEST(RegionCentreLine, AStraightBandGivesItsOwnCentreLine) {
  const Camera& cam = pinhole();
  const Image mask = seen(band(0.1, 3, 1.0, 1.0, 20), cam);  // the camera sees the ground 2-12 m ahead
  const std::optional<Segment2> c = regionCentreLine(mask, Image(), cam, 1);
  ASSERT_TRUE(c);
  EXPECT_NEAR(angleDeg(*c), 3.0, 0.2);
  EXPECT_NEAR(yAt(*c, 5), 0.1 + std::tan(degToRad(3)) * 5, 0.02);
  EXPECT_LT(c->a.x(), 2.2);  // from the bottom row's range ...
  EXPECT_GT(c->b.x(), 10);   // ... to the far rows'
  // On a grid of 4 x 4 pixel cells the same to a cell's rounding.
  Image coarse(mask.width / 4, mask.height / 4, 1);
  for (int y = 0; y < coarse.height; ++y)
    for (int x = 0; x < coarse.width; ++x) coarse.pixel(x, y)[0] = mask.pixel(4 * x + 2, 4 * y + 2)[0];
  const std::optional<Segment2> g = regionCentreLine(coarse, Image(), cam, 4);
  ASSERT_TRUE(g);
  EXPECT_NEAR(angleDeg(*g), 3.0, 0.5);
  EXPECT_NEAR(yAt(*g, 5), 0.1 + std::tan(degToRad(3)) * 5, 0.05);
}

// Near the vehicle a wide road fills the frame from side to side: those rows say nothing of its
// middle (a frame side is not a road edge) and give no point; the rows that show both edges do.
TEST(RegionCentreLine, RowsCutByTheFramesSidesGiveNoPoint) {
  const Camera& cam = pinhole();
  const Image mask = seen(band(-0.2, -3, 3, 1.0, 20), cam);  // both its edges in view from about 7.5 m
  ASSERT_EQ(mask.pixel(0, mask.height - 1)[0], 255);  // the bottom row is road from side to side
  ASSERT_EQ(mask.pixel(mask.width - 1, mask.height - 1)[0], 255);
  const std::optional<Segment2> c = regionCentreLine(mask, Image(), cam, 1);
  ASSERT_TRUE(c);
  EXPECT_NEAR(angleDeg(*c), -3.0, 0.3);
  EXPECT_NEAR(yAt(*c, 9), -0.2 - std::tan(degToRad(3)) * 9, 0.05);
  EXPECT_GT(c->a.x(), 6.0);  // its first point where both edges are in view
}

// Another region beside the road (a lawn patch the classifier took for road, not joined to it):
// the run followed up the image is the one continuing the road's, and the prediction picks the
// road's at the bottom where both start.
TEST(RegionCentreLine, TheRunThatContinuesTheRoadIsFollowedNotAPatchBesideIt) {
  const Camera& cam = pinhole();
  Image mask = seen(band(0, 0, 1, 1, 20), cam);
  const Image patch = seen({{4, 1}, {20, 1}, {20, 3}, {4, 3}}, cam);
  for (std::size_t i = 0; i < mask.data.size(); ++i) mask.data[i] |= patch.data[i];
  const Image predicted = seen(band(0, 0, 1, 1, 20), cam);
  const std::optional<Segment2> c = regionCentreLine(mask, predicted, cam, 1);
  ASSERT_TRUE(c);
  EXPECT_NEAR(angleDeg(*c), 0.0, 0.2);
  EXPECT_NEAR(yAt(*c, 6), 0.0, 0.02);
  // Without the prediction the widest run in the lowest row starts it: the road's (the patch begins
  // 4 m ahead).
  const std::optional<Segment2> unguided = regionCentreLine(mask, Image(), cam, 1);
  ASSERT_TRUE(unguided);
  EXPECT_NEAR(yAt(*unguided, 6), 0.0, 0.02);
}

TEST(RegionCentreLine, TooLittleRegionGivesNoneAndBadInputIsNamed) {
  const Camera& cam = pinhole();
  EXPECT_FALSE(regionCentreLine(Image(cam.width(), cam.height(), 1), Image(), cam, 1));  // no region
  EXPECT_FALSE(regionCentreLine(seen(band(0, 0, 1, 4, 5.5), cam), Image(), cam, 1));  // 1.5 m of road: under min_length_m
  CentreLineOptions strict;
  strict.min_rows = 100000;
  EXPECT_FALSE(regionCentreLine(seen(band(0, 0, 1, 1, 20), cam), Image(), cam, 1, strict));
  EXPECT_THROW(regionCentreLine(Image(4, 4, 3), Image(), cam, 1), InvalidInput);
  EXPECT_THROW(regionCentreLine(Image(4, 4, 1), Image(5, 4, 1), cam, 1), InvalidInput);
}

}  // namespace
}  // namespace mapnav
