#include "world_options_checks.h"
#include "mapnav/sim/world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "mapnav/core/error.h"
#include "mapnav/geometry/polygon.h"
#include "mapnav/image/png.h"
#include "mapnav/map/map_io.h"
#include "mapnav/sim/world_io.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

// The Terregator cameras of maps/cameras/, at 512 × 512.
std::unique_ptr<Camera> pinhole512() { return testing::terregatorCamera(LensModel::Pinhole, 512, 512); }
std::unique_ptr<Camera> fisheye512() { return testing::terregatorCamera(LensModel::PaperFisheye, 512, 512); }

// Without its landmarks (testing::withoutLandmarks): the world's own tests render roads and shadows.
const Map& campus() { return testing::campusWithoutLandmarks(); }

// Independent of the renderer's grid: backproject every pixel with the camera and test the map's own
// polygons with the exact mapnav::contains. Only ground within `range` m of the vehicle counts.
double maskIoU(const Frame& frame, const Camera& camera, const Map& map, const Pose2& pose, double range) {
  std::vector<std::pair<Polygon2, Box2>> polys;
  auto add = [&](Polygon2 ring) {
    Box2 box;
    for (const Vec2& v : ring) box.extend(v);
    polys.emplace_back(std::move(ring), box);
  };
  for (const Road& road : map.roads()) add(map.roadPolygon(road));
  for (const Intersection& in : map.intersections()) add(map.intersectionShape(in));
  long inter = 0, uni = 0;
  for (int v = 0; v < camera.height(); ++v) {
    for (int u = 0; u < camera.width(); ++u) {
      const auto g = camera.backproject(Vec2(u, v));
      if (!g || g->norm() > range) continue;
      const Vec2 p = pose.transform(*g);
      bool truth = false;
      for (const auto& [ring, box] : polys) {
        if (box.contains(p) && contains(ring, p)) {
          truth = true;
          break;
        }
      }
      const bool rendered = frame.mask.pixel(u, v)[0] == 255;
      inter += (truth && rendered) ? 1 : 0;
      uni += (truth || rendered) ? 1 : 0;
    }
  }
  EXPECT_GT(uni, 1000) << "too little road in view to measure";
  return uni == 0 ? 0.0 : static_cast<double>(inter) / static_cast<double>(uni);
}

TEST(World, RenderedMaskMatchesTheMapsPolygons) {
  const World world(campus());
  const auto pin = pinhole512();
  const auto fish = fisheye512();
  // The dialogue's start on R1 near I1 looking east; the cross at I11 ahead; the plaza I14; R2 north.
  const std::vector<Pose2> poses{Pose2(53, 40, 0), Pose2(92, 40.5, 0.05), Pose2(91, 79, 0.3), Pose2(50.4, 55, kPi / 2)};
  for (const Pose2& pose : poses) {
    for (const Camera* camera : {pin.get(), fish.get()}) {
      const Frame frame = world.render(*camera, pose, 0.0);
      ASSERT_EQ(frame.mask.channels, 1);
      ASSERT_EQ(frame.rgb.channels, 3);
      const double iou = maskIoU(frame, *camera, campus(), pose, 30.0);
      std::printf("IoU %s at (%.1f, %.1f, %.2f): %.5f\n", std::string(toString(camera->model())).c_str(), pose.x(),
                  pose.y(), pose.heading(), iou);
      EXPECT_GE(iou, 0.99) << toString(camera->model()) << " at " << pose.x() << ", " << pose.y();
    }
  }
}

TEST(World, MaskIsZeroOnSkyAndOutsideTheLens) {
  const World world(campus());
  const auto fish = fisheye512();
  const Frame frame = world.render(*fish, Pose2(53, 40, 0), 0.0);
  EXPECT_EQ(frame.mask.pixel(0, 0)[0], 0);      // a corner: outside the fish-eye's circle
  EXPECT_EQ(frame.rgb.pixel(0, 0)[0], 0);
  EXPECT_EQ(frame.mask.pixel(256, 60)[0], 0);   // above the horizon (v ≈ 168): sky
  EXPECT_GT(frame.rgb.pixel(256, 60)[2], 150);  // and the sky is blue-ish bright
}

TEST(World, RenderIsDeterministicAndSeeded) {
  const auto pin = pinhole512();
  const Pose2 pose(53, 40, 0);
  WorldOptions a;
  a.shadow_density = 0.4;
  a.leaf_density = 0.05;
  const Frame f1 = World(campus(), a).render(*pin, pose, 3.0);
  const Frame f2 = World(campus(), a).render(*pin, pose, 3.0);
  EXPECT_TRUE(f1.rgb == f2.rgb);
  EXPECT_TRUE(f1.mask == f2.mask);
  // The cached ray table and an explicit one agree.
  const World world(campus(), a);
  const RayTable table(*pin);
  EXPECT_TRUE(world.render(table, pose, 3.0).rgb == f1.rgb);
  EXPECT_TRUE(world.render(*pin, pose, 3.0).rgb == f1.rgb);
  WorldOptions b = a;
  b.seed = 2;
  const Frame f3 = World(campus(), b).render(*pin, pose, 3.0);
  EXPECT_FALSE(f1.rgb == f3.rgb);
  EXPECT_TRUE(f1.mask == f3.mask);  // the ground truth does not depend on the seed
  // Without sensor noise a different seed still changes the texture.
  a.noise_sigma = 0;
  b.noise_sigma = 0;
  const Frame g1 = World(campus(), a).render(*pin, pose, 3.0);
  const Frame g2 = World(campus(), b).render(*pin, pose, 3.0);
  long differing = 0;
  for (std::size_t i = 0; i < g1.rgb.data.size(); ++i) differing += g1.rgb.data[i] != g2.rgb.data[i] ? 1 : 0;
  EXPECT_GT(differing, static_cast<long>(g1.rgb.data.size() / 4));
}

// Isolate the shadow: no noise, no drift (t = 0), no leaves, no haze.
WorldOptions shadowTestOptions(double density, double blue) {
  WorldOptions o;
  o.noise_sigma = 0;
  o.leaf_density = 0;
  o.haze_distance_m = 0;
  o.shadow_density = density;
  o.shadow_blue_shift = blue;
  return o;
}

TEST(World, ShadowedColourIsKTimesSunlit) {
  const auto pin = pinhole512();
  const Pose2 pose(53, 40, 0);
  for (double blue : {0.0, 0.12}) {
    const WorldOptions sun_opts = shadowTestOptions(0.0, blue);
    const WorldOptions shade_opts = shadowTestOptions(1.0, blue);
    const Frame sun = World(campus(), sun_opts).render(*pin, pose, 0.0);
    const Frame shade = World(campus(), shade_opts).render(*pin, pose, 0.0);
    const double k = shade_opts.shadow_k;
    const std::array<double, 3> tint{1 - blue, 1, 1 + blue};
    long road = 0;
    double worst = 0;
    for (int v = 0; v < 512; ++v) {
      for (int u = 0; u < 512; ++u) {
        if (sun.mask.pixel(u, v)[0] != 255) continue;
        ++road;
        for (int c = 0; c < 3; ++c) {
          const double expected = k * tint[static_cast<std::size_t>(c)] * sun.rgb.pixel(u, v)[c];
          worst = std::max(worst, std::abs(shade.rgb.pixel(u, v)[c] - expected));
        }
      }
    }
    ASSERT_GT(road, 20000);
    // Both frames are rounded to whole levels: |error| ≤ 0.5 + k(1 + b)·0.5 < 1.
    EXPECT_LE(worst, 1.0) << "blue shift " << blue;
  }
}

TEST(World, PartialShadowsDarkenSomeOfTheGround) {
  const auto pin = pinhole512();
  const Frame sun = World(campus(), shadowTestOptions(0.0, 0.12)).render(*pin, Pose2(53, 40, 0), 0.0);
  const Frame some = World(campus(), shadowTestOptions(0.6, 0.12)).render(*pin, Pose2(53, 40, 0), 0.0);
  long darker = 0, total = 0;
  for (int v = 0; v < 512; ++v)
    for (int u = 0; u < 512; ++u) {
      ++total;
      darker += some.rgb.pixel(u, v)[1] < 0.7 * sun.rgb.pixel(u, v)[1] ? 1 : 0;
    }
  EXPECT_GT(darker, total / 20);
  EXPECT_LT(darker, total);
}

TEST(World, LowDynamicRangeCapsTheRatioAtSeven) {
  const auto fish = fisheye512();
  WorldOptions o;
  o.low_dynamic_range = true;
  o.shadow_density = 0.6;
  o.noise_sigma = 4;
  const Frame f = World(campus(), o).render(*fish, Pose2(53, 40, 0), 10.0);
  const auto [lo, hi] = std::minmax_element(f.rgb.data.begin(), f.rgb.data.end());
  ASSERT_GT(*lo, 0);
  EXPECT_LE(static_cast<double>(*hi) / static_cast<double>(*lo), 7.0);
  // Without the option the same scene spans a wider range.
  o.low_dynamic_range = false;
  const Frame g = World(campus(), o).render(*fish, Pose2(53, 40, 0), 10.0);
  const auto [glo, ghi] = std::minmax_element(g.rgb.data.begin(), g.rgb.data.end());
  EXPECT_GT(static_cast<double>(*ghi), 7.0 * std::max<double>(*glo, 1.0));
}

TEST(World, TvColourShiftChangesChromaNotTheMask) {
  const auto pin = pinhole512();
  WorldOptions o;
  o.noise_sigma = 0;
  const Frame plain = World(campus(), o).render(*pin, Pose2(53, 40, 0), 0.0);
  o.tv_color_shift = true;
  const Frame tv = World(campus(), o).render(*pin, Pose2(53, 40, 0), 0.0);
  EXPECT_TRUE(plain.mask == tv.mask);
  EXPECT_FALSE(plain.rgb == tv.rgb);
}

TEST(World, IlluminationDriftsSlowlyWithTime) {
  const auto pin = pinhole512();
  WorldOptions o;
  o.noise_sigma = 0;
  const World world(campus(), o);
  auto mean = [](const Frame& f) {
    double s = 0;
    for (std::uint8_t b : f.rgb.data) s += b;
    return s / static_cast<double>(f.rgb.data.size());
  };
  const double m0 = mean(world.render(*pin, Pose2(53, 40, 0), 0.0));
  const double m1 = mean(world.render(*pin, Pose2(53, 40, 0), 1.0));
  const double mq = mean(world.render(*pin, Pose2(53, 40, 0), o.illumination_period_s / 4));
  EXPECT_NEAR(m1, m0, 0.01 * m0);  // a second changes little
  EXPECT_GT(mq, m0 * (1 + o.illumination_drift / 2));
}

TEST(WorldOptions, DefaultsAreValidAndBadValuesAreNamed) {
  EXPECT_NO_THROW(WorldOptions{}.validate());
  WorldOptions o;
  o.shadow_k = 0;
  EXPECT_TRUE(simtest::rejectedNaming(o, "shadow_k"));
  o = {};
  o.shadow_density = 1.5;
  EXPECT_TRUE(simtest::rejectedNaming(o, "shadow_density"));
  o = {};
  o.noise_sigma = -1;
  EXPECT_TRUE(simtest::rejectedNaming(o, "noise_sigma"));
  o = {};
  o.illumination_period_s = 0;
  EXPECT_TRUE(simtest::rejectedNaming(o, "illumination_period_s"));
  o = {};
  o.slab_gap_width_m = std::nan("");
  EXPECT_TRUE(simtest::rejectedNaming(o, "slab_gap_width_m"));
  o = {};
  o.leaf_density = -0.1;
  EXPECT_TRUE(simtest::rejectedNaming(o, "leaf_density"));
  o = {};
  o.tv_chroma_blur_px = -1;
  EXPECT_TRUE(simtest::rejectedNaming(o, "tv_chroma_blur_px"));
  o = {};
  o.paved_edge_samples = 0;
  EXPECT_TRUE(simtest::rejectedNaming(o, "paved_edge_samples"));
  o = {};
  o.paved_edge_samples = 17;
  EXPECT_TRUE(simtest::rejectedNaming(o, "paved_edge_samples"));
  EXPECT_EQ(simtest::readsGoodAndNamesBad("paved_edge_samples", "4", "0").paved_edge_samples, 4);
  o = {};
  o.shadow_blue_shift = 1;
  EXPECT_TRUE(simtest::rejectedNaming(o, "shadow_blue_shift"));
  o = {};
  o.shadow_k = 2;
  EXPECT_THROW(World(campus(), o), InvalidInput);
}

TEST(WorldOptions, TheRulesAreTheTablesAndTheirMessagesSayThem) {
  WorldOptions o;
  o.pavement_noise = 2000;  // the rule was always [0, 1000]; its message said ">= 0"
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { o.validate(); },
                                                "WorldOptions::pavement_noise = 2000: must be in [0, 1000]"));
  o = {};
  o.sun_elevation_rad = 2;
  EXPECT_TRUE(testing::throwsInvalidInputNaming(
      [&] { o.validate(); }, "WorldOptions::sun_elevation_rad = 2: must be in [0.1, 1.5707963267948966]"));
  o = {};
  o.illumination_drift = 1;
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { o.validate(); },
                                                "WorldOptions::illumination_drift = 1: must be in [0, 1)"));
  const std::vector<OptionInfo> list = worldOptionTable().list();
  ASSERT_EQ(list.size(), 28u);  // every field, seed first
  EXPECT_EQ(list.front().name, "seed");
  EXPECT_EQ(list.front().default_json, "1");
}

TEST(WorldOptions, TheWorldBlockNamesEveryBadMemberAtItsPointer) {
  Issues issues;
  const WorldOptions o = parseWorldOptions(
      R"({"seed": 9, "shadow_k": 2, "paved_edge_samples": 2.5, "dust": "x", "shadw": 1, "x-note": "fine", "leaf_density": 0.5})",
      "/world", issues);
  ASSERT_EQ(issues.size(), 4u);  // in the block's order
  EXPECT_EQ(issues[0], (Issue{Severity::Error, "schema.range", "/world/shadow_k", "option shadow_k = 2: must be in (0, 1]"}));
  EXPECT_EQ(issues[1], (Issue{Severity::Error, "schema.type", "/world/paved_edge_samples",
                              "option paved_edge_samples = 2.5: must be an integer"}));  // no longer rounded to 3
  EXPECT_EQ(issues[2], (Issue{Severity::Error, "schema.type", "/world/dust", "option dust = \"x\": must be a number"}));
  EXPECT_EQ(issues[3], (Issue{Severity::Error, "schema.unknown_field", "/world/shadw", "unknown option \"shadw\""}));
  EXPECT_EQ(o.seed, 9u);  // the good members apply
  EXPECT_EQ(o.leaf_density, 0.5);
  issues.clear();
  parseWorldOptions(R"({"seed": -1})", "/world", issues);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0], (Issue{Severity::Error, "schema.range", "/world/seed",
                              "option seed = -1: must be an integer in [0, 9007199254740992]"}));
  issues.clear();
  parseWorldOptions("{\"seed\": 1,\n \"dust\": }", "/world", issues);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].check, "json.syntax");
  EXPECT_EQ(issues[0].line, 2);
}

// A straight 3 m asphalt road between grass along the world's x axis, every texture, shadow, drift and
// noise off: the pavement and the lawn each one flat colour (the lawn's worn strip changes over
// decimetres, not within a pixel).
struct FlatRoad {
  Map map;
  WorldOptions options;
};
FlatRoad flatRoad(int paved_edge_samples) {
  MapData data = testing::straightRoad("flat road", 80, 3.0, "asphalt", "grass");
  data.surfaces = loadMap(testing::mapPath("park_path.json")).data().surfaces;
  WorldOptions o;
  o.pavement_noise = o.ground_noise = o.crack_density = o.dust = o.shadow_density = o.leaf_density = 0;
  o.slab_spacing_m = o.illumination_drift = o.white_balance_drift = o.haze_distance_m = o.noise_sigma = 0;
  o.paved_edge_samples = paved_edge_samples;
  return {Map(data, "flat road"), o};
}

// Area sampling at the paved area's edge: the two pixels either side of a class change in a row hold,
// between them, as much asphalt as the true edge leaves them. Measured per edge crossing against the
// edge projected by the camera (independent of the renderer's ray table): the asphalt in the pair
// from their colours, each pixel's fraction along the grass-to-asphalt colour of the pure pixels
// beside the pair. Sampled at the centre alone, the pair holds one pixel of asphalt whatever the
// edge's phase: an error uniform in ±0.5 px (RMS 0.29).
TEST(World, PavedEdgePixelsMixBothSurfacesByTheirArea) {
  const auto cam = pinhole512();
  const Pose2 pose(5.0, 0.3, degToRad(3.0));  // the edges cross the columns at every phase
  // The true edge's column at the centre of row v: the ground point of that row on the edge line
  // y = ±1.5, by bisection on the distance ahead.
  const auto edgeColumn = [&](double y, int v) -> std::optional<double> {
    double lo = pose.x() + 1.0, hi = pose.x() + 60.0;
    const auto at = [&](double x) { return cam->projectGround(pose.inverseTransform(Vec2(x, y))); };
    const auto plo = at(lo), phi = at(hi);
    if (!plo || !phi || !(plo->y() > v && phi->y() < v)) return std::nullopt;
    for (int it = 0; it < 60; ++it) {
      const double mid = 0.5 * (lo + hi);
      const auto p = at(mid);
      if (!p) return std::nullopt;
      (p->y() > v ? lo : hi) = mid;
    }
    return at(0.5 * (lo + hi))->x();
  };
  for (const int samples : {1, 4}) {
    const FlatRoad fr = flatRoad(samples);
    const World world(fr.map, fr.options);
    const Frame f = world.render(*cam, pose, 0.0);
    const auto paved = [&](int u, int v) { return f.mask.pixel(u, v)[0] == 255; };
    double sum2 = 0, worst = 0;
    int n = 0;
    for (int v = 0; v < f.rgb.height; ++v) {
      for (int u = 3; u + 2 < f.rgb.width; ++u) {
        const bool road_right = paved(u, v);
        if (paved(u - 1, v) == road_right) continue;
        // The pure pixels beside the pair, two away: grass on one side, asphalt on the other.
        const int g = road_right ? u - 2 : u + 1, r = road_right ? u + 1 : u - 2;
        if (paved(g, v) || !paved(r, v)) continue;
        double asphalt = 0;  // in the pair, px
        for (const int k : {u - 1, u}) {
          double num = 0, den = 0;
          for (int c = 0; c < 3; ++c) {
            const double d = f.rgb.pixel(r, v)[c] - f.rgb.pixel(g, v)[c];
            num += (f.rgb.pixel(k, v)[c] - f.rgb.pixel(g, v)[c]) * d;
            den += d * d;
          }
          asphalt += num / den;
        }
        // The true edge through the pair (the nearer of the road's two), and the asphalt it leaves
        // the pair's columns [u − 1.5, u + 0.5].
        std::optional<double> ue;
        for (const double y : {-1.5, 1.5})
          if (const auto c = edgeColumn(y, v); c && (!ue || std::abs(*c - (u - 0.5)) < std::abs(*ue - (u - 0.5)))) ue = c;
        ASSERT_TRUE(ue) << "row " << v;
        ASSERT_LE(std::abs(*ue - (u - 0.5)), 0.5) << "row " << v << ": the class change is not at the true edge";
        const double truth = road_right ? u + 0.5 - *ue : *ue - (u - 1.5);
        const double err = asphalt - truth;
        sum2 += err * err;
        worst = std::max(worst, std::abs(err));
        ++n;
      }
    }
    const double rms = std::sqrt(sum2 / n);
    std::printf("paved_edge_samples %d: %d edge crossings, the asphalt in the pair off the true edge's by RMS %.3f px, "
                "worst %.3f px\n",
                samples, n, rms, worst);
    ASSERT_GE(n, 300);
    if (samples == 1) {
      // A whole pixel of asphalt in the pair wherever the edge is: uniform quantisation, RMS 1/√12.
      EXPECT_NEAR(rms, 1 / std::sqrt(12.0), 0.03);
      EXPECT_GT(worst, 0.45);
    } else {
      EXPECT_LT(rms, 0.05);
      EXPECT_LT(worst, 0.15);
    }
  }
}

// Pictures for people: run with --gtest_also_run_disabled_tests; writes /tmp/world_*.png.
TEST(World, DISABLED_WritePictures) {
  const auto pin = pinhole512();
  const auto fish = fisheye512();
  const World world(campus());
  writePng(world.render(*pin, Pose2(53, 40, 0), 0.0).rgb, "/tmp/world_campus_pinhole.png");
  writePng(world.render(*pin, Pose2(53, 40, 0), 0.0).mask, "/tmp/world_campus_pinhole_mask.png");
  writePng(world.render(*fish, Pose2(53, 40, 0), 0.0).rgb, "/tmp/world_campus_fisheye.png");
  const Map park = loadMap(testing::mapPath("park_path.json"));
  WorldOptions po;
  po.shadow_density = 0.55;
  po.leaf_density = 0.06;
  const World park_world(park, po);
  const Road& r1 = park.road("R1");
  for (double s : {20.0, 60.0, 110.0}) {
    const Vec2 p = r1.centerline.pointAt(s);
    const Pose2 pose(p, r1.centerline.headingAt(s));
    char name[64];
    std::snprintf(name, sizeof name, "/tmp/world_park_%03d.png", static_cast<int>(s));
    writePng(park_world.render(*pin, pose, s).rgb, name);
  }
  const Vec2 p = r1.centerline.pointAt(60.0);
  writePng(park_world.render(*fish, Pose2(p, r1.centerline.headingAt(60.0)), 60).rgb, "/tmp/world_park_fisheye.png");
  WorldOptions tv = po;
  tv.tv_color_shift = true;
  tv.low_dynamic_range = true;
  writePng(World(park, tv).render(*pin, Pose2(p, r1.centerline.headingAt(60.0)), 60).rgb, "/tmp/world_park_tv_ldr.png");
}

}  // namespace
}  // namespace mapnav
