// The park-mode road finder of Jochem & Baluja 1993 ("cluster-perceptron"), its training: the
// clusters (§3), the perceptron (§4; raw RGB, normalised colour, the balanced bootstrap), the masks
// they give, and the colour lookup table's fast path against the per-pixel reference.
// On simulator frames of maps/park_path.json (asphalt path between grass, dirt and gravel,
// shadow_density 0.4) seen by the Terregator pin-hole camera (512 x 480, 22 deg tilt) unless a test
// says otherwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <random>
#include <thread>
#include <vector>

#include "../../vision/src/cluster_perceptron_internal.h"
#include "cluster_perceptron_test_util.h"
#include "mapnav/map/predict.h"
#include "mapnav/sim/world.h"

namespace mapnav {
namespace {

using namespace visiontest;

TEST(ClusterPerceptron, ReconstructionErrorFallsAndConverges) {
  const World world(parkScenery(), parkWorld());
  const auto poses = straightPoses(10.0);
  ASSERT_FALSE(poses.empty());
  for (int clusters : {5, 12, 30}) {
    ClusterPerceptronOptions o;
    o.clusters = clusters;
    ClusterPerceptron cp(o);
    const Frame f = world.render(cam(), poses.front().pose, 0.0);
    const std::vector<Vec3> hist = cp.trainClusters(f.rgb.data.data(), f.rgb.width, f.rgb.height);
    ASSERT_GE(hist.size(), 2u);
    EXPECT_LE(hist.size(), 31u) << "at most 30 iterations";
    EXPECT_LT(hist.back().sum(), 0.2 * hist.front().sum()) << clusters << " clusters";
    // Converged: the last step's change is below the threshold in every band.
    EXPECT_LT((hist.back() - hist[hist.size() - 2]).cwiseAbs().maxCoeff(), o.cluster_slope_threshold)
        << clusters << " clusters, " << hist.size() - 1 << " iterations";
    // The reconstruction image's error is the last entry.
    const Image rec = cp.reconstruct(f.rgb.data.data(), f.rgb.width, f.rgb.height);
    double e = 0;
    for (std::size_t i = 0; i < rec.data.size(); ++i) {
      const double d = static_cast<double>(rec.data[i]) - f.rgb.data[i];
      e += d * d;
    }
    e /= static_cast<double>(rec.data.size());
    EXPECT_NEAR(e, hist.back().mean(), 0.5);
    std::printf("clusters %d: %zu iterations, MSE/band %.1f -> %.1f\n", clusters, hist.size() - 1,
                hist.front().mean(), hist.back().mean());
  }
}

// The clustering passes see each colour once, weighted by its pixels: what they find cannot depend
// on where the pixels are, and a frame of every pixel twice is the same frame to them (weights of 2
// scale every sum exactly). Their last reconstruction error is the per-pixel one of the means found.
TEST(ClusterPerceptron, ClusteringWeighsEachColourByItsPixelsWhereverTheyAre) {
  const World world(parkScenery(), parkWorld());
  const Frame f = world.render(cam(), straightPoses(10.0).front().pose, 0.0);
  const int w = f.rgb.width, h = f.rgb.height;
  const std::vector<std::uint8_t>& rgb = f.rgb.data;
  std::vector<std::uint8_t> shuffled(rgb.size()), twice(2 * rgb.size());
  std::vector<std::size_t> order(static_cast<std::size_t>(w) * h);
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), std::mt19937_64(7));
  for (std::size_t i = 0; i < order.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      shuffled[3 * i + c] = rgb[3 * order[i] + c];
      twice[3 * i + c] = twice[3 * (i + order.size()) + c] = rgb[3 * i + c];
    }
  }
  for (const char* space : {"rgb", "log", "normalised"}) {
    for (int stride : {1, 3}) {
      ClusterPerceptronOptions o;
      o.clusters = 8;
      o.train_stride = stride;
      o.log_color = std::string(space) == "log";
      o.normalized_color = std::string(space) == "normalised";
      ClusterPerceptron a(o), b(o), c(o);
      const std::vector<Vec3> history = a.trainClusters(rgb.data(), w, h);
      const double per_pixel = a.reconstructionError(rgb.data(), w, h, stride);
      EXPECT_NEAR(history.back().mean(), per_pixel, 1e-9 * per_pixel) << space << ", stride " << stride;
      EXPECT_GT(history.size(), 2u);
      if (stride != 1) continue;  // a stride samples other pixels of a shuffled frame
      EXPECT_EQ(b.trainClusters(shuffled.data(), w, h), history) << space;
      EXPECT_EQ(b.means(), a.means()) << space;
      EXPECT_EQ(c.trainClusters(twice.data(), w, 2 * h), history) << space;
      EXPECT_EQ(c.means(), a.means()) << space;
    }
  }
}

TEST(ClusterPerceptron, PerceptronLearnsTheBootstrapOutline) {
  const World world(parkScenery(), parkWorld());
  const auto poses = straightPoses(10.0);
  const Frame f = world.render(cam(), poses.front().pose, 0.0);
  const Prediction pred = predictView(park(), poses.front().pose, cam());
  const Image outline = predictedRoadMask(pred.view, cam());
  ClusterPerceptronOptions o;
  ClusterPerceptron cp(o);
  cp.trainClusters(f.rgb.data.data(), f.rgb.width, f.rgb.height);
  const std::vector<double> hist = cp.trainPerceptron(f.rgb.data.data(), f.rgb.width, f.rgb.height,
                                                      outline.data.data());
  ASSERT_GE(hist.size(), 2u);
  EXPECT_LT(hist.back(), hist.front());
  EXPECT_LT(hist.back(), 0.3);
  if (std::getenv("PARK_DEBUG")) {
    std::printf("%zu iterations, error %.3f -> %.3f\n", hist.size(), hist.front(), hist.back());
    for (std::size_t k = 0; k < cp.means().size(); ++k) {
      const Vec3 m = cp.means()[k];
      std::printf("cluster %zu (%.0f %.0f %.0f) w %.3f out %.3f\n", k, m.x(), m.y(), m.z(), cp.weights()[k],
                  cp.outputReference(static_cast<std::uint8_t>(m.x()), static_cast<std::uint8_t>(m.y()),
                                     static_cast<std::uint8_t>(m.z())));
    }
  }
}

TEST(ClusterPerceptron, ParkRoadMaskIoU) {
  const World world(parkScenery(), parkWorld());
  const std::vector<Pose2> poses = visiontest::roadPoses(park(), 12.0);
  ASSERT_GE(poses.size(), 20u);
  // Each road is a new scene (its own shoulder surfaces): the finder is retrained (reset()) on the
  // road's first frame, then frozen for the rest of the road (§6).
  double tp = 0, fp = 0, fn = 0;
  int frames = 0;
  const Road* current = nullptr;
  std::optional<ClusterPerceptron> cp;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Road* road = &park().roads().front();
    double bd = 1e18;
    for (const Road& r : park().roads()) {
      const double d = r.centerline.project(poses[i].translation()).distance;
      if (d < bd) {
        bd = d;
        road = &r;
      }
    }
    if (road != current) {
      cp = trainedOn(world, poses[i], static_cast<double>(i));
      current = road;
    }
    const Frame f = world.render(cam(), poses[i], static_cast<double>(i));
    const RoadFinding r = cp->find(f.rgb.data.data(), f.rgb.width, f.rgb.height, true);
    ASSERT_FALSE(r.mask.empty()) << r.reason;
    for (std::size_t k = 0; k < r.mask.data.size(); ++k) {
      const bool d = r.mask.data[k] != 0, t = f.mask.data[k] != 0;
      tp += d && t;
      fp += d && !t;
      fn += !d && t;
    }
    ++frames;
  }
  const double iou = tp / (tp + fp + fn);
  std::printf("park road/non-road IoU over %d frames: %.4f (fp %.4f, fn %.4f of truth)\n", frames, iou, fp / (tp + fn),
              fn / (tp + fn));
  EXPECT_GE(frames, 20);
  EXPECT_GE(iou, 0.95);
}

// Beyond the paper (§9): the perceptron on raw R, G, B. On the park, asphalt is bluer than grass,
// dirt and their shadows, which one linear unit separates well; its lookup table is exact too.
TEST(ClusterPerceptron, RawRgbPerceptronLearnsTheRoadAndItsTableIsExact) {
  const World world(parkScenery(), parkWorld());
  const auto poses = straightPoses(10.0);
  ClusterPerceptronOptions o;
  o.raw_rgb = true;
  ClusterPerceptron fast = trainedOn(world, poses.front().pose, 0.0, o);
  ASSERT_EQ(fast.weights().size(), 4u);
  ClusterPerceptron ref = fast;
  ref.setFast(false);
  double tp = 0, fp = 0, fn = 0;
  for (std::size_t i = 0; i < 6; ++i) {
    const Frame f = world.render(cam(), poses[i].pose, static_cast<double>(i));
    const RoadFinding a = fast.find(f.rgb.data.data(), f.rgb.width, f.rgb.height, true);
    const RoadFinding b = ref.find(f.rgb.data.data(), f.rgb.width, f.rgb.height, true);
    ASSERT_TRUE(a.ok) << a.reason;
    EXPECT_EQ(a.mask, b.mask) << "frame " << i;
    EXPECT_EQ(a.centerline_image.a, b.centerline_image.a) << "frame " << i;
    for (std::size_t k = 0; k < a.mask.data.size(); ++k) {
      const bool d = a.mask.data[k] != 0, t = f.mask.data[k] != 0;
      tp += d && t;
      fp += d && !t;
      fn += !d && t;
    }
  }
  const double iou = tp / (tp + fp + fn);
  std::printf("raw-RGB perceptron: weights %.3f %.3f %.3f bias %.3f, IoU over 6 frames %.4f\n", fast.weights()[0],
              fast.weights()[1], fast.weights()[2], fast.weights()[3], iou);
  EXPECT_GE(iou, 0.95);
}

// Wallace et al. 1985 §3.4.3: a shadow scales a colour by k (C1 = k·C2), which the normalised colour
// does not see. Finders trained on a sunlit frame (no tree shadows) classify the same view in full
// shadow (WorldOptions::shadow_density 1: k = 0.45 everywhere), untinted and with the default
// skylight tint (12 % toward blue): normalised, the road mask's IoU against the truth stays at the
// bar of 0.95 in the shade, where RGB's falls below it (the figures: docs/measurements.md).
TEST(ClusterPerceptron, NormalisedColourClassifiesAShadedViewAsTheSunlitOne) {
  WorldOptions sunlit = parkWorld();
  sunlit.shadow_density = 0;
  WorldOptions shaded = sunlit, tinted = sunlit;
  shaded.shadow_density = tinted.shadow_density = 1.0;
  shaded.shadow_blue_shift = 0;
  const World sun(park(), sunlit), shade(park(), shaded), tint(park(), tinted);
  const Pose2 pose = straightPoses(10.0).front().pose;
  const auto iou = [&](const ClusterPerceptron& cp, const World& world) {
    const Frame f = world.render(cam(), pose, 0.0);
    return maskIoU(cp.find(f.rgb.data.data(), f.rgb.width, f.rgb.height, true).mask, f.mask);
  };
  ClusterPerceptronOptions o;
  const ClusterPerceptron rgb = trainedOn(sun, pose, 0.0, o);
  o.normalized_color = true;
  const ClusterPerceptron normalised = trainedOn(sun, pose, 0.0, o);
  const double rgb_sun = iou(rgb, sun), rgb_shade = iou(rgb, shade), rgb_tint = iou(rgb, tint);
  const double n_sun = iou(normalised, sun), n_shade = iou(normalised, shade), n_tint = iou(normalised, tint);
  std::printf("road IoU, trained sunlit: RGB sunlit %.4f, shaded %.4f, tinted %.4f; normalised sunlit %.4f, shaded %.4f, "
              "tinted %.4f\n",
              rgb_sun, rgb_shade, rgb_tint, n_sun, n_shade, n_tint);
  EXPECT_GE(rgb_sun, 0.95);
  EXPECT_GE(n_sun, 0.95);
  EXPECT_GE(n_shade, 0.95);
  EXPECT_GE(n_tint, 0.95);
  EXPECT_LT(rgb_shade, 0.95);  // the bar, which RGB meets sunlit and misses in the shade
  // The reconstruction (§3.2) in normalised colour: each pixel its cluster's chromaticity at its own
  // brightness, R + G + B kept to the rounding of the three bands.
  const Frame f = shade.render(cam(), pose, 0.0);
  const Image rec = normalised.reconstruct(f.rgb.data.data(), f.rgb.width, f.rgb.height);
  int worst = 0;
  for (std::size_t i = 0; i < rec.data.size(); i += 3) {
    const int sum = rec.data[i] + rec.data[i + 1] + rec.data[i + 2];
    const int was = f.rgb.data[i] + f.rgb.data[i + 1] + f.rgb.data[i + 2];
    worst = std::max(worst, std::abs(sum - was));
  }
  EXPECT_LE(worst, 1);  // three roundings of at most 0.5
}

// The lookup table stays exact in normalised colour and in log colour: every one of the 2^24 colours
// (68.3 frames of them) gets the reference path's class, for the clusters' perceptron and (normalised)
// for raw_rgb's. And a colour and its double have the same normalised colour to the bit, so the same
// output. Under the sanitizers, where the reference runs 5-10 times slower, one frame of colours in
// seven and one red level in three: the release stage checks them all.
TEST(ClusterPerceptron, NormalisedAndLogColourTablesAreExactForEveryColour) {
  const World world(parkScenery(), parkWorld());
  const Pose2 pose = straightPoses(10.0).front().pose;
  const int w = cam().width(), h = cam().height();
  const std::uint32_t per_frame = static_cast<std::uint32_t>(w) * static_cast<std::uint32_t>(h);
  for (const auto& [raw, log] : {std::pair{false, false}, std::pair{true, false}, std::pair{false, true}}) {
    ClusterPerceptronOptions o;
    o.normalized_color = !log;
    o.log_color = log;
    o.raw_rgb = raw;
    const ClusterPerceptron fast = trainedOn(world, pose, 0.0, o);
    ClusterPerceptron ref = fast;
    ref.setFast(false);
    std::size_t differing = 0, road = 0, total = 0;
    Image frame(w, h, 3);
    for (std::uint32_t first = 0; first < (1u << 24); first += per_frame * (testing::kUnderSanitizers ? 7 : 1)) {
      for (std::uint32_t i = 0; i < per_frame; ++i) {
        const std::uint32_t c = (first + i) & 0xFFFFFFu;
        frame.data[3 * i] = static_cast<std::uint8_t>(c >> 16);
        frame.data[3 * i + 1] = static_cast<std::uint8_t>(c >> 8);
        frame.data[3 * i + 2] = static_cast<std::uint8_t>(c);
      }
      const RoadFinding a = fast.find(frame.data.data(), w, h, true);
      const RoadFinding b = ref.find(frame.data.data(), w, h, true);
      ASSERT_EQ(a.mask.data.size(), b.mask.data.size());
      for (std::size_t k = 0; k < a.mask.data.size(); ++k) {
        differing += a.mask.data[k] != b.mask.data[k];
        road += b.mask.data[k] != 0;
      }
      total += b.mask.data.size();
      EXPECT_EQ(a.ok, b.ok);
      EXPECT_EQ(a.shift, b.shift);
      EXPECT_EQ(a.intercept_col, b.intercept_col);
    }
    std::printf("%s colour%s: %zu of %zu colours differ between the table and the reference, %.1f %% road\n",
                log ? "log" : "normalised", raw ? ", raw_rgb" : "", differing, total,
                100.0 * static_cast<double>(road) / static_cast<double>(total));
    EXPECT_EQ(differing, 0u);
    EXPECT_GT(road, total / 100);
    EXPECT_LT(road, total - total / 100);
    if (log) continue;
    int halved_differ = 0;
    for (int r = 0; r < 128; r += testing::kUnderSanitizers ? 3 : 1)
      for (int g = 0; g < 128; ++g)
        for (int b = 0; b < 128; ++b)
          halved_differ += ref.outputReference(static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(g),
                                               static_cast<std::uint8_t>(b)) !=
                           ref.outputReference(static_cast<std::uint8_t>(2 * r), static_cast<std::uint8_t>(2 * g),
                                               static_cast<std::uint8_t>(2 * b));
    std::printf("normalised colour%s: %d colours differ from their doubles\n", raw ? ", raw_rgb" : "", halved_differ);
    EXPECT_EQ(halved_differ, 0);
  }
}

TEST(ClusterPerceptron, FastPathEqualsReferenceOn100Frames) {
  const World world(parkScenery(), parkWorld());
  const std::vector<Pose2> poses = visiontest::roadPoses(park(), 5.0);
  ASSERT_GE(poses.size(), 100u);
  ClusterPerceptron fast = trainedOn(world, straightPoses(10.0).front().pose, 0.0);
  ClusterPerceptron ref = fast;
  ref.setFast(false);
  std::size_t differing = 0, total = 0;
  // The first 25 frames under the sanitizers, where rendering and finding run 5-10 times slower.
  const std::size_t frames = testing::kUnderSanitizers ? 25 : 100;
  for (std::size_t i = 0; i < frames; ++i) {
    const Frame f = world.render(cam(), poses[i], static_cast<double>(i));
    const RoadFinding a = fast.find(f.rgb.data.data(), f.rgb.width, f.rgb.height, true);
    const RoadFinding b = ref.find(f.rgb.data.data(), f.rgb.width, f.rgb.height, true);
    ASSERT_EQ(a.ok, b.ok);
    ASSERT_EQ(a.mask.data.size(), b.mask.data.size());
    for (std::size_t k = 0; k < a.mask.data.size(); ++k) differing += a.mask.data[k] != b.mask.data[k];
    total += a.mask.data.size();
    // Identical: boundary cells of the lookup table are classified per pixel, so the masks, the block
    // certainties and so the Hough and the line are bit-identical.
    EXPECT_EQ(a.mask, b.mask) << "frame " << i;
    EXPECT_EQ(a.centerline_image.a, b.centerline_image.a) << "frame " << i;
    EXPECT_EQ(a.centerline_image.b, b.centerline_image.b) << "frame " << i;
    EXPECT_EQ(a.shift, b.shift);
    EXPECT_EQ(a.intercept_col, b.intercept_col);
  }
  std::printf("fast vs reference: %zu of %zu mask pixels differ\n", differing, total);
}

// The lookup table is computed as frames need it (the first frame after training its cells, the
// second the rest), under a lock: four threads finding on one freshly trained finder at once — a
// park frame and three frames of other colours (slices of the colour cube), started in reverse —
// give the answers a second finder, trained the same way, gives them one after the other, and every
// certainty is one of the 16 levels (a cell read before it was computed would not be).
TEST(ClusterPerceptron, ThreadsFillingOneLookupTableGetTheSequentialAnswers) {
  const World world(parkScenery(), parkWorld());
  const Pose2 at = straightPoses(10.0).front().pose;
  const ClusterPerceptron shared = trainedOn(world, at, 0.0), alone = trainedOn(world, at, 0.0);
  std::vector<Image> frames = {world.render(cam(), at, 1.0).rgb};
  const int w = frames[0].width, h = frames[0].height;
  for (const int blue : {40, 140, 240}) {
    Image cube(w, h, 3);
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        std::uint8_t* p = cube.pixel(u, v);
        p[0] = static_cast<std::uint8_t>(u * 255 / (w - 1)), p[1] = static_cast<std::uint8_t>(v * 255 / (h - 1));
        p[2] = static_cast<std::uint8_t>(blue);
      }
    frames.push_back(std::move(cube));
  }
  std::vector<RoadFinding> sequential, concurrent(frames.size());
  for (const Image& f : frames) sequential.push_back(alone.find(f.data.data(), w, h, true));
  std::vector<std::thread> threads;
  for (std::size_t i = frames.size(); i-- > 0;)
    threads.emplace_back([&, i] { concurrent[i] = shared.find(frames[i].data.data(), w, h, true); });
  for (std::thread& t : threads) t.join();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(concurrent[i].certainty, sequential[i].certainty) << "frame " << i;
    EXPECT_EQ(concurrent[i].ok, sequential[i].ok) << "frame " << i;
    EXPECT_EQ(concurrent[i].centerline_image.a, sequential[i].centerline_image.a) << "frame " << i;
    for (const RoadFinding* r : {&sequential[i], &concurrent[i]})
      EXPECT_TRUE(std::all_of(r->certainty.data.begin(), r->certainty.data.end(), [](std::uint8_t c) { return c % 16 == 0; }))
          << "frame " << i;
  }
  EXPECT_GT(std::count(sequential[0].mask.data.begin(), sequential[0].mask.data.end(), 255), 1000);  // road seen
}

// The channel tables' nearest cluster (the clustering's and the lookup table's; a vector path up to 8
// clusters) is the first cluster of least float sum, as a plain loop over the clusters finds it: for
// 1 to 10 clusters with means on a coarse lattice (many colours equally far from two of them), every
// colour of a 5-level lattice of the cube.
TEST(ChannelTables, NearestIsTheFirstClusterOfLeastSum) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> level(0, 8);
  for (int n = 1; n <= 10; ++n) {
    std::vector<Vec3> means;
    for (int k = 0; k < n; ++k) means.emplace_back(32.0 * level(rng), 32.0 * level(rng), 32.0 * level(rng));
    const ChannelTables tables([](double r, double g, double b) { return Vec3(r, g, b); }, means);
    int ties = 0;
    for (int r = 0; r < 256; r += 5)
      for (int g = 0; g < 256; g += 5)
        for (int b = 0; b < 256; b += 5) {
          int best = 0, equal = 0;
          float bd = std::numeric_limits<float>::infinity();
          for (int k = 0; k < n; ++k) {
            const auto sq = [&](int x, int c) {
              const float d = static_cast<float>(x) - static_cast<float>(means[k][c]);
              return d * d;
            };
            const float d = sq(r, 0) + sq(g, 1) + sq(b, 2);
            if (d == bd) ++equal;
            if (d < bd) bd = d, best = k, equal = 0;
          }
          ties += equal > 0;
          ASSERT_EQ(tables.nearest(r, g, b), best) << n << " clusters, colour " << r << " " << g << " " << b;
        }
    if (n >= 4) {
      EXPECT_GT(ties, 0) << n << " clusters: the lattice gave no tie to check";
    }
  }
}

// The bootstrap on a road that is a small part of the frame: a 100 x 100 frame of grey 200 with 1000
// pixels of grey 50, of which the 10 x 10 outline holds 100. Unbalanced, grey 50's cluster has 100
// road and 900 other pixels and is not road; balanced, each road pixel counts 9900 / 100 = 99 times,
// and grey 50 (all of the outline, 9 % of the rest) is road while grey 200 is not.
TEST(ClusterPerceptron, BalancedBootstrapFindsASmallRoad) {
  Image frame(100, 100, 3);
  Image outline(100, 100, 1);
  for (int v = 0; v < 100; ++v)
    for (int u = 0; u < 100; ++u) {
      const bool inside = u >= 45 && u < 55 && v >= 90;   // 10 x 10
      const bool dark = inside || (v < 30 && u < 30);       // + 900 outside
      std::fill(frame.pixel(u, v), frame.pixel(u, v) + 3, dark ? 50 : 200);
      outline.pixel(u, v)[0] = inside ? 255 : 0;
    }
  for (const bool balance : {false, true}) {
    ClusterPerceptronOptions o;
    o.clusters = 2;
    o.balance_classes = balance;
    o.nonroad_gate_sigma = 0;  // the paper's bootstrap, balanced or not (the gate: the next test)
    ClusterPerceptron cp(o);
    cp.trainClusters(frame.data.data(), 100, 100);
    cp.trainPerceptron(frame.data.data(), 100, 100, outline.data.data());
    EXPECT_EQ(cp.outputReference(50, 50, 50) > 0, balance) << "balance " << balance;
    EXPECT_LT(cp.outputReference(200, 200, 200), 0) << "balance " << balance;
  }
}

// The non-road gate on the same frame, unbalanced. The paper's bootstrap calls none of the outline
// road (the share 0 < nonroad_gate_below 0.5), so the perceptron is trained again with "not road"
// only where the colour lies more than 16 sigma from the outline's (grey 50, covariance 0 + 1 level^2:
// grey 200 lies 150 sqrt(3) sigma away, the 900 dark pixels outside 0 away and train nothing): grey
// 50 is road (100 road pixels, none against), grey 200 not. With nonroad_gate_below 0 it is never
// used; with the outline on every dark pixel the paper's bootstrap separates (share 1) and stands.
TEST(ClusterPerceptron, NonroadGateWhereThePapersBootstrapCannotSeparate) {
  Image frame(100, 100, 3);
  Image small(100, 100, 1), whole(100, 100, 1);
  for (int v = 0; v < 100; ++v)
    for (int u = 0; u < 100; ++u) {
      const bool inside = u >= 45 && u < 55 && v >= 90;
      const bool dark = inside || (v < 30 && u < 30);
      std::fill(frame.pixel(u, v), frame.pixel(u, v) + 3, dark ? 50 : 200);
      small.pixel(u, v)[0] = inside ? 255 : 0;
      whole.pixel(u, v)[0] = dark ? 255 : 0;
    }
  struct Case {
    double below;
    const Image* outline;
    bool gated;
  };
  for (const Case& c : {Case{0.5, &small, true}, Case{0.0, &small, false}, Case{0.5, &whole, false}}) {
    ClusterPerceptronOptions o;
    o.clusters = 2;
    o.nonroad_gate_below = c.below;
    ClusterPerceptron cp(o);
    cp.trainClusters(frame.data.data(), 100, 100);
    cp.trainPerceptron(frame.data.data(), 100, 100, c.outline->data.data());
    EXPECT_EQ(cp.nonroadGated(), c.gated) << c.below;
    EXPECT_EQ(cp.outputReference(50, 50, 50) > 0, c.gated || c.outline == &whole) << c.below;
    EXPECT_LT(cp.outputReference(200, 200, 200), 0) << c.below;
  }
}

}  // namespace
}  // namespace mapnav
