// WorldOptions::texel_cache_mib: the ground's colour kept in world space across frames
// (sim/src/world_texels.h). Its frames do not depend on what the cache held, its masks and
// landmarks are the per-pixel renderer's, and its colours stay within the texels' interpolation
// of the per-pixel renderer's (the independent reference: texel_cache_mib 0).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "../../sim/src/world_texels.h"
#include "world_options_checks.h"
#include "mapnav/sim/world.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

WorldOptions texelsWorld(double mib) {
  WorldOptions o;
  o.shadow_density = 0.3;
  o.texel_cache_mib = mib;
  return o;
}

bool sameTexelFrame(const Frame& a, const Frame& b) {
  return a.rgb == b.rgb && a.mask == b.mask && a.landmark_mask == b.landmark_mask && a.landmarks.size() == b.landmarks.size();
}

TEST(WorldTexels, AFrameDoesNotDependOnWhatTheCacheHeld) {
  const auto cam = testing::terregatorCamera(LensModel::Pinhole, 160, 150);
  const Pose2 here(53, 40, 0), there(80, 40.5, 0.3), away(20, 2, -1.2);
  const World world(testing::campusMap(), texelsWorld(64));
  const Frame cold = world.render(*cam, here, 1.0);
  // After other frames, with the tiles of this one cached and others beside them.
  world.render(*cam, there, 2.0);
  world.render(*cam, away, 3.0);
  EXPECT_TRUE(sameTexelFrame(world.render(*cam, here, 1.0), cold));
  // A cache of one tile drops every tile as soon as the next is shaded.
  const World tiny(testing::campusMap(), texelsWorld(1e-6));
  tiny.render(*cam, there, 2.0);
  EXPECT_TRUE(sameTexelFrame(tiny.render(*cam, here, 1.0), cold));
  // Bands of rows on three threads share the cache and shade tiles side by side.
  WorldOptions three = texelsWorld(64);
  three.threads = 3;
  EXPECT_TRUE(sameTexelFrame(World(testing::campusMap(), three).render(*cam, here, 1.0), cold));
}

// Frames of the bench scene (a tree's, a pole's and a bench's shadows, seeded canopies) and of a
// manhole cover, against the per-pixel renderer's.
TEST(WorldTexels, MasksAreThePerPixelRenderersAndColoursWithinTheTexelsInterpolation) {
  const auto cam = testing::terregatorPinhole();
  const World texels(testing::campusMap(), texelsWorld(64)), exact(testing::campusMap(), texelsWorld(0));
  for (const Pose2& pose : {Pose2(53, 40, 0), Pose2(74, 40, 0.02), Pose2(48.5, 45, 1.5)}) {
    const Frame f = texels.render(*cam, pose, 0.0), g = exact.render(*cam, pose, 0.0);
    EXPECT_TRUE(f.mask == g.mask);
    EXPECT_TRUE(f.landmark_mask == g.landmark_mask);
    ASSERT_EQ(f.landmarks.size(), g.landmarks.size());
    for (std::size_t k = 0; k < f.landmarks.size(); ++k) {
      EXPECT_EQ(f.landmarks[k].index, g.landmarks[k].index);
      EXPECT_EQ(f.landmarks[k].pixels, g.landmarks[k].pixels);
    }
    std::vector<int> d(f.rgb.data.size());
    double sum = 0;
    for (std::size_t k = 0; k < d.size(); ++k) {
      d[k] = std::abs(int{f.rgb.data[k]} - int{g.rgb.data[k]});
      sum += d[k];
    }
    std::sort(d.begin(), d.end());
    const double mean = sum / static_cast<double>(d.size());
    const int p99 = d[d.size() * 99 / 100];
    std::printf("pose (%.1f, %.1f, %.2f): |texels − per pixel| mean %.3f, 99th percentile %d, max %d levels\n", pose.x(),
                pose.y(), pose.heading(), mean, p99, d.back());
    EXPECT_LT(mean, 1.5);
    EXPECT_LE(p99, 14);
  }
}

// A pixel of footprint f reads level L with s_L ≤ f < 2 s_L and level L + 1, the second's weight
// rising from 0 to 1 over the middle quarter of the octave.
TEST(WorldTexels, LevelsBracketTheFootprint) {
  using world_detail::kTexel0;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> log2f(-9.5, 12.0);  // 1.4 mm … 4 m
  for (int i = 0; i < 10000; ++i) {
    const double f = kTexel0 * std::exp2(log2f(rng));
    const world_detail::TexelLod lod = world_detail::texelLod(f);
    const double s = std::ldexp(kTexel0, lod.level);
    const double x = f / s - 1;  // where f lies in the octave
    if (f < kTexel0) {
      EXPECT_EQ(lod.level, 0);
      EXPECT_EQ(lod.mix, 0.0f);
      continue;
    }
    ASSERT_LE(s, f);
    ASSERT_LT(f, 2 * s);
    EXPECT_NEAR(lod.mix, std::clamp(4 * x - 1.5, 0.0, 1.0), 1e-6) << f;
  }
  EXPECT_EQ(world_detail::texelLod(kTexel0 * 1.37).mix, 0.0f);
  EXPECT_EQ(world_detail::texelLod(kTexel0 * 1.63).mix, 1.0f);
  EXPECT_FLOAT_EQ(world_detail::texelLod(kTexel0 * 1.5).mix, 0.5f);
  EXPECT_EQ(world_detail::texelLod(kTexel0 * 5).level, 2);  // 4 ≤ 5 < 8
}

TEST(WorldTexels, TheCacheDropsTheLeastRecentlyUsedBeyondItsBudget) {
  using world_detail::texelKey;
  world_detail::TexelCache cache(2);
  const auto tile = [] { return std::make_shared<world_detail::TexelTile>(); };
  const std::uint64_t a = texelKey(3, -1, 2), b = texelKey(3, 0, 2), c = texelKey(4, -1, 2);
  EXPECT_NE(a, b);
  EXPECT_NE(a, c);
  cache.insert(a, tile());
  cache.insert(b, tile());
  cache.endFrame();
  ASSERT_TRUE(cache.find(a));  // used again in the next frame: b is now the least recent
  cache.insert(c, tile());
  cache.endFrame();
  EXPECT_EQ(cache.size(), 2u);
  EXPECT_TRUE(cache.find(a));
  EXPECT_FALSE(cache.find(b));
  EXPECT_TRUE(cache.find(c));
  // A tile stored twice keeps the first (two threads shading one tile store the same values).
  const auto first = cache.find(a);
  EXPECT_EQ(cache.insert(a, tile()), first);
}

TEST(WorldTexels, BadBudgetsAreNamed) {
  for (const double bad : {-1.0, std::nan(""), 2e6}) {
    WorldOptions o;
    o.texel_cache_mib = bad;
    EXPECT_TRUE(simtest::rejectedNaming(o, "texel_cache_mib")) << bad;
  }
  EXPECT_EQ(simtest::readsGoodAndNamesBad("texel_cache_mib", "32", "-3").texel_cache_mib, 32.0);
}

}  // namespace
}  // namespace mapnav
