#include <gtest/gtest.h>

#include <cmath>
#include <span>

#include "map_fixtures.h"
#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/image/png.h"
#include "mapnav/map/info.h"
#include "mapnav/map/map_render.h"
#include "mapnav/map/predict_render.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

TEST(DescribeMap, CountsLengthsAndBoundsOfTheCross) {
  const MapInfo info = describeMap(Map(testing::crossOfFourRoads()));
  EXPECT_EQ(info.intersections, 5u);
  EXPECT_EQ(info.roads, 4u);
  EXPECT_EQ(info.intersections_by_kind.at("cross"), 1u);
  EXPECT_EQ(info.intersections_by_kind.at("end"), 4u);
  EXPECT_EQ(info.roads_by_surface.at("concrete"), 4u);
  EXPECT_DOUBLE_EQ(info.total_length_m, 80.0);
  EXPECT_DOUBLE_EQ(info.paved_area_m2, 160.0);
  EXPECT_EQ(info.components, 1u);
  const Json j = Json::parse(toJson(info));
  EXPECT_EQ(j["total_length_m"], 80.0);
  EXPECT_EQ(j["bounds"]["min"][0], -21.0);
  EXPECT_NE(toText(info).find("total length:  80.0 m"), std::string::npos);
}

TEST(DescribeMap, CountsLandmarksByKind) {
  MapData data = testing::crossWithOneLandmarkOfEachKind();
  data.landmarks.push_back({"T2", LandmarkKind::Tree, Vec2(3, 12), 0.2, 7.0, "", {}});
  const MapInfo info = describeMap(Map(data));
  EXPECT_EQ(info.landmarks, 6u);
  EXPECT_EQ(info.landmarks_by_kind,
            (std::map<std::string, std::size_t>{{"bench", 1}, {"bollard", 1}, {"manhole", 1}, {"pole", 1}, {"tree", 2}}));
  EXPECT_NE(toText(info).find("\nlandmarks:     6 (bench 1, bollard 1, manhole 1, pole 1, tree 2)\n"), std::string::npos)
      << toText(info);
  const Json j = Json::parse(toJson(info));
  EXPECT_EQ(j["landmarks"], 6);
  EXPECT_EQ(j["landmarks_by_kind"]["tree"], 2);
  EXPECT_NE(toText(describeMap(Map(testing::crossOfFourRoads()))).find("\nlandmarks:     0\n"), std::string::npos);
}

// The map drawn 800 px wide without labels, as a PNG decoded again, for reading its pixels.
struct RenderedMap {
  MapPicture picture;
  Image image;
  /// The colour of the pixel at a world point.
  Vec3 rgbAt(const Vec2& world) const {
    const Vec2 px = picture.view.toPixel(world);
    const std::uint8_t* rgb = image.pixel(static_cast<int>(std::lround(px.x())), static_cast<int>(std::lround(px.y())));
    return Vec3(rgb[0], rgb[1], rgb[2]);
  }
};

RenderedMap renderAt800(const Map& map) {
  MapRenderOptions options;
  options.width_px = 800;
  options.labels = false;
  MapPicture picture = renderMap(map, options);
  const std::string png = picture.canvas.toPng();
  Image image = decodePng(std::span(reinterpret_cast<const std::uint8_t*>(png.data()), png.size()), "map");
  return {std::move(picture), std::move(image)};
}

::testing::AssertionResult colourNear(const Vec3& actual, render::Rgb expected, double tolerance = 4.0) {
  const Vec3 want(expected.r, expected.g, expected.b);
  if ((actual - want).cwiseAbs().maxCoeff() <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "colour (" << actual.transpose() << "), expected (" << want.transpose() << ")";
}

TEST(RenderMap, RoadsArePaintedInTheirSurfaceColourOnTheShoulderGround) {
  const Map map(testing::crossOfFourRoads());
  const RenderedMap rendered = renderAt800(map);
  const MapPicture& picture = rendered.picture;
  const Image& image = rendered.image;
  EXPECT_EQ(picture.canvas.width(), 800);
  ASSERT_EQ(image.channels, 3);
  EXPECT_EQ(image.width, 800);
  EXPECT_EQ(image.height, picture.canvas.height());
  auto rgbAt = [&](const Vec2& world) { return rendered.rgbAt(world); };
  // On R1, 0.6 m left of the dashed centre line: concrete (178, 176, 168).
  EXPECT_LT((rgbAt(Vec2(15, 0.6)) - Vec3(178, 176, 168)).cwiseAbs().maxCoeff(), 4.0);
  // Far from every road: the lightened grass ground, green above red and blue.
  const Vec3 ground = rgbAt(Vec2(15, 15));
  EXPECT_GT(ground.y(), ground.x());
  EXPECT_GT(ground.y(), ground.z());
  // North up: R2 (to the north) is above the centre in the picture.
  EXPECT_LT(picture.view.toPixel(Vec2(0, 10)).y(), picture.view.toPixel(Vec2(0, 0)).y());
}

// Each landmark of crossWithOneLandmarkOfEachKind() in its colour where it stands (about
// 16 px a metre here, so each symbol is several pixels across).
TEST(RenderMap, LandmarksPutTheirColoursWhereTheyStand) {
  const RenderedMap rendered = renderAt800(Map(testing::crossWithOneLandmarkOfEachKind()));
  ASSERT_GT(rendered.picture.view.pixelsPerMetre(), 12.0);
  // T1 at (−3, 12): the trunk's dark dot (0.25 m) at its foot, the green crown (8 m / 3) 1.5 m north.
  EXPECT_TRUE(colourNear(rendered.rgbAt(Vec2(-3, 12)), kTreeTrunk));
  const Vec3 crown = rendered.rgbAt(Vec2(-3, 13.5));
  EXPECT_TRUE(colourNear(crown, kTreeCrown));
  EXPECT_GT(crown.y(), crown.x() + 60) << "green";
  EXPECT_TRUE(colourNear(rendered.rgbAt(Vec2(10, 2)), kPole));
  EXPECT_TRUE(colourNear(rendered.rgbAt(Vec2(2, -6)), kBollard));
  EXPECT_TRUE(colourNear(rendered.rgbAt(Vec2(15, 0)), kManhole));
  // B1 at (−12, −2.5), 0.8 m each way along R3 (east–west): brown 0.5 m east of its centre, not
  // 0.5 m north of it (a bar a quarter metre either side of the line).
  EXPECT_TRUE(colourNear(rendered.rgbAt(Vec2(-11.5, -2.5)), kBench));
  EXPECT_FALSE(colourNear(rendered.rgbAt(Vec2(-12, -2.0)), kBench));
}

TEST(MapRenderOptions, DefaultsAreValidAndBadValuesAreNamed) {
  EXPECT_NO_THROW(MapRenderOptions{}.validate());
  MapRenderOptions options;
  options.width_px = 10;
  EXPECT_THROW(options.validate(), Error);
  options = {};
  options.margin_px = 800;  // half the width
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { options.validate(); },
                                                "MapRenderOptions::margin_px = 800: must be < width_px / 2"));
  PredictionPictureOptions picture;
  picture.panel_px = 99;
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { picture.validate(); },
                                                "PredictionPictureOptions::panel_px = 99: must be in [100, 4000]"));
}

}  // namespace
}  // namespace mapnav
