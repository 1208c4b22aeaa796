#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "mapnav/core/error.h"
#include "mapnav/vision/color_classifier.h"
#include "mapnav/vision/region.h"

namespace mapnav {
namespace {

// An image: left half grey "concrete", right half green "grass", each with noise; half the
// concrete darkened as a shadow (k = 0.45) in the top rows.
std::vector<std::uint8_t> twoTone(int w, int h, bool shadow, std::uint32_t seed = 3) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0, 5);
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w) * h * 3);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      double c[3];
      if (u < w / 2) c[0] = 178, c[1] = 176, c[2] = 168;
      else c[0] = 70, c[1] = 120, c[2] = 50;
      if (shadow && v < h / 2) c[0] *= 0.45, c[1] *= 0.45, c[2] *= 0.45;
      for (int k = 0; k < 3; ++k)
        rgb[(static_cast<std::size_t>(v) * w + u) * 3 + k] = static_cast<std::uint8_t>(std::clamp(c[k] + n(rng), 0.0, 255.0));
    }
  }
  return rgb;
}

// twoTone's labels: road on the concrete half, non-road on the grass half, 4 columns either side of
// the boundary unlabelled.
std::pair<std::vector<std::uint8_t>, std::vector<std::uint8_t>> concreteAndGrassLabels(int w, int h) {
  std::vector<std::uint8_t> road(w * h, 0), non(w * h, 0);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) (u < w / 2 - 4 ? road : non)[v * w + u] = (u < w / 2 - 4 || u > w / 2 + 4) ? 1 : 0;
  return {road, non};
}

TEST(ColorClassifier, SeparatesRoadFromGrassInBothSpaces) {
  const int w = 64, h = 64;
  const auto rgb = twoTone(w, h, false);
  const auto [road, non] = concreteAndGrassLabels(w, h);
  for (ColorSpace space : {ColorSpace::LogRGB, ColorSpace::NormalizedRG}) {
    ColorClassifierOptions o;
    o.space = space;
    o.min_pixels = 50;
    ColorClassifier c(o);
    const auto r = c.update(rgb.data(), w, h, road.data(), non.data());
    EXPECT_TRUE(r.road_accepted && r.nonroad_accepted) << r.note;
    ASSERT_TRUE(c.trained());
    EXPECT_GT(c.separation(), 2.0);
    const auto llr = c.logOdds(rgb.data(), w, h);
    int errors = 0;
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) errors += (llr[v * w + u] > 0) != (u < w / 2);
    EXPECT_EQ(errors, 0);
  }
}

TEST(ColorClassifier, NormalizedRgIgnoresShadowsWhereRgbDoesNot) {
  const int w = 64, h = 64;
  const auto train = twoTone(w, h, false);
  const auto test = twoTone(w, h, true, 9);
  std::vector<std::uint8_t> road(w * h, 0), non(w * h, 0);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) (u < w / 2 ? road : non)[v * w + u] = 1;
  int errs[2] = {0, 0};
  int idx = 0;
  for (ColorSpace space : {ColorSpace::LogRGB, ColorSpace::NormalizedRG}) {
    ColorClassifierOptions o;
    o.space = space;
    o.min_pixels = 50;
    ColorClassifier c(o);
    c.update(train.data(), w, h, road.data(), non.data());
    const auto llr = c.logOdds(test.data(), w, h);
    for (int v = 0; v < h / 2; ++v)
      for (int u = 0; u < w / 2; ++u) errs[idx] += llr[v * w + u] <= 0;
    ++idx;
  }
  EXPECT_GT(errs[0], 0.9 * (w / 2) * (h / 2));  // log RGB: shadowed concrete is not road
  EXPECT_LT(errs[1], 0.01 * (w / 2) * (h / 2));  // rg: it is (noise aside)
}

TEST(ColorClassifier, DriftGuardRefusesAJumpAndTooFewPixels) {
  const int w = 64, h = 64;
  const auto rgb = twoTone(w, h, false);
  std::vector<std::uint8_t> road(w * h, 0), non(w * h, 0), swapped_road(w * h, 0);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      (u < w / 2 ? road : non)[v * w + u] = 1;
      if (u >= w / 2) swapped_road[v * w + u] = 1;
    }
  ColorClassifierOptions o;
  o.min_pixels = 50;
  ColorClassifier c(o);
  c.update(rgb.data(), w, h, road.data(), non.data());
  const Vec3 before = c.road().mean;
  // Road labels on grass: the road mean would jump many sigma — refused.
  auto r = c.update(rgb.data(), w, h, swapped_road.data(), non.data());
  EXPECT_FALSE(r.road_accepted);
  EXPECT_NE(r.note.find("sigma"), std::string::npos);
  EXPECT_EQ(c.road().mean, before);
  // Too few pixels: refused.
  std::vector<std::uint8_t> few(w * h, 0);
  few[0] = 1;
  r = c.update(rgb.data(), w, h, few.data(), non.data());
  EXPECT_FALSE(r.road_accepted);
  EXPECT_NE(r.note.find("too few"), std::string::npos);
  // A consistent update is accepted.
  r = c.update(rgb.data(), w, h, road.data(), non.data());
  EXPECT_TRUE(r.road_accepted);
  EXPECT_THROW(ColorClassifier(ColorClassifierOptions{.space = ColorSpace::LogRGB, .blend = 0}), InvalidInput);
}

// The surroundings change: a concrete path between lawns, then between brown dirt shoulders
// (150, 120, 90: r = 151 / 363 = 0.416, g = 0.333 against the concrete's 0.339, 0.337 and the
// grass's 0.292, 0.498). The dirt's non-road estimate lies many sigma from the lawn's model. Gated
// (no road colour in it), it is blended in (mean halfway, blend 0.5) and after a few frames the dirt
// is not road; refused by the drift guard, as it was, the model stayed the lawn's, and much of the
// dirt, nearer the concrete in r and g than the lawn, was road (a third of it in this draw).
// Ungated, the guard still refuses it, and the road's own jump is refused either way.
TEST(ColorClassifier, AGatedNonRoadModelFollowsTheSurroundingsAsTheyChange) {
  const int w = 64, h = 64;
  const auto lawn = twoTone(w, h, false);
  auto dirt = twoTone(w, h, false, 7);
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0, 5);
  for (int v = 0; v < h; ++v)
    for (int u = w / 2; u < w; ++u)
      for (int k = 0; k < 3; ++k)
        dirt[(v * w + u) * 3 + k] = static_cast<std::uint8_t>(std::clamp((k == 0 ? 150 : k == 1 ? 120 : 90) + noise(rng), 0.0, 255.0));
  const auto [road, non] = concreteAndGrassLabels(w, h);
  ColorClassifierOptions o;
  o.min_pixels = 50;
  o.stride = 1;
  o.nonroad_gate_sigma = 3;
  const auto dirtIsRoad = [&](const ColorClassifier& c) {
    const auto llr = c.logOdds(dirt.data(), w, h);
    int n = 0;
    for (int v = 0; v < h; ++v)
      for (int u = w / 2 + 5; u < w; ++u) n += llr[v * w + u] > 0;
    return n;
  };
  ColorClassifier gated(o), fresh(o);
  ASSERT_TRUE(gated.update(lawn.data(), w, h, road.data(), non.data()).nonroad_accepted);
  const Vec3 lawn_mean = gated.nonroad().mean;
  ASSERT_TRUE(fresh.update(dirt.data(), w, h, road.data(), non.data()).nonroad_accepted);
  EXPECT_GT(std::sqrt((fresh.nonroad().mean - lawn_mean).squaredNorm()), 0.1);  // far from the lawn's
  const auto r = gated.update(dirt.data(), w, h, road.data(), non.data());
  EXPECT_TRUE(r.nonroad_accepted) << r.note;
  EXPECT_NEAR((gated.nonroad().mean - (0.5 * lawn_mean + 0.5 * fresh.nonroad().mean)).norm(), 0, 1e-12);
  for (int k = 0; k < 3; ++k) gated.update(dirt.data(), w, h, road.data(), non.data());
  EXPECT_EQ(dirtIsRoad(gated), 0);
  // Ungated: the guard refuses the jump; the lawn's model stays, and the dirt is road to it.
  o.nonroad_gate_sigma = 0;
  ColorClassifier guarded(o);
  guarded.update(lawn.data(), w, h, road.data(), non.data());
  const auto g = guarded.update(dirt.data(), w, h, road.data(), non.data());
  EXPECT_FALSE(g.nonroad_accepted);
  EXPECT_NE(g.note.find("non-road: mean moved"), std::string::npos) << g.note;
  EXPECT_GT(dirtIsRoad(guarded), (w / 2 - 5) * h / 10);
  // The road's jump is refused with the gate as well: road labels on the dirt.
  std::vector<std::uint8_t> on_dirt(w * h, 0);
  for (int v = 0; v < h; ++v)
    for (int u = w / 2 + 5; u < w; ++u) on_dirt[v * w + u] = 1;
  std::vector<std::uint8_t> none(w * h, 0);
  EXPECT_FALSE(gated.update(dirt.data(), w, h, on_dirt.data(), none.data()).road_accepted);
}

// The non-road gate: a real road's surroundings are mostly more road. Road labels on the left
// grey half; non-road labels on the right half, where a band of columns 32-47 is the same grey and
// columns 48-63 grass. Without the gate the non-road mean is the mixture's (half grey, half grass);
// with it, only the grass trains non-road, so its mean is the grass colour (70, 120, 50) in rg:
// r = 71 / 243, g = 121 / 243 (the feature adds 1 per channel), to the noise (sigma 5 per channel).
TEST(ColorClassifier, NonRoadGateTrainsNonRoadOnlyOnWhatIsNotRoadColoured) {
  const int w = 64, h = 64;
  auto rgb = twoTone(w, h, false);
  const std::vector<std::uint8_t> grey_half = twoTone(w, h, false, 5);
  for (int v = 0; v < h; ++v)  // columns 32-47: grey too (copied from another image's grey half)
    for (int u = 32; u < 48; ++u)
      for (int k = 0; k < 3; ++k) rgb[(v * w + u) * 3 + k] = grey_half[(v * w + u - 32) * 3 + k];
  std::vector<std::uint8_t> road(w * h, 0), non(w * h, 0);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) (u < 32 ? road : non)[v * w + u] = 1;
  ColorClassifierOptions o;
  o.min_pixels = 50;
  o.stride = 1;
  ColorClassifier plain(o);
  plain.update(rgb.data(), w, h, road.data(), non.data());
  o.nonroad_gate_sigma = 8;
  ColorClassifier gated(o);
  const auto r = gated.update(rgb.data(), w, h, road.data(), non.data());
  ASSERT_TRUE(r.road_accepted && r.nonroad_accepted) << r.note;
  const double grass_r = 71.0 / 243, grass_g = 121.0 / 243, grey_r = 179.0 / 525;
  EXPECT_NEAR(gated.nonroad().mean[0], grass_r, 0.003);
  EXPECT_NEAR(gated.nonroad().mean[1], grass_g, 0.003);
  EXPECT_EQ(gated.nonroad().count, 16.0 * h);  // the grass columns only
  EXPECT_NEAR(plain.nonroad().mean[0], 0.5 * (grass_r + grey_r), 0.003);
  // The grey band is road to the gated classifier.
  const auto llr = gated.logOdds(rgb.data(), w, h);
  int grey_band_road = 0;
  for (int v = 0; v < h; ++v)
    for (int u = 32; u < 48; ++u) grey_band_road += llr[v * w + u] > 0;
  EXPECT_EQ(grey_band_road, 16 * h);
  EXPECT_THROW(ColorClassifier(ColorClassifierOptions{.nonroad_gate_sigma = -1}), InvalidInput);
}

// Log RGB: each channel c as 255 ln(c + 1) / ln 256 (s = 45.99 levels per unit of ln). The road
// class is the road pixels' sample mean and covariance in those features, plus the camera's noise
// floor on the diagonal (noise_sigma 1: (s / 129)², one level at mid-grey) and brightness_sigma's
// (0.1 s)² = 21.15 in every entry: a shade of the road's own colour is one step along the grey axis.
TEST(ColorClassifier, LogRgbSpreadsTheRoadAlongTheGreyAxis) {
  const int w = 64, h = 64;
  const auto rgb = twoTone(w, h, false);
  const auto [road, non] = concreteAndGrassLabels(w, h);
  const double s = 255.0 / std::log(256.0);
  Vec3 sum = Vec3::Zero();
  Mat3 sq = Mat3::Zero();
  double n = 0;
  for (int i = 0; i < w * h; ++i) {
    if (road[i] == 0) continue;
    const Vec3 x(s * std::log(rgb[3 * i] + 1.0), s * std::log(rgb[3 * i + 1] + 1.0), s * std::log(rgb[3 * i + 2] + 1.0));
    sum += x, sq += x * x.transpose(), n += 1;
  }
  const Vec3 mean = sum / n;
  const Mat3 sample = sq / n - mean * mean.transpose();
  ColorClassifier c({.space = ColorSpace::LogRGB, .min_pixels = 50, .stride = 1, .brightness_sigma = 0.1});
  c.update(rgb.data(), w, h, road.data(), non.data());
  ASSERT_TRUE(c.trained());
  EXPECT_NEAR((c.road().mean - mean).norm(), 0.0, 1e-9);
  const double spread = 0.01 * s * s, floor = (s / 129) * (s / 129);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(c.road().cov(i, j), sample(i, j) + spread + (i == j ? floor : 0.0), 1e-9) << i << j;
  // A 10 % shade moves every channel by s ln 0.9 = -4.85, 8.39 along the grey axis. The class's
  // variance along that axis is 3 x 21.15 + about 1.8 (the pixels' noise, 5 levels = 1.28 in log at
  // 178, and the floor): 1.04 sigma. Without the spread, the noise alone: 8.39 / 1.34 = 6.3 sigma.
  const Vec3 shade = Vec3::Constant(s * std::log(0.9));
  const auto sigmas = [](const GaussianClass& g, const Vec3& d) { return std::sqrt(d.dot(g.cov.inverse() * d)); };
  EXPECT_NEAR(sigmas(c.road(), shade), 1.04, 0.02);
  ColorClassifier tight({.space = ColorSpace::LogRGB, .min_pixels = 50, .stride = 1});
  tight.update(rgb.data(), w, h, road.data(), non.data());
  EXPECT_NEAR(sigmas(tight.road(), shade), 6.3, 0.4);
}

// The log brightness as a third feature: a dark grey car has the concrete's rg (178, 176, 168 scaled
// by a third), so in rg alone it is within the non-road gate of the road, never trains non-road, and
// is road. With brightness_sigma 0.1 it is ln 3 ≈ 1.1 away, about 11 sigma, so it trains non-road
// (with the grass) and is not road. The road's third mean is ln((178 + 176 + 168 + 3) / 3) = ln 175,
// and its spread the noise's (5 / sqrt 3 per channel mean, 2.9 / 175 in ln: variance 2.7e-4) plus
// the floor's 0.01. A road trained in sun and shadow (x 0.45) keeps both.
// brightness_separation decides per model whether the brightness is needed (below).
TEST(ColorClassifier, BrightnessTellsADarkGreyCarFromAGreyRoad) {
  const int w = 64, h = 64;
  auto rgb = twoTone(w, h, false);
  const std::vector<std::uint8_t> concrete = twoTone(w, h, false, 9);
  for (int v = 0; v < h; ++v)  // columns 48-63: the concrete at a third of its brightness
    for (int u = 48; u < 64; ++u)
      for (int k = 0; k < 3; ++k)
        rgb[(v * w + u) * 3 + k] = static_cast<std::uint8_t>(concrete[(v * w + u - 48) * 3 + k] / 3);
  std::vector<std::uint8_t> road(w * h, 0), non(w * h, 0);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) (u < 32 ? road : non)[v * w + u] = 1;
  const auto car_as_road = [&](const ColorClassifier& c) {
    const auto llr = c.logOdds(rgb.data(), w, h);
    int n = 0;
    for (int v = 0; v < h; ++v)
      for (int u = 48; u < 64; ++u) n += llr[v * w + u] > 0;
    return n;
  };
  ColorClassifierOptions o{.min_pixels = 50, .stride = 1, .nonroad_gate_sigma = 8};
  ColorClassifier rg(o);
  rg.update(rgb.data(), w, h, road.data(), non.data());
  EXPECT_EQ(rg.nonroad().count, 16.0 * h);  // the grass only
  EXPECT_EQ(car_as_road(rg), 16 * h);
  o.brightness_sigma = 0.1;
  ColorClassifier bright(o);
  const auto r = bright.update(rgb.data(), w, h, road.data(), non.data());
  ASSERT_TRUE(bright.trained()) << r.note;
  EXPECT_EQ(bright.nonroad().count, 32.0 * h);  // grass and car
  EXPECT_NEAR(bright.road().mean[2], std::log(175.0), 0.005);
  EXPECT_GT(bright.road().cov(2, 2), 0.01);
  EXPECT_LT(bright.road().cov(2, 2), 0.0106);
  EXPECT_EQ(car_as_road(bright), 0);
  EXPECT_TRUE(bright.brightnessUsed());
  EXPECT_THROW(ColorClassifier(ColorClassifierOptions{.brightness_sigma = -0.1}), InvalidInput);

  // With brightness_separation 5: rg alone separates the road from grass and car together by less
  // (the car has the road's rg), so the brightness is used; from grass alone by far more, so rg
  // alone is, and the classifier is the rg one exactly.
  o.brightness_separation = 5;
  ColorClassifier needed(o);
  needed.update(rgb.data(), w, h, road.data(), non.data());
  EXPECT_TRUE(needed.brightnessUsed());
  EXPECT_EQ(car_as_road(needed), 0);
  const auto lawn = twoTone(w, h, false);
  ColorClassifier not_needed(o), rg_alone(ColorClassifierOptions{.min_pixels = 50, .stride = 1, .nonroad_gate_sigma = 8});
  not_needed.update(lawn.data(), w, h, road.data(), non.data());
  rg_alone.update(lawn.data(), w, h, road.data(), non.data());
  EXPECT_FALSE(not_needed.brightnessUsed());
  EXPECT_GT(rg_alone.separation(), 5);
  EXPECT_NEAR(not_needed.separation(), rg_alone.separation(), 1e-9);
  EXPECT_EQ(not_needed.logOdds(lawn.data(), w, h), rg_alone.logOdds(lawn.data(), w, h));

  const auto shaded = twoTone(w, h, true);  // the concrete's top half in shadow, labelled road too
  ColorClassifier sun_and_shade(o);
  sun_and_shade.update(shaded.data(), w, h, road.data(), non.data());
  const auto llr = sun_and_shade.logOdds(shaded.data(), w, h);
  int concrete_road = 0;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < 32; ++u) concrete_road += llr[v * w + u] > 0;
  EXPECT_GE(concrete_road, 32 * h - 5);  // a few of the darkest shaded pixels: rg is noisy in the dark
}

// Nothing confidently off the road: every non-road label is road-coloured. With the gate, non-road
// is then flat (every colour about equally likely): the grey is road, a colour far from it is not.
// The feature of every brightness: rg and ln((R + G + B + 3) / 3) as written (the per-pixel loops
// read the logarithm from a table).
TEST(ColorClassifier, FeatureIsRgAndTheLogBrightnessAtEveryLevel) {
  ColorClassifierOptions o;
  o.brightness_sigma = 0.1;
  for (int sum = 0; sum <= 765; ++sum) {
    const std::uint8_t r = static_cast<std::uint8_t>(std::min(sum, 255));
    const std::uint8_t g = static_cast<std::uint8_t>(std::min(sum - r, 255));
    const std::uint8_t px[3] = {r, g, static_cast<std::uint8_t>(sum - r - g)};
    const double s = sum + 3.0;
    const Vec3 f = colorFeature(o, px);
    EXPECT_EQ(f.x(), (r + 1.0) / s) << sum;
    EXPECT_EQ(f.y(), (g + 1.0) / s) << sum;
    EXPECT_EQ(f.z(), std::log(s / 3.0)) << sum;
  }
  EXPECT_EQ(colorFeature(o, std::array<std::uint8_t, 3>{0, 0, 0}.data()).z(), 0.0);  // black: ln 1
}

TEST(ColorClassifier, NonRoadIsFlatUntilAFrameShowsSomethingOffTheRoad) {
  const int w = 64, h = 64;
  const auto rgb = twoTone(w, h, false);
  std::vector<std::uint8_t> road(w * h, 0), non(w * h, 0);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w / 2; ++u) (v < h / 2 ? road : non)[v * w + u] = 1;  // both on the grey half
  ColorClassifierOptions o{.min_pixels = 50, .stride = 1, .nonroad_gate_sigma = 8};
  ColorClassifier c(o);
  const auto r = c.update(rgb.data(), w, h, road.data(), non.data());
  ASSERT_TRUE(c.trained()) << r.note;
  EXPECT_NE(r.note.find("non-road: flat"), std::string::npos) << r.note;
  EXPECT_EQ(c.nonroad().count, 0.0);
  const auto llr = c.logOdds(rgb.data(), w, h);
  int grey_road = 0, grass_road = 0;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) (u < w / 2 ? grey_road : grass_road) += llr[v * w + u] > 0;
  EXPECT_EQ(grey_road, w / 2 * h);
  EXPECT_EQ(grass_road, 0);
  // Without the gate the same labels give two classes of one colour (they do not separate).
  ColorClassifier plain(ColorClassifierOptions{.min_pixels = 50, .stride = 1});
  plain.update(rgb.data(), w, h, road.data(), non.data());
  EXPECT_LT(plain.separation(), 0.05);
}

TEST(Region, BlockReductionKeepsTheRoadAndDropsSpeckle) {
  const int w = 128, h = 96;
  Image road(w, h, 1), valid(w, h, 1), pred(w, h, 1);
  std::fill(valid.data.begin(), valid.data.end(), 255);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const bool in = u >= 40 && u < 90;
      pred.pixel(u, v)[0] = in ? 255 : 0;
      road.pixel(u, v)[0] = in ? 255 : 0;
    }
  // Speckle outside, holes inside.
  for (int k = 0; k < 40; ++k) {
    road.pixel((k * 37) % 30, (k * 53) % h)[0] = 255;
    road.pixel(45 + (k * 7) % 40, (k * 29) % h)[0] = 0;
  }
  // A blob on the right, 18 px from the road: the block closing joins its blocks to the road's, but
  // it is more than two blocks (16 px) from the road's pixels, so it is not a part split off by a line.
  for (int v = 10; v < 40; ++v)
    for (int u = 108; u < 126; ++u) road.pixel(u, v)[0] = 255;
  const RegionResult r = reproduceRegion(road, valid, pred);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.area_px, 50.0 * h);
  EXPECT_EQ(r.mask.pixel(110, 20)[0], 0);
  EXPECT_EQ(r.mask.pixel(60, 50)[0], 255);
  EXPECT_GE(r.contour.size(), 4u);
}

// A lane marking 6 px wide (wider than the pixel closing fills) splits the road into a left part of
// 38 columns and a right one of 36: both are the region's mask, the outline is the larger's; with
// min_part_fraction above 1 the mask is the larger part alone.
TEST(Region, KeepsThePartALaneMarkingSplitsOff) {
  const int w = 128, h = 96;
  Image road(w, h, 1), valid(w, h, 1), pred(w, h, 1);
  std::fill(valid.data.begin(), valid.data.end(), 255);
  for (int v = 0; v < h; ++v)
    for (int u = 20; u < 100; ++u) {
      pred.pixel(u, v)[0] = 255;
      road.pixel(u, v)[0] = (u >= 58 && u < 64) ? 0 : 255;
    }
  const RegionResult both = reproduceRegion(road, valid, pred);
  ASSERT_TRUE(both.found);
  EXPECT_EQ(both.area_px, (38.0 + 36.0) * h);
  EXPECT_EQ(both.mask.pixel(80, 50)[0], 255);
  EXPECT_EQ(both.mask.pixel(60, 50)[0], 0);
  double max_u = 0;
  for (const Vec2& p : both.contour) max_u = std::max(max_u, p.x());
  EXPECT_EQ(max_u, 57.0);
  RegionOptions main_only;
  main_only.min_part_fraction = 1.5;
  const RegionResult left = reproduceRegion(road, valid, pred, main_only);
  EXPECT_EQ(left.area_px, 38.0 * h);
  EXPECT_EQ(left.mask.pixel(80, 50)[0], 0);
}

// Holes: a 100 x 80 road with a 4 x 4 hole (a leaf: 16 px, 0.2 % of the area) and a 20 x 20 hole
// (a car: 400 px, 5 %). The default (2 %) fills the leaf and keeps the car out; 0 fills neither,
// 1 both; so do 5.1 % (408 px: the holes together are more, the car alone is not) and 6 % (480 px:
// more than both together).
TEST(Region, FillsSmallHolesAndLeavesLargeOnes) {
  const int w = 128, h = 96;
  Image road(w, h, 1), valid(w, h, 1), pred(w, h, 1);
  std::fill(valid.data.begin(), valid.data.end(), 255);
  for (int v = 8; v < 88; ++v)
    for (int u = 14; u < 114; ++u) road.pixel(u, v)[0] = pred.pixel(u, v)[0] = 255;
  for (int v = 20; v < 24; ++v)
    for (int u = 30; u < 34; ++u) road.pixel(u, v)[0] = 0;
  for (int v = 40; v < 60; ++v)
    for (int u = 60; u < 80; ++u) road.pixel(u, v)[0] = 0;
  RegionOptions o;
  o.pixel_morph_px = 0;  // closing would fill the leaf by itself
  const double outline = 100.0 * 80;
  for (const auto& [fraction, area] : {std::pair{0.02, outline - 400}, std::pair{0.0, outline - 416}, std::pair{1.0, outline},
                                       std::pair{0.051, outline}, std::pair{0.06, outline}}) {
    o.max_hole_fraction = fraction;
    const RegionResult r = reproduceRegion(road, valid, pred, o);
    ASSERT_TRUE(r.found);
    EXPECT_EQ(r.area_px, area) << fraction;
    EXPECT_EQ(r.mask.pixel(31, 21)[0], fraction > 0 ? 255 : 0) << fraction;
    EXPECT_EQ(r.mask.pixel(70, 50)[0], fraction > 0.05 ? 255 : 0) << fraction;
  }
  o.max_hole_fraction = 1.5;
  EXPECT_THROW(o.validate(), InvalidInput);
}

}  // namespace
}  // namespace mapnav

