// The suite of unseen maps: the random campus generator (map/random_campus.h).
#include "mapnav/map/random_campus.h"

#include <gtest/gtest.h>

#include <set>

#include "mapnav/core/error.h"
#include "mapnav/map/map_io.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

// Seeds 1..30 (the suite's fixed list): each a valid map with the junctions it says, the spine's
// roads and branches as drawn, widths in [1.5, 4] m, one family of surfaces, its mission's positions
// on its roads; every junction kind occurs over the 30.
TEST(RandomCampus, ThirtySeedsGiveValidMapsOfEveryJunctionKind) {
  std::set<IntersectionKind> kinds;
  std::size_t with_via = 0, arcs = 0;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    RandomCampusOptions o;
    o.seed = seed;
    const RandomCampus c = makeRandomCampus(o);
    const Map map(c.map, "seed " + std::to_string(seed));
    ASSERT_EQ(c.junctions.size(), 3u) << seed;
    std::size_t branches = 0;
    for (const IntersectionKind k : c.junctions) {
      kinds.insert(k);
      branches += k == IntersectionKind::Cross ? 2 : k == IntersectionKind::L ? 0 : 1;
    }
    EXPECT_EQ(map.roads().size(), 4 + branches) << seed;
    std::set<std::string> surfaces;
    for (const Road& r : map.roads()) {
      EXPECT_GE(r.width, 1.5) << seed << " " << r.id;
      EXPECT_LE(r.width, 4.0) << seed << " " << r.id;
      surfaces.insert(r.surface);
      arcs += r.centerline.size() > 2;
    }
    const bool slabs = surfaces.count("concrete") + surfaces.count("brick") == surfaces.size();
    const bool park = surfaces.count("asphalt") + surfaces.count("gravel") == surfaces.size();
    EXPECT_TRUE(slabs || park) << seed;
    EXPECT_EQ(c.start, "S1@I0+5");
    EXPECT_EQ(c.goal.rfind("S4@J3+", 0), 0u) << c.goal;
    with_via += !c.via.empty();
    for (const std::string& v : c.via) EXPECT_EQ(v[0], 'B') << v;
  }
  EXPECT_EQ(kinds.size(), 4u);
  EXPECT_GT(with_via, 5u);
  EXPECT_GT(arcs, 5u);
}

TEST(RandomCampus, TheSameSeedGivesTheSameMapAnotherSeedAnother) {
  RandomCampusOptions o;
  o.seed = 7;
  const RandomCampus a = makeRandomCampus(o), b = makeRandomCampus(o);
  EXPECT_EQ(mapToJson(a.map), mapToJson(b.map));
  EXPECT_EQ(a.goal, b.goal);
  o.seed = 8;
  EXPECT_NE(mapToJson(makeRandomCampus(o).map), mapToJson(a.map));
}

TEST(RandomCampus, BadOptionsAreNamed) {
  RandomCampusOptions o;
  o.junctions = 0;
  EXPECT_THROW(makeRandomCampus(o), InvalidInput);
  o = {};
  o.max_width_m = 1.0;  // below min_width_m
  try {
    makeRandomCampus(o);
    ADD_FAILURE();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "RandomCampusOptions::max_width_m = 1: must be >= min_width_m");
  }
  o = {};
  o.min_branch_m = 12;  // not above 3 max_width_m
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { o.validate(); },
                                                "RandomCampusOptions::min_branch_m = 12: must be > 3 max_width_m"));
  o = {};
  o.min_width_m = 0;
  EXPECT_TRUE(testing::throwsInvalidInputNaming([&] { o.validate(); },
                                                "RandomCampusOptions::min_width_m = 0: must be finite and > 0"));
}

}  // namespace
}  // namespace mapnav
