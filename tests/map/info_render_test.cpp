#include <gtest/gtest.h>

#include <cmath>
#include <span>

#include "map_fixtures.h"
#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/image/png.h"
#include "mapnav/map/info.h"
#include "mapnav/map/map_render.h"

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

TEST(RenderMap, RoadsArePaintedInTheirSurfaceColourOnTheShoulderGround) {
  const Map map(testing::crossOfFourRoads());
  MapRenderOptions options;
  options.width_px = 800;
  options.labels = false;
  const MapPicture picture = renderMap(map, options);
  EXPECT_EQ(picture.canvas.width(), 800);
  const std::string png = picture.canvas.toPng();
  const Image image = decodePng(std::span(reinterpret_cast<const std::uint8_t*>(png.data()), png.size()), "map");
  ASSERT_EQ(image.channels, 3);
  EXPECT_EQ(image.width, 800);
  EXPECT_EQ(image.height, picture.canvas.height());
  auto rgbAt = [&](const Vec2& world) {
    const Vec2 px = picture.view.toPixel(world);
    const std::uint8_t* rgb = image.pixel(static_cast<int>(std::lround(px.x())), static_cast<int>(std::lround(px.y())));
    return Vec3(rgb[0], rgb[1], rgb[2]);
  };
  // On R1, 0.6 m left of the dashed centre line: concrete (178, 176, 168).
  EXPECT_LT((rgbAt(Vec2(15, 0.6)) - Vec3(178, 176, 168)).cwiseAbs().maxCoeff(), 4.0);
  // Far from every road: the lightened grass ground, green above red and blue.
  const Vec3 ground = rgbAt(Vec2(15, 15));
  EXPECT_GT(ground.y(), ground.x());
  EXPECT_GT(ground.y(), ground.z());
  // North up: R2 (to the north) is above the centre in the picture.
  EXPECT_LT(picture.view.toPixel(Vec2(0, 10)).y(), picture.view.toPixel(Vec2(0, 0)).y());
}

TEST(MapRenderOptions, DefaultsAreValid) {
  EXPECT_NO_THROW(MapRenderOptions{}.validate());
  MapRenderOptions options;
  options.width_px = 10;
  EXPECT_THROW(options.validate(), Error);
}

}  // namespace
}  // namespace mapnav
