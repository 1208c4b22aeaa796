// The oriented edge tracker (Wallace 1985, 3.1-3.2) on synthetic steps and simulated park-path frames.
#include "mapnav/vision/edge_tracker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/map/map_io.h"
#include "mapnav/map/predict.h"
#include "mapnav/sim/world.h"
#include "mapnav/testing/support.h"
#include "mapnav/vision/pipelines.h"

#include "eval_common.h"

namespace mapnav {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

using visiontest::park;
const Camera& cam() { return visiontest::pinhole(); }

/// A pose on R1 at `ds` m past the centre-line vertex nearest `vertex`, looking along the road.
Pose2 poseNear(const Vec2& vertex, double ds) {
  const Polyline2& line = park().road("R1").centerline;
  const double s = line.project(vertex).arc_length + ds;
  const Vec2 t = line.tangentAt(s);
  return {line.pointAt(s), std::atan2(t.y(), t.x())};
}

/// A pose on the second curve of R1 (about 36 m radius), `ds` m past its start: the pin-hole sees
/// both 3 m apart edges only from about 6 m to 12 m ahead, so the vehicle stands on the extension of
/// the centre line's chord from 6 m to 12 m ahead (about 1 m off the centre line), looking along it.
Pose2 curvePose(double ds = 2.0) {
  const Polyline2& line = park().road("R1").centerline;
  const double s = line.project(Vec2(119.931, 81.09)).arc_length + ds;
  const Vec2 p6 = line.pointAt(s + 6), p12 = line.pointAt(s + 12);
  const Vec2 u = (p12 - p6).normalized();
  return {p6 - 6 * u, std::atan2(u.y(), u.x())};
}
Pose2 straightPose() { return poseNear(Vec2(74.936, 27.467), 15.0); }

/// The true edge's projection into the image: dense ground points of the edge ahead of the camera.
std::vector<Vec2> projectedEdge(const Polyline2& edge, const Pose2& pose) {
  std::vector<Vec2> out;
  for (double s = 0; s <= edge.length(); s += 0.02) {
    const Vec2 g = pose.inverseTransform(edge.pointAt(s));
    if (g.x() < 0.5 || g.norm() > 40) continue;
    if (const auto p = cam().projectGround(g)) out.push_back(*p);
  }
  return out;
}

double distanceToPolyline(const std::vector<Vec2>& line, const Vec2& p) {
  double best = 1e18;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    if ((line[i + 1] - line[i]).norm() > 20) continue;  // a jump: not a neighbour
    best = std::min(best, Segment2{line[i], line[i + 1]}.distanceTo(p));
  }
  return best;
}

struct TrackRun {
  Frame frame;
  Prediction prediction;
  DetectedObject detected;
  EdgeTrackReport report;
};

/// The frame `world` renders at `pose` and time `t`, tracked against the view predicted from
/// `predicted_from` (in a closed loop: the Map's estimate).
TrackRun runAt(const World& world, const Pose2& pose, const Pose2& predicted_from, double t, EdgeTracker& tracker) {
  if (std::getenv("MAPNAV_EDGE_DUMP") != nullptr) {
    int shaded = 0, total = 0;
    for (double x = 2; x < 13; x += 0.5)
      for (double y = -3; y <= 3; y += 0.5, ++total) shaded += world.shadowAt(pose.transform(Vec2(x, y))) > 0.5;
    std::printf("%d of %d ground samples in view shaded\n", shaded, total);
  }
  TrackRun r;
  r.frame = world.render(cam(), pose, t);
  r.prediction = predictView(park(), predicted_from, cam());
  const VisionFrame vf{r.frame.rgb.width, r.frame.rgb.height, r.frame.rgb.data.data(), &cam(), t};
  r.detected = tracker.detect(vf, r.prediction.view);
  r.report = tracker.lastReport();
  if (std::getenv("MAPNAV_EDGE_DUMP") != nullptr) {
    static int k = 0;
    Image im = r.frame.rgb;
    auto put = [&](const Vec2& p, std::uint8_t R, std::uint8_t G, std::uint8_t B) {
      for (int dv = -1; dv <= 1; ++dv)
        for (int du = -1; du <= 1; ++du) {
          const int u = static_cast<int>(std::lround(p.x())) + du, v = static_cast<int>(std::lround(p.y())) + dv;
          if (u < 0 || v < 0 || u >= im.width || v >= im.height) continue;
          std::uint8_t* q = im.data.data() + 3 * (static_cast<std::size_t>(v) * im.width + u);
          q[0] = R; q[1] = G; q[2] = B;
        }
    };
    for (const auto& e : {r.report.left, r.report.right}) {
      put(e.start, 255, 0, 255);
      for (const Vec2& p : e.image) put(p, 255, 0, 0);
      std::printf("edge %s start (%.1f %.1f) dir (%.2f %.2f) pts %zu stop %s\n", e.label ? e.label->c_str() : "-",
                  e.start.x(), e.start.y(), e.start_direction.x(), e.start_direction.y(), e.image.size(),
                  e.stop_reason.c_str());
      for (std::size_t i = 0; i < e.image.size(); ++i)
        std::printf("   (%.1f %.1f) c %.1f\n", e.image[i].x(), e.image[i].y(), e.matches[i].contrast);
    }
    for (const auto& sg : r.prediction.view.segments)
      std::printf("seg %s side %s img (%.0f %.0f)-(%.0f %.0f)\n", sg.id.c_str(), sg.side.c_str(), sg.image.a.x(),
                  sg.image.a.y(), sg.image.b.x(), sg.image.b.y());
    const std::string path = "/tmp/edge_dump_" + std::to_string(k++) + ".ppm";
    std::FILE* f = std::fopen(path.c_str(), "wb");
    std::fprintf(f, "P6 %d %d 255\n", im.width, im.height);
    std::fwrite(im.data.data(), 1, im.data.size(), f);
    std::fclose(f);
  }
  return r;
}

/// The same at t = 0 in the default world with `shadow_density`, predicted from the true pose.
TrackRun runAt(const Pose2& pose, double shadow_density, EdgeTracker& tracker) {
  WorldOptions wo;
  wo.shadow_density = shadow_density;
  const World world(park(), wo);
  return runAt(world, pose, pose, 0.0, tracker);
}

/// The world of maps/missions/park_loop.json.
const World& parkLoopWorld() {
  static const World world = [] {
    WorldOptions wo;
    wo.seed = 1993;
    wo.shadow_density = 0.45;
    wo.leaf_density = 0.05;
    wo.noise_sigma = 2.5;
    return World(park(), wo);
  }();
  return world;
}

/// The largest distance of an edge's points from a true edge's projection, px.
double maxDistance(const TrackedEdge& e, const std::vector<Vec2>& true_edge) {
  double worst = 0;
  for (const Vec2& p : e.image) worst = std::max(worst, distanceToPolyline(true_edge, p));
  return worst;
}

/// On R4's 30 m left curve the pin-hole sees only the outer edge, R4's right (asphalt against
/// gravel): the tracker starts from the prediction and reports that edge alone (or fails).
void expectR4GravelEdgeAlone(const TrackRun& r, const std::string& what) {
  std::printf("%s: %s%s; %zu points, stop: %s\n", what.c_str(),
              r.detected.status == DetectedObject::Status::Ok ? "ok: " : "failed: ", r.detected.reason.c_str(),
              r.report.right.image.size(), r.report.right.stop_reason.c_str());
  ASSERT_EQ(r.report.start_source, "prediction");
  EXPECT_EQ(r.report.left.stop_reason, "not predicted in the image");
  ASSERT_TRUE(r.report.right.label.has_value());
  EXPECT_EQ(r.report.right.label->rfind("R4.right.", 0), 0u) << *r.report.right.label;
}

/// Max pixel error of the tracked points from the true edges (left/right of the vehicle).
void trackingErrors(const TrackRun& r, const Pose2& pose, double& left_max, double& right_max) {
  const Road& road = park().road("R1");
  // The pose looks along from → to, so the road's left edge is the vehicle's left.
  const auto left = projectedEdge(park().leftEdge(road), pose);
  const auto right = projectedEdge(park().rightEdge(road), pose);
  left_max = right_max = 0;
  for (const Vec2& p : r.report.left.image) left_max = std::max(left_max, distanceToPolyline(left, p));
  for (const Vec2& p : r.report.right.image) right_max = std::max(right_max, distanceToPolyline(right, p));
}

TEST(OrientedEdgeOperator, FindsASyntheticStepWithin1PxAnd2Deg) {
  for (const double angle_deg : {0.0, 30.0, -40.0, 63.0}) {
    GreyImage g;
    g.width = 512;
    g.height = 480;
    g.data.resize(static_cast<std::size_t>(g.width) * g.height);
    const Vec2 c0(256.3, 240.0);
    const Vec2 d(std::sin(angle_deg * kDeg), -std::cos(angle_deg * kDeg));  // along the edge, up the image
    const Vec2 n(-d.y(), d.x());
    for (int v = 0; v < g.height; ++v)
      for (int u = 0; u < g.width; ++u)
        g.data[static_cast<std::size_t>(v) * g.width + u] = (Vec2(u, v) - c0).dot(n) > 0 ? 140.0f : 60.0f;
    // Start 7 px off the edge, with a direction 6 degrees off.
    const Vec2 guess_dir(std::sin((angle_deg + 6) * kDeg), -std::cos((angle_deg + 6) * kDeg));
    const EdgeMatch m = orientedEdge(g, c0 + 7 * n, guess_dir, OrientedEdgeParams{});
    ASSERT_TRUE(m.found) << angle_deg;
    const double dist = std::abs((m.point - c0).dot(n));
    const double err_deg = std::acos(std::clamp(m.direction.dot(d), -1.0, 1.0)) / kDeg;
    EXPECT_LT(dist, 1.0) << angle_deg;
    EXPECT_LT(err_deg, 2.0) << angle_deg;
    EXPECT_NEAR(m.contrast, 80, 8) << angle_deg;
    EXPECT_GT(m.correlation, 0.8) << angle_deg;
  }
}

// The park map's colours (maps/park_path.json) and the simulator's tree shadow (WorldOptions:
// shadow_k 0.45, shadow_blue_shift 0.12: a colour times (0.45 x 0.88, 0.45, 0.45 x 1.12)).
TEST(GreyBand, NormalizedGreenSeparatesGrassFromAsphaltAndIgnoresTreeShadow) {
  const Vec3 asphalt(74, 74, 78), grass(70, 120, 50), shade(0.45 * 0.88, 0.45, 0.45 * 1.12);
  const Vec3 asphalt_shaded = asphalt.cwiseProduct(shade), grass_shaded = grass.cwiseProduct(shade);
  auto level = [](const Vec3& c, GreyBand band) { return bandLevel(c.x(), c.y(), c.z(), band); };
  // 255 (G + 1) / (R + G + B + 3): asphalt 255 x 75 / 229, grass 255 x 121 / 243.
  EXPECT_NEAR(level(asphalt, GreyBand::NormalizedGreen), 83.515, 1e-3);
  EXPECT_NEAR(level(grass, GreyBand::NormalizedGreen), 126.975, 1e-3);
  // Shaded asphalt (29.304, 33.3, 39.312): 255 x 34.3 / 104.916 = 83.367.
  EXPECT_NEAR(level(asphalt_shaded, GreyBand::NormalizedGreen), 83.367, 1e-3);
  // Shaded grass (27.72, 54, 25.2): 255 x 55 / 109.92 = 127.592.
  EXPECT_NEAR(level(grass_shaded, GreyBand::NormalizedGreen), 127.592, 1e-3);
  // In luminance the shadow's step on the asphalt (74.456 - 32.791 = 41.7) is four times the
  // shaded grass-to-asphalt step (42.859 - 32.791 = 10.1), the failure of the luminance tracker.
  EXPECT_NEAR(level(asphalt, GreyBand::Luminance) - level(asphalt_shaded, GreyBand::Luminance), 41.665, 1e-3);
  EXPECT_NEAR(level(grass_shaded, GreyBand::Luminance) - level(asphalt_shaded, GreyBand::Luminance), 10.069, 1e-3);
  EXPECT_DOUBLE_EQ(level(asphalt, GreyBand::Blue), 78);
  // A grey, black included, is at a third of 255.
  EXPECT_DOUBLE_EQ(level(Vec3(0, 0, 0), GreyBand::NormalizedGreen), 85);
  EXPECT_DOUBLE_EQ(level(Vec3(200, 200, 200), GreyBand::NormalizedGreen), 85);
}

// Dirt (maps/park_path.json: 122, 95, 68) has the asphalt's normalised green; its normalised red
// is a step of 25 levels, sunlit or shaded.
TEST(GreyBand, NormalizedRedSeparatesDirtFromAsphaltWhereTheGreenCannot) {
  const Vec3 asphalt(74, 74, 78), dirt(122, 95, 68), shade(0.45 * 0.88, 0.45, 0.45 * 1.12);
  auto level = [](const Vec3& c, GreyBand band) { return bandLevel(c.x(), c.y(), c.z(), band); };
  // Green: 255 x 96 / 288 = 85.0 against 83.515. Red: 255 x 123 / 288 = 108.906 against 255 x 75 / 229.
  EXPECT_NEAR(level(dirt, GreyBand::NormalizedGreen) - level(asphalt, GreyBand::NormalizedGreen), 1.485, 1e-3);
  EXPECT_NEAR(level(dirt, GreyBand::NormalizedRed), 108.906, 1e-3);
  EXPECT_NEAR(level(asphalt, GreyBand::NormalizedRed), 83.515, 1e-3);
  // Shaded: dirt (48.312, 42.75, 34.272) 255 x 49.312 / 128.334, asphalt 255 x 30.304 / 104.916.
  EXPECT_NEAR(level(dirt.cwiseProduct(shade), GreyBand::NormalizedRed) -
                  level(asphalt.cwiseProduct(shade), GreyBand::NormalizedRed),
              24.329, 1e-3);
}

// R2's 15 m hairpin (the pose of park_loop's frame 182, docs/measurements.md): the
// pin-hole sees only the inner edge, asphalt against dirt. In normalised green there is no step at
// its start; with the band from the prediction it is traced in normalised red along the true edge.
TEST(EdgeTracker, TracesADirtEdgeInTheBandItsPredictedColoursSeparate) {
  const Pose2 pose(Vec2(241.192, -39.055), -92.865 * kDeg);
  const auto trueRight = projectedEdge(park().rightEdge(park().road("R2")), pose);
  for (const bool from_prediction : {false, true}) {
    SCOPED_TRACE(from_prediction);
    EdgeTrackerOptions o;
    o.single_edge = true;
    o.band_from_prediction = from_prediction;
    EdgeTracker tracker(o);
    const TrackRun r = runAt(pose, 0.45, tracker);
    ASSERT_EQ(r.report.start_source, "prediction");
    EXPECT_EQ(r.report.left.stop_reason, "not predicted in the image");
    ASSERT_TRUE(r.report.right.label.has_value());
    EXPECT_EQ(r.report.right.label->rfind("R2.right.", 0), 0u) << *r.report.right.label;
    if (!from_prediction) {
      EXPECT_EQ(r.detected.status, DetectedObject::Status::Failed);
      EXPECT_EQ(r.report.right.stop_reason, "no step edge at the start point");
      continue;
    }
    ASSERT_EQ(r.detected.status, DetectedObject::Status::Ok) << r.detected.reason;
    EXPECT_EQ(r.report.right.band, GreyBand::NormalizedRed);
    EXPECT_GE(r.report.right.image.size(), 4u);
    const double worst = maxDistance(r.report.right, trueRight);
    std::printf("hairpin: %zu points, max %.2f px from the true edge, contrast %.1f\n", r.report.right.image.size(),
                worst, r.report.right.eval.contrast);
    EXPECT_LT(worst, 4.0);
    EXPECT_GT(r.report.right.eval.contrast, 15);
  }
}

// R4's 30 m left curve, park_loop's frame 413 (its world, the Map's estimate 0.75 m ahead and
// 1.35 deg off; the closed loop stood halted there from frame 411: the trace lost the edge at frames
// 410 and 412 on, and after resuming the vehicle left the path): the pin-hole
// sees only the outer edge, asphalt against gravel, entering at the image's right border and running
// up to the top. Gravel differs from asphalt in brightness only: 2.8 levels in normalised green, 6.6
// in normalised red (bandLevel of the map's colours), where the trace lost it under the texture;
// with min_normalised_step it is traced in luminance (60 levels) along the true edge to the top.
TEST(EdgeTracker, TracesAGravelEdgeFromTheImageBorderInLuminance) {
  const Appearance* gravel = park().findSurface("gravel");
  const Appearance* asphalt = park().findSurface("asphalt");
  ASSERT_TRUE(gravel != nullptr && asphalt != nullptr);
  auto step = [&](GreyBand b) {
    return bandLevel(gravel->rgb.x(), gravel->rgb.y(), gravel->rgb.z(), b) -
           bandLevel(asphalt->rgb.x(), asphalt->rgb.y(), asphalt->rgb.z(), b);
  };
  EXPECT_NEAR(step(GreyBand::NormalizedGreen), 2.76, 0.01);
  EXPECT_NEAR(step(GreyBand::NormalizedRed), 6.60, 0.01);
  EXPECT_NEAR(step(GreyBand::Luminance), 59.97, 0.01);

  const Pose2 pose(Vec2(326.0445, 277.4157), 29.827 * kDeg), estimate(Vec2(326.6453, 277.8713), 31.1769 * kDeg);
  const auto trueRight = projectedEdge(park().rightEdge(park().road("R4")), pose);
  for (const double min_step : {0.0, 12.0}) {
    SCOPED_TRACE(min_step);
    EdgeTrackerOptions o;
    o.min_normalised_step = min_step;
    EdgeTracker tracker(o);
    const TrackRun r = runAt(parkLoopWorld(), pose, estimate, 826.0, tracker);
    expectR4GravelEdgeAlone(r, min_step > 0 ? "min_normalised_step 12" : "min_normalised_step 0");
    EXPECT_GT(r.report.right.start.x(), 460);  // near the right border of the 512 px wide image
    if (min_step == 0) {
      EXPECT_EQ(r.report.right.band, GreyBand::NormalizedRed);
      EXPECT_EQ(r.detected.status, DetectedObject::Status::Failed);
      continue;
    }
    ASSERT_EQ(r.detected.status, DetectedObject::Status::Ok) << r.detected.reason;
    EXPECT_EQ(r.report.right.band, GreyBand::Luminance);
    EXPECT_TRUE(r.report.right.reached_top) << r.report.right.stop_reason;
    EXPECT_GE(r.report.right.image.size(), 8u);
    const double worst = maxDistance(r.report.right, trueRight);
    std::printf("gravel: max %.2f px from the true edge, contrast %.1f\n", worst, r.report.right.eval.contrast);
    EXPECT_LT(worst, 4.0);
    EXPECT_GT(r.report.right.eval.contrast, 30);
  }
}

// Farther along R4's curve, park_loop's frame 429 (its world, the Map's estimate 1.6 m ahead and
// 3.2 deg off): the gravel edge, traced in luminance, has shaded gravel beside it and sunlit gravel
// beyond, a larger step (59 to 134 levels) than asphalt against gravel in the same shade (33 to 59).
// Searching the whole window, the second point takes the shadow's edge and the trace turns too
// sharply (docs/measurements.md); gated, it follows the true edge from the image's side to the top.
TEST(EdgeTracker, GatesALuminanceEdgeAgainstTheShadowOnItsBrightShoulder) {
  const Pose2 truth(Vec2(340.0927, 297.272), 78.643 * kDeg), estimate(Vec2(340.3659, 298.851), 81.8239 * kDeg);
  const auto trueRight = projectedEdge(park().rightEdge(park().road("R4")), truth);
  for (const bool gate : {false, true}) {
    SCOPED_TRACE(gate);
    EdgeTrackerOptions o;
    o.gate_luminance = gate;
    EdgeTracker tracker(o);
    const TrackRun r = runAt(parkLoopWorld(), truth, estimate, 858.0, tracker);
    expectR4GravelEdgeAlone(r, gate ? "gated" : "not gated");
    EXPECT_EQ(r.report.right.band, GreyBand::Luminance);
    if (!gate) {
      EXPECT_EQ(r.report.right.label, std::optional<std::string>("R4.right.33"));
      EXPECT_LE(r.report.right.image.size(), 5u);
      continue;
    }
    ASSERT_EQ(r.detected.status, DetectedObject::Status::Ok) << r.detected.reason;
    EXPECT_EQ(r.report.right.label, std::optional<std::string>("R4.right.32"));  // the nearest segment
    EXPECT_GT(r.report.right.start.x(), 460);         // at the image's right side
    EXPECT_TRUE(r.report.right.reached_top) << r.report.right.stop_reason;
    EXPECT_GE(r.report.right.image.size(), 10u);
    const double worst = maxDistance(r.report.right, trueRight);
    std::printf("gated: max %.2f px from the true edge\n", worst);
    EXPECT_LT(worst, 2.0);
  }
}

// The same curve at park_loop's frame 421 (the Map's estimate 1.0 m ahead and 1.9 deg off): the
// nearest predicted segment, R4.right.30, enters at the image's right side; from its start the
// gated trace takes a shadow's edge on the gravel 16 px off the true one at the second point and
// turns too sharply at the third (the vehicle halted there 13 frames). The next segment's near end
// lies on the true edge: started again from it, the trace follows the edge to the top.
TEST(EdgeTracker, StartsAgainFromTheNextPredictedSegmentWhenTheEdgeIsLostAtTheImageSide) {
  const Pose2 truth(Vec2(339.0244, 293.4323), 70.8924 * kDeg), estimate(Vec2(339.342, 294.389), 72.8291 * kDeg);
  const auto trueRight = projectedEdge(park().rightEdge(park().road("R4")), truth);
  EdgeTracker tracker;
  const TrackRun r = runAt(parkLoopWorld(), truth, estimate, 842.0, tracker);
  ASSERT_EQ(r.report.start_source, "prediction");
  // The nearest segment: the lowest near end, at the image's right side.
  const InterestSegment* nearest = nullptr;
  for (const InterestSegment& sg : r.prediction.view.segments)
    if (nearest == nullptr || std::max(sg.image.a.y(), sg.image.b.y()) > std::max(nearest->image.a.y(), nearest->image.b.y()))
      nearest = &sg;
  ASSERT_NE(nearest, nullptr);
  EXPECT_EQ(nearest->id, "R4.right.30");
  EXPECT_GT(std::max(nearest->image.a.x(), nearest->image.b.x()), 500);
  ASSERT_EQ(r.detected.status, DetectedObject::Status::Ok) << r.detected.reason;
  ASSERT_TRUE(r.report.right.label.has_value());
  EXPECT_EQ(*r.report.right.label, "R4.right.31");
  EXPECT_TRUE(r.report.right.reached_top) << r.report.right.stop_reason;
  EXPECT_GE(r.report.right.image.size(), 7u);
  const double worst = maxDistance(r.report.right, trueRight);
  std::printf("started again: %zu points from %s, max %.2f px from the true edge\n", r.report.right.image.size(),
              r.report.right.label->c_str(), worst);
  EXPECT_LT(worst, 2.0);
  for (const DetectedLine& l : r.detected.lines) EXPECT_EQ(l.label, std::optional<std::string>("R4.right.31"));
}

// Just past R1's end at I2 (park_loop, frame 112 of the mission's run at 7724cc9's parent): the last
// metres of R1's right edge are the nearest edge in view, at the image's right side, beside both
// edges of R2. Traced alone, that stub had lost the frame ("left: not predicted in the image"); the
// tracker starts from R2, the nearest road with both edges in view.
TEST(EdgeTracker, StartsFromTheRoadWithBothEdgesInViewPastTheEndOfTheLast) {
  const Pose2 truth(Vec2(185.2585, 76.7698), -30.0429 * kDeg), estimate(Vec2(185.2593, 76.7632), -29.6827 * kDeg);
  EdgeTracker tracker;
  const TrackRun r = runAt(parkLoopWorld(), truth, estimate, 224.0, tracker);
  const auto& segments = r.prediction.view.segments;
  ASSERT_TRUE(std::any_of(segments.begin(), segments.end(), [](const InterestSegment& s) { return s.id.rfind("R1.right", 0) == 0; }));
  ASSERT_EQ(r.detected.status, DetectedObject::Status::Ok) << r.detected.reason;
  ASSERT_TRUE(r.report.left.label && r.report.right.label);
  EXPECT_EQ(r.report.left.label->rfind("R2.", 0), 0u) << *r.report.left.label;
  EXPECT_EQ(r.report.right.label->rfind("R2.", 0), 0u) << *r.report.right.label;
}

TEST(EdgeTracker, FollowsBothEdgesOfACurvingPathToTheTop) {
  // shadow_density 0.2 puts no tree shadow in these views; 0.4 shades about a tenth of the ground in
  // the views 0 and 4 m into the curve (and 40 % further on: see HeavyShadowFailsRatherThanMisleads).
  const std::vector<std::pair<double, double>> cases = {{0.0, 0.0}, {0.0, 4.0}, {0.0, 8.0}, {0.0, 12.0},
                                                        {0.4, 0.0}, {0.4, 4.0}};
  for (const auto& [shadows, ds] : cases) {
    SCOPED_TRACE(::testing::Message() << "shadow_density " << shadows << ", " << ds << " m into the curve");
    EdgeTracker tracker;
    const Pose2 pose = curvePose(ds);
    const TrackRun r = runAt(pose, shadows, tracker);
    ASSERT_EQ(r.report.start_source, "prediction");
    ASSERT_EQ(r.detected.status, DetectedObject::Status::Ok) << r.detected.reason;
    double lmax = 0, rmax = 0;
    trackingErrors(r, pose, lmax, rmax);
    std::printf("shadow %.1f ds %4.1f: left %zu pts max err %.2f px (top v %.1f), right %zu pts max err %.2f px (top v %.1f), "
                "width %.3f m sd %.3f angle %.2f deg, conf %.2f\n",
                shadows, ds, r.report.left.image.size(), lmax, r.report.left.image.back().y(),
                r.report.right.image.size(), rmax, r.report.right.image.back().y(), r.report.pair.width_m,
                r.report.pair.width_sd_m, r.report.pair.angle_deg, r.detected.confidence);
    EXPECT_LT(lmax, 4.0);
    EXPECT_LT(rmax, 4.0);
    for (const TrackedEdge* e : {&r.report.left, &r.report.right}) {
      EXPECT_TRUE(e->reached_top) << e->stop_reason;
      EXPECT_LT(e->image.back().y(), 64.0);  // the last window is near the top
      EXPECT_GE(e->image.size(), 6u);
      ASSERT_TRUE(e->label.has_value());
      EXPECT_EQ(e->label->rfind("R1.", 0), 0u) << *e->label;
      EXPECT_GT(e->eval.contrast, 10);
      EXPECT_GT(e->eval.consistency, 0.6);
    }
    EXPECT_NEAR(r.report.pair.width_m, 3.0, 0.3);
    ASSERT_TRUE(r.detected.centerline_vehicle.has_value());
    // The fitted centre line's ends lie near the true centre line (the curve's sagitta is ~0.1 m).
    const Polyline2& centre = park().road("R1").centerline;
    for (const Vec2& g : {r.detected.centerline_vehicle->a, r.detected.centerline_vehicle->b})
      EXPECT_LT((centre.project(pose.transform(g)).point - pose.transform(g)).norm(), 0.3);
    EXPECT_FALSE(r.detected.lines.empty());
    for (const DetectedLine& l : r.detected.lines) EXPECT_TRUE(l.label.has_value());
    EXPECT_GE(r.detected.region_image.size(), 6u);
    EXPECT_GT(r.detected.confidence, 0.3);
  }
}

TEST(EdgeTracker, HeavyShadowFailsRatherThanMisleads) {
  // 8 and 12 m into the curve, shadow_density 0.4 shades ~40 % of the ground in view, the right edge
  // mostly (the paper, 3.2.1: "we have had difficulty ... when shadows lie on the road"). The
  // tracker must then fail, or be right.
  for (const double ds : {8.0, 12.0}) {
    EdgeTracker tracker;
    const Pose2 pose = curvePose(ds);
    const TrackRun r = runAt(pose, 0.4, tracker);
    double lmax = 0, rmax = 0;
    trackingErrors(r, pose, lmax, rmax);
    std::printf("heavy shadow ds %4.1f: %s%s; left %zu pts max err %.2f px, right %zu pts max err %.2f px\n", ds,
                r.detected.status == DetectedObject::Status::Ok ? "ok" : "failed: ", r.detected.reason.c_str(),
                r.report.left.image.size(), lmax, r.report.right.image.size(), rmax);
    if (r.detected.status == DetectedObject::Status::Ok) {
      EXPECT_LT(lmax, 4.0) << ds;
      EXPECT_LT(rmax, 4.0) << ds;
    }
  }
}

TEST(EdgeTracker, ParallelismPassesOnAStraightStretchAndAWrongWidthIsFlagged) {
  {
    EdgeTracker tracker;
    const TrackRun r = runAt(straightPose(), 0.0, tracker);
    ASSERT_EQ(r.detected.status, DetectedObject::Status::Ok) << r.detected.reason;
    EXPECT_TRUE(r.report.pair.parallel_ok);
    EXPECT_TRUE(r.report.pair.width_ok);
    EXPECT_NEAR(r.report.pair.expected_width_m, 3.0, 0.05);  // from the prediction's relation
    EXPECT_NEAR(r.report.pair.width_m, 3.0, 0.3);
    EXPECT_LT(r.report.pair.angle_deg, 3.0);
    std::printf("straight: width %.3f m, sd %.3f, angle %.2f deg\n", r.report.pair.width_m, r.report.pair.width_sd_m,
                r.report.pair.angle_deg);
  }
  {
    EdgeTrackerOptions o;
    o.expected_width_m = 5.0;
    EdgeTracker tracker(o);
    const TrackRun r = runAt(straightPose(), 0.0, tracker);
    EXPECT_EQ(r.detected.status, DetectedObject::Status::Failed);
    EXPECT_NE(r.detected.reason.find("width"), std::string::npos) << r.detected.reason;
    EXPECT_TRUE(r.report.pair.parallel_ok);
    EXPECT_FALSE(r.report.pair.width_ok);
  }
}

TEST(EdgeTracker, CarriesThePreviousEdgesWithTheVehicleMotion) {
  EdgeTracker tracker;
  const Pose2 a = curvePose(0.0);
  const Pose2 b = a * Pose2(0.8, 0.0, -0.03);  // odometry: 0.8 m ahead, turning right
  const TrackRun first = runAt(a, 0.0, tracker);
  ASSERT_EQ(first.detected.status, DetectedObject::Status::Ok) << first.detected.reason;
  tracker.advance(a.inverse() * b);
  WorldOptions wo;
  wo.shadow_density = 0;
  const Frame f = World(park(), wo).render(cam(), b, 0.0);
  const VisionFrame vf{f.rgb.width, f.rgb.height, f.rgb.data.data(), &cam(), 0.0};
  const DetectedObject d = tracker.detect(vf, PredictedObject{});
  EXPECT_EQ(tracker.lastReport().start_source, "carried");
  ASSERT_EQ(d.status, DetectedObject::Status::Ok) << d.reason;
  EXPECT_NEAR(tracker.lastReport().pair.width_m, 3.0, 0.3);
}

TEST(EdgeTracker, LostEdgeFails) {
  // A flat grey frame: no edge at the option start points.
  std::vector<std::uint8_t> rgb(512 * 480 * 3, 100);
  EdgeTracker tracker;
  const VisionFrame vf{512, 480, rgb.data(), &cam(), 0.0};
  const DetectedObject d = tracker.detect(vf, PredictedObject{});
  EXPECT_EQ(tracker.lastReport().start_source, "options");
  EXPECT_EQ(d.status, DetectedObject::Status::Failed);
  EXPECT_NE(d.reason.find("lost"), std::string::npos) << d.reason;
}

// --- Starts from a predicted region (no interest segments: `mapnav eval`'s bootstrap trapezoid) ---

/// A 512 x 480 frame: asphalt (100, 100, 100) with grass (60, 140, 50) left of u = 40 + 0.5 (479 - v)
/// when `grass_left`, and right of u = 471 - 0.5 (479 - v) when `grass_right`.
std::vector<std::uint8_t> verges(bool grass_left, bool grass_right) {
  std::vector<std::uint8_t> rgb(512 * 480 * 3);
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 512; ++u) {
      const bool grass = (grass_left && u < 40 + 0.5 * (479 - v)) || (grass_right && u > 471 - 0.5 * (479 - v));
      std::uint8_t* p = &rgb[3 * (static_cast<std::size_t>(v) * 512 + u)];
      p[0] = grass ? 60 : 100;
      p[1] = grass ? 140 : 100;
      p[2] = grass ? 50 : 100;
    }
  return rgb;
}

/// The default bootstrap trapezoid of `mapnav eval` (bottom 0.5 wide at 0.98 h, top 0.2 wide at
/// 0.7 h) as the prediction's road region, on the ground.
PredictedObject trapezoidRegion() {
  PredictedRegion region;
  region.id = "train-region";
  Polygon2 ground;
  for (const Vec2& p : {Vec2(128, 470.4), Vec2(384, 470.4), Vec2(307.2, 336), Vec2(204.8, 336)})
    ground.push_back(*cam().backproject(p));
  region.vehicle = {ground};
  PredictedObject pred;
  pred.regions = {region};
  return pred;
}

/// The region's left and right columns on row v (its ring: left side bottom → top, then right).
std::pair<double, double> regionColumns(const DetectedObject& d, double v) {
  double l = 1e9, r = -1e9;
  for (const Vec2& p : d.region_image)
    if (std::abs(p.y() - v) < 0.5) l = std::min(l, p.x()), r = std::max(r, p.x());
  return {l, r};
}

TEST(EdgeTracker, FindsTheVergesFarOutsideAPredictedRegionsSides) {
  // The trapezoid's sides are at columns 128 and 384 at the bottom; the verges at 40 and 471, up to
  // 88 px outside them. The region between the found edges' lines reaches region_far_m (25 m).
  const std::vector<std::uint8_t> rgb = verges(true, true);
  EdgeTracker tracker;
  VisionFrame vf{512, 480, rgb.data(), &cam(), 0.0};
  vf.want_masks = true;
  const DetectedObject d = tracker.detect(vf, trapezoidRegion());
  EXPECT_EQ(tracker.lastReport().start_source, "region");
  ASSERT_EQ(d.status, DetectedObject::Status::Ok) << d.reason;
  EXPECT_EQ(d.reason, "");
  const auto [l, r] = regionColumns(d, 479);
  EXPECT_NEAR(l, 40, 2);
  EXPECT_NEAR(r, 471, 2);
  auto topRow = [](const DetectedObject& det) {
    double top = 1e9;
    for (const Vec2& p : det.region_image) top = std::min(top, p.y());
    return top;
  };
  // This camera sees 25 m ahead above the image (row -60): the region ends where the verges' lines
  // meet, row 479 - 431 = 48, at its last row of 4 px before it (51).
  ASSERT_LT(cam().projectGround(Vec2(25, 0))->y(), 0);
  EXPECT_EQ(topRow(d), 51);
  // With region_far_m 5 it ends at the row seeing 5 m ahead.
  EdgeTrackerOptions o;
  o.region_far_m = 5;
  EdgeTracker near(o);
  const double far_row = cam().projectGround(Vec2(5, 0))->y();
  ASSERT_GT(far_row, 60);
  const double top = topRow(near.detect(vf, trapezoidRegion()));
  EXPECT_GE(top, far_row - 1e-6);
  EXPECT_LT(top, far_row + 4);  // the region's rows are 4 px apart
  // Its per-pixel confidence: road inside (>= 129), not on the verge, none above the horizon.
  ASSERT_EQ(d.road_confidence.width, 512);
  EXPECT_GE(d.road_confidence.pixel(256, 420)[0], 129);
  EXPECT_LE(d.road_confidence.pixel(10, 470)[0], 10);
  EXPECT_LE(d.road_confidence.pixel(505, 470)[0], 10);
  int v_sky = 0;
  while (cam().backproject(Vec2(256, v_sky + 1)) == std::nullopt) ++v_sky;
  EXPECT_EQ(d.road_confidence.pixel(256, v_sky)[0], 0);
}

TEST(EdgeTracker, ASideWithoutAStepIsRoadToTheImagesSide) {
  // Grass on the right only: the left edge's search (up to the region's centre) finds no step and
  // does not take the right verge's; the road reaches the image's left side.
  const std::vector<std::uint8_t> rgb = verges(false, true);
  EdgeTracker tracker;
  const VisionFrame vf{512, 480, rgb.data(), &cam(), 0.0};
  const DetectedObject d = tracker.detect(vf, trapezoidRegion());
  ASSERT_EQ(d.status, DetectedObject::Status::Ok) << d.reason;
  EXPECT_NE(d.reason.find("left edge lost"), std::string::npos) << d.reason;
  const auto [l, r] = regionColumns(d, 479);
  EXPECT_EQ(l, 0);
  EXPECT_NEAR(r, 471, 2);
  EXPECT_TRUE(d.road_confidence.empty());  // not wanted
}

TEST(EdgeTrackerPipeline, RegisteredWithDocumentedOptions) {
  registerBuiltinPipelines();
  bool found = false;
  for (const PipelineInfo& info : listPipelines())
    if (info.name == "edge-tracker") {
      found = true;
      EXPECT_GE(info.options.size(), 15u);
      for (const OptionInfo& o : info.options) {
        EXPECT_FALSE(o.default_json.empty()) << o.name;
        EXPECT_NO_THROW(createPipeline("edge-tracker", "{\"" + o.name + "\": " + o.default_json + "}")) << o.name;
      }
    }
  EXPECT_TRUE(found);
  EXPECT_NO_THROW(createPipeline("edge-tracker", R"({"band": "luminance", "window_rows": 48})"));
  EXPECT_THROW(createPipeline("edge-tracker", R"({"band": "red"})"), InvalidInput);
  EXPECT_THROW(createPipeline("edge-tracker", R"({"no_such": 1})"), InvalidInput);
  EXPECT_THROW(createPipeline("edge-tracker", R"({"window_rows": 2})"), InvalidInput);
  EXPECT_THROW(createPipeline("edge-tracker", R"({"use_carried_edges": 1})"), InvalidInput);
}

}  // namespace
}  // namespace mapnav
