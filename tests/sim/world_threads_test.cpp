// WorldOptions::threads: bands of rows rendered in parallel give the very frame one thread renders.
#include <gtest/gtest.h>

#include <string>

#include "world_options_checks.h"
#include "mapnav/sim/world.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

TEST(WorldThreads, EveryThreadCountRendersTheSameFrame) {
  // The fish-eye sees ground, sky and the black outside its circle; 97 rows do not split evenly.
  const auto cam = testing::terregatorCamera(LensModel::PaperFisheye, 160, 97);
  WorldOptions o;
  o.seed = 5;
  o.shadow_density = 0.4;
  o.leaf_density = 0.1;
  o.paved_edge_samples = 3;  // the edge pass reads the rows above and below a band
  o.tv_color_shift = true;   // the chroma blur runs along rows
  const Pose2 pose(53, 40, 0.3);
  const Frame one = World(testing::campusMap(), o).render(*cam, pose, 7.0);
  int paved = 0;
  for (std::uint8_t m : one.mask.data) paved += m == 255;
  EXPECT_GT(paved, 0);  // the frame shows the road: the bands have edges to re-sample
  for (int threads : {2, 3, 7, 0, 200}) {
    o.threads = threads;
    const Frame f = World(testing::campusMap(), o).render(*cam, pose, 7.0);
    EXPECT_TRUE(f.rgb == one.rgb) << threads << " threads";
    EXPECT_TRUE(f.mask == one.mask) << threads << " threads";
  }
}

TEST(WorldThreads, BadCountsAreNamed) {
  WorldOptions o;
  o.threads = -1;
  EXPECT_TRUE(simtest::rejectedNaming(o, "threads"));
  o.threads = 257;
  EXPECT_TRUE(simtest::rejectedNaming(o, "threads"));
  EXPECT_EQ(simtest::readsGoodAndNamesBad("threads", "2", "-3").threads, 2);
}

}  // namespace
}  // namespace mapnav
