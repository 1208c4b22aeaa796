// The park-mode road finder of Jochem & Baluja 1993 ("cluster-perceptron"), the paper's straight
// road model: the Hough's centre line (§5) against the truth, and the prior's window (prior_px).
// On simulator frames of maps/park_path.json (asphalt path between grass, dirt and gravel,
// shadow_density 0.4) seen by the Terregator pin-hole camera (512 x 480, 22 deg tilt) unless a test
// says otherwise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <utility>

#include "cluster_perceptron_test_util.h"
#include "mapnav/sim/world.h"

namespace mapnav {
namespace {

using namespace visiontest;

/// The road's centre line projected into the image: u = a + b v.
std::pair<double, double> truthLine(const RoadPose& sp) {
  double n = 0, sv = 0, su = 0, svv = 0, svu = 0;
  for (double d = -2.0; d <= 25.0; d += 0.25) {
    const Vec2 w = sp.road->centerline.pointAt(sp.s + d);
    const auto p = cam().projectGround(sp.pose.inverseTransform(w));
    if (!p || p->y() < -0.5 || p->y() > cam().height() - 0.5) continue;
    n += 1;
    sv += p->y();
    su += p->x();
    svv += p->y() * p->y();
    svu += p->y() * p->x();
  }
  const double b = (n * svu - sv * su) / (n * svv - sv * sv);
  return {(su - b * sv) / n, b};
}

// The Hough's two parameters (§5): the centre line's column at the top road row within 2 px of the
// truth, and its angle within 1 degree, on every straight frame. The offset at the bottom row is
// printed too: where the road fills the image's width there, it is extrapolated from the rows above.
TEST(ClusterPerceptron, HoughCentreLineOnStraightStretches) {
  const World world(parkScenery(), parkWorld());
  const auto poses = straightPoses(4.0);
  ASSERT_GE(poses.size(), 40u);
  double worst_top = 0, worst_bot = 0, worst_deg = 0, sum_top = 0, sum_deg = 0;
  int n = 0;
  std::optional<ClusterPerceptron> trained;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    // Retrained (reset()) on the first frame of each road: a new scene; frozen along the road (§6).
    if (i == 0 || poses[i].road != poses[i - 1].road) trained = trainedOn(world, poses[i].pose, static_cast<double>(i));
    const Frame f = world.render(cam(), poses[i].pose, static_cast<double>(i));
    const RoadFinding r = trained->find(f.rgb.data.data(), f.rgb.width, f.rgb.height, false);
    ASSERT_TRUE(r.ok) << r.reason;
    EXPECT_TRUE(r.refined) << "frame " << i;
    const auto [a, b] = truthLine(poses[i]);
    const Segment2& cl = r.centerline_image;
    const double e_top = std::abs(cl.a.x() - (a + b * cl.a.y()));
    const double e_bot = std::abs(cl.b.x() - (a + b * cl.b.y()));
    const double db = (cl.b.x() - cl.a.x()) / (cl.b.y() - cl.a.y());
    const double e_deg = std::abs(std::atan(db) - std::atan(b)) * 180.0 / std::numbers::pi;
    worst_top = std::max(worst_top, e_top);
    worst_bot = std::max(worst_bot, e_bot);
    worst_deg = std::max(worst_deg, e_deg);
    sum_top += e_top;
    sum_deg += e_deg;
    ++n;
    EXPECT_LE(e_top, 2.0) << "frame " << i;
    EXPECT_LE(e_deg, 1.0) << "frame " << i;
  }
  std::printf("centre line on %d straight frames: top-row offset mean %.2f px, worst %.2f px; angle mean %.3f deg, "
              "worst %.3f deg; bottom-row offset worst %.2f px\n",
              n, sum_top / n, worst_top, sum_deg / n, worst_deg, worst_bot);
}

// The prior (prior_px): a 200 x 100 frame of grey 200 with two dark (50) roads 40 wide, A at columns
// 20..59 (centre 39.5) broken by background in rows 70..79, B at columns 130..169 (centre 149.5)
// whole; trained on A's rows 50..99 (balanced: 1600 dark pixels inside against 6000 outside). With
// the whole image searched B wins (10 more road rows); with a prior on A and prior_px 10, A's centre
// is found, on both runtime paths. prior_px 0 ignores the prior.
TEST(ClusterPerceptron, PriorKeepsTheHoughNearThePredictedCentreLine) {
  Image frame(200, 100, 3);
  Image outline(200, 100, 1);
  for (int v = 0; v < 100; ++v)
    for (int u = 0; u < 200; ++u) {
      const bool a = u >= 20 && u < 60 && !(v >= 70 && v < 80), b = u >= 130 && u < 170;
      std::fill(frame.pixel(u, v), frame.pixel(u, v) + 3, a || b ? 50 : 200);
      outline.pixel(u, v)[0] = u >= 20 && u < 60 && v >= 50 ? 255 : 0;
    }
  const Segment2 prior{Vec2(39.5, 50), Vec2(39.5, 99)};
  for (const double prior_px : {0.0, 10.0}) {
    ClusterPerceptronOptions o;
    o.clusters = 2;
    o.balance_classes = true;
    o.prior_px = prior_px;
    ClusterPerceptron cp(o);
    cp.trainClusters(frame.data.data(), 200, 100);
    cp.setRowWidths(trapezoidRowWidths(outline));
    cp.trainPerceptron(frame.data.data(), 200, 100, outline.data.data());
    ASSERT_GT(cp.outputReference(50, 50, 50), 0);
    ASSERT_LT(cp.outputReference(200, 200, 200), 0);
    ClusterPerceptron ref = cp;
    ref.setFast(false);
    const RoadFinding f = cp.find(frame.data.data(), 200, 100, false, prior);
    const RoadFinding r = ref.find(frame.data.data(), 200, 100, false, prior);
    ASSERT_TRUE(f.ok) << f.reason;
    const double want = prior_px > 0 ? 39.5 : 149.5;
    EXPECT_NEAR(f.centerline_image.a.x(), want, 0.5) << "prior_px " << prior_px;
    EXPECT_NEAR(f.centerline_image.b.x(), want, 0.5) << "prior_px " << prior_px;
    EXPECT_EQ(f.centerline_image.a, r.centerline_image.a);
    EXPECT_EQ(f.centerline_image.b, r.centerline_image.b);
  }
}

}  // namespace
}  // namespace mapnav
