// The park-mode road finder of Jochem & Baluja 1993 ("cluster-perceptron") on simulator frames of
// maps/park_path.json (asphalt path between grass, dirt and gravel, shadow_density 0.4), seen by the
// Terregator pin-hole camera (512 x 480, 22 deg tilt).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

#include "eval_common.h"
#include "mapnav/core/error.h"
#include "mapnav/image/png.h"
#include "mapnav/map/predict.h"
#include "mapnav/sim/odometry.h"
#include "mapnav/sim/world.h"
#include "mapnav/vision/cluster_perceptron.h"
#include "mapnav/vision/pipelines.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {
namespace {

using visiontest::park;
const Camera& cam() { return visiontest::pinhole(); }

WorldOptions parkWorld() {
  WorldOptions wo;
  wo.shadow_density = 0.4;
  return wo;
}

/// A pose near a road's centre line, and the arc length s of the centre line's point it stands by
/// (the truth the tests measure against: the centre line from s on, in the road's direction).
struct RoadPose {
  Pose2 pose;
  const Road* road;
  double s;
};

/// Poses on straight stretches: the road's centre line is straight from 2 m behind to 25 m ahead.
std::vector<RoadPose> straightPoses(double step) {
  std::vector<RoadPose> out;
  int k = 0;
  const double lateral[] = {0.0, 0.2, -0.25, 0.1};
  const double dheading[] = {0.0, 2.0, -2.5, 1.0};
  for (const Road& road : park().roads()) {
    const Polyline2& line = road.centerline;
    for (double s = 3.0; s + 25.0 < line.length(); s += step) {
      const Vec2 t0 = line.tangentAt(s - 2.0);
      bool straight = true;
      for (double d = 0; d <= 25.0 && straight; d += 1.0) {
        const Vec2 t = line.tangentAt(s + d);
        straight = std::abs(std::atan2(t0.x() * t.y() - t0.y() * t.x(), t0.dot(t))) < 0.002;
      }
      if (!straight) continue;
      const Vec2 left(-t0.y(), t0.x());
      const double heading = std::atan2(t0.y(), t0.x()) + dheading[k % 4] * std::numbers::pi / 180.0;
      out.push_back({Pose2(line.pointAt(s) + lateral[k % 4] * left, heading), &road, s});
      ++k;
    }
  }
  return out;
}

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

/// The finder trained on the frame of `world` (rendered from `map`) at `pose`, bootstrapped from the
/// map's predicted road outline.
ClusterPerceptron trainedOn(const World& world, const Pose2& pose, double t, ClusterPerceptronOptions o = {},
                            const Map& map = park()) {
  const Frame f = world.render(cam(), pose, t);
  const Prediction pred = predictView(map, pose, cam());
  const Image outline = predictedRoadMask(pred.view, cam());
  ClusterPerceptron cp(o);
  cp.trainClusters(f.rgb.data.data(), f.rgb.width, f.rgb.height);
  cp.setRowWidths(trapezoidRowWidths(outline));
  cp.setCamera(cam());
  cp.trainPerceptron(f.rgb.data.data(), f.rgb.width, f.rgb.height, outline.data.data());
  return cp;
}

TEST(ClusterPerceptron, ReconstructionErrorFallsAndConverges) {
  const World world(park(), parkWorld());
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

TEST(ClusterPerceptron, PerceptronLearnsTheBootstrapOutline) {
  const World world(park(), parkWorld());
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
  const World world(park(), parkWorld());
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

// The Hough's two parameters (§5): the centre line's column at the top road row within 2 px of the
// truth, and its angle within 1 degree, on every straight frame. The offset at the bottom row is
// printed too: where the road fills the image's width there, it is extrapolated from the rows above.
TEST(ClusterPerceptron, HoughCentreLineOnStraightStretches) {
  const World world(park(), parkWorld());
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

/// Poses on bends: the centre line's heading turns by at least 10 degrees over the 12 m ahead, with a
/// radius of curvature of 15 m or more everywhere in between (the park's tightest bends are 15 m).
std::vector<RoadPose> curvePoses(double step) {
  std::vector<RoadPose> out;
  for (const Road& road : park().roads()) {
    const Polyline2& line = road.centerline;
    for (double s = 3.0; s + 14.0 < line.length(); s += step) {
      const Vec2 t0 = line.tangentAt(s), t1 = line.tangentAt(s + 12.0);
      const double turn = std::atan2(t0.x() * t1.y() - t0.y() * t1.x(), t0.dot(t1));
      if (std::abs(turn) < 10.0 * std::numbers::pi / 180.0) continue;
      out.push_back({Pose2(line.pointAt(s), std::atan2(t0.y(), t0.x())), &road, s});
    }
  }
  return out;
}

// The premise of the arc model: a pin-hole tilted over flat ground sees one ground distance x_r in
// each row, and there the column is affine in the lateral offset, u = a_r + b_r·y. Derivation
// (camera at height h, tilt φ, focal f): a ground point's depth Z = x·cos φ + h·sin φ and height
// Y = −x·sin φ + h·cos φ depend on x alone, so v = v_c + f·Y/Z fixes x; u = u_c − f·y/Z, b_r = −f/Z.
TEST(ClusterPerceptron, ArcModelPremiseRowsSeeOneDistanceAndMapOffsetsAffinely) {
  const double phi = 22.0 * std::numbers::pi / 180.0, h = 1.5, f = 904.0;
  for (const double x : {2.5, 4.0, 7.0, 11.0}) {
    const double Z = x * std::cos(phi) + h * std::sin(phi);
    const double v = 239.5 + f * (-x * std::sin(phi) + h * std::cos(phi)) / Z;
    for (const double y : {-4.0, -1.0, 0.0, 0.5, 3.0}) {
      const auto p = cam().projectGround(Vec2(x, y));
      ASSERT_TRUE(p.has_value());
      EXPECT_NEAR(p->y(), v, 1e-9) << "x " << x << " y " << y;         // the row: x alone
      EXPECT_NEAR(p->x(), 255.5 - f * y / Z, 1e-9) << "x " << x << " y " << y;  // affine in y
    }
  }
}

/// The road's true centre line projected into the image, from 2 m behind the pose to 16 m ahead,
/// every 5 cm (the points the camera sees).
std::vector<Vec2> truthCurve(const RoadPose& sp) {
  std::vector<Vec2> truth;
  for (double d = -2.0; d <= 16.0; d += 0.05)
    if (const auto p = cam().projectGround(sp.pose.inverseTransform(sp.road->centerline.pointAt(sp.s + d))))
      truth.push_back(*p);
  return truth;
}

/// The column where `curve` first crosses row v (linear between its points); nullopt when it does not.
std::optional<double> columnAt(const std::vector<Vec2>& curve, double v) {
  for (std::size_t k = 1; k < curve.size(); ++k)
    if ((curve[k - 1].y() - v) * (curve[k].y() - v) <= 0 && curve[k - 1].y() != curve[k].y())
      return curve[k - 1].x() + (v - curve[k - 1].y()) / (curve[k].y() - curve[k - 1].y()) * (curve[k].x() - curve[k - 1].x());
  return std::nullopt;
}

/// The worst column error of a found centre curve against the truth (the road's centre line
/// projected, sampled densely), over the curve's points whose true column is in the image.
double worstCurveError(const RoadFinding& r, const RoadPose& sp) {
  const std::vector<Vec2> truth = truthCurve(sp);
  double worst = 0;
  for (const Vec2& p : r.centerline_curve)
    if (const auto u = columnAt(truth, p.y()); u && *u >= 0 && *u < cam().width())
      worst = std::max(worst, std::abs(p.x() - *u));
  return worst;
}

/// The image angle error at the bottom of a found centre curve, degrees: the direction (du/dv) of its
/// last segment against the truth's (the road's centre line projected) between the same two rows.
double bottomAngleError(const RoadFinding& r, const RoadPose& sp) {
  if (r.centerline_curve.size() < 2) return 180.0;
  const Vec2 a = r.centerline_curve[r.centerline_curve.size() - 2], b = r.centerline_curve.back();
  const std::vector<Vec2> curve = truthCurve(sp);
  const auto truthAt = [&](double v) { return columnAt(curve, v).value_or(std::nan("")); };
  const double found = std::atan2(b.x() - a.x(), b.y() - a.y());
  const double truth = std::atan2(truthAt(b.y()) - truthAt(a.y()), b.y() - a.y());
  return std::isfinite(truth) ? std::abs(found - truth) * 180.0 / std::numbers::pi : 180.0;
}

/// The least worst column error any single circle on the ground can have on a frame, bounded from
/// above: the circle fitted to the true centre line (algebraic least squares, x² + y² + Dx + Ey + F =
/// 0, each point weighted by its row's pixels per metre) over the rows the image sees, evaluated like
/// a found curve (worstCurveError()) on the rows from `v_top` down, every 8. Where the road's
/// curvature changes in view (a straight running into a bend) or its polyline's 1.5 m chords leave
/// the circle by their sagitta (1.8 cm on 15 m bends: 7 px at the bottom row's 2 m), no circle
/// reaches 2 px.
double bestCircleError(const RoadPose& sp, double v_top) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (double d = -2.0; d <= 16.0; d += 0.1) {
    const Vec2 q = sp.pose.inverseTransform(sp.road->centerline.pointAt(sp.s + d));
    const auto p = cam().projectGround(q);
    const auto p1 = cam().projectGround(q + Vec2(0.0, 1.0));
    if (!p || !p1 || p->y() < -0.5 || p->y() > cam().height() - 0.5) continue;
    const double w2 = (*p1 - *p).squaredNorm();  // (pixels per metre)²
    const Eigen::Vector3d phi(q.x(), q.y(), 1.0);
    A += w2 * phi * phi.transpose();
    rhs -= w2 * phi * q.squaredNorm();
  }
  const Eigen::Vector3d sol = A.ldlt().solve(rhs);
  const double cx = -0.5 * sol[0], cy = -0.5 * sol[1], r2 = cx * cx + cy * cy - sol[2];
  RoadFinding circle;
  for (double v = v_top; v < cam().height(); v += 8) {
    const auto g = cam().backproject(Vec2(0.5 * (cam().width() - 1), v));
    if (!g || r2 < (g->x() - cx) * (g->x() - cx)) continue;
    const double h = std::sqrt(r2 - (g->x() - cx) * (g->x() - cx));
    const double y = std::abs(cy + h) < std::abs(cy - h) ? cy + h : cy - h;  // the branch through the vehicle
    if (const auto p = cam().projectGround(Vec2(g->x(), y))) circle.centerline_curve.push_back(*p);
  }
  return worstCurveError(circle, sp);
}

/// How many rows of the mask show the road's true edges: rows where a true edge (the centre line
/// ±1.5 m, projected) is in the image and the mask changes class within 3 px of it, over both
/// edges (`shown`); in how many rows a true edge is in the image (`in_image`); and the ground distance
/// ahead of the nearest edge shown (`nearest_m`, infinite when none is).
struct EdgeRows {
  int shown = 0, in_image = 0;
  double nearest_m = std::numeric_limits<double>::infinity();
};
EdgeRows trueEdgeRowsInMask(const Image& mask, const RoadPose& sp) {
  EdgeRows rows;
  for (const double side : {1.5, -1.5}) {
    int last = -1;
    for (double d = -2.0; d <= 16.0; d += 0.05) {
      const Vec2 t = sp.road->centerline.tangentAt(sp.s + d);
      const Vec2 g = sp.road->centerline.pointAt(sp.s + d) + side * Vec2(-t.y(), t.x());
      const auto p = cam().projectGround(sp.pose.inverseTransform(g));
      if (!p) continue;
      const int v = static_cast<int>(std::lround(p->y())), u = static_cast<int>(std::lround(p->x()));
      if (v == last || v < 0 || v >= mask.height || u < 3 || u > mask.width - 4) continue;
      last = v;
      ++rows.in_image;
      bool change = false;
      for (int k = u - 2; k <= u + 3; ++k)
        change = change || mask.data[static_cast<std::size_t>(v) * mask.width + k] !=
                               mask.data[static_cast<std::size_t>(v) * mask.width + k - 1];
      rows.shown += change;
      if (change) rows.nearest_m = std::min(rows.nearest_m, sp.pose.inverseTransform(g).x());
    }
  }
  return rows;
}

/// The column error of a found centre curve at its first (top) row against the truth (the road's
/// centre line projected); 0 where the true centre is outside the image on that row (on tight bends
/// it leaves the image's side), as in worstCurveError(); 1e9 when the truth does not cross that row.
double topRowError(const RoadFinding& r, const RoadPose& sp) {
  if (r.centerline_curve.empty()) return 1e9;
  const Vec2 top = r.centerline_curve.front();
  const auto u = columnAt(truthCurve(sp), top.y());
  if (!u) return 1e9;
  return *u >= 0 && *u < cam().width() ? std::abs(top.x() - *u) : 0.0;
}

/// For looking at a frame (ARC_PNG_DIR set): <dir>/frame_<i>.png, the frame with the true centre line
/// (green) and edges (yellow), the arc model's curve (red) and the straight model's (blue), beside the
/// arc model's mask and the true road mask.
void writeArcPicture(const std::string& dir, std::size_t i, const Frame& f, const RoadFinding& arc,
                     const RoadFinding& line, const RoadPose& sp) {
  Image pic(3 * f.rgb.width, f.rgb.height, 3);
  for (int v = 0; v < f.rgb.height; ++v)
    for (int u = 0; u < f.rgb.width; ++u) {
      std::copy_n(f.rgb.pixel(u, v), 3, pic.pixel(u, v));
      std::fill_n(pic.pixel(f.rgb.width + u, v), 3, arc.mask.empty() ? 0 : arc.mask.pixel(u, v)[0]);
      std::fill_n(pic.pixel(2 * f.rgb.width + u, v), 3, f.mask.pixel(u, v)[0]);
    }
  const auto dot = [&](double u, double v, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    const int iu = static_cast<int>(std::lround(u)), iv = static_cast<int>(std::lround(v));
    for (const int side : {0, f.rgb.width})
      if (iu >= 0 && iu < f.rgb.width && iv >= 0 && iv < f.rgb.height) {
        std::uint8_t* p = pic.pixel(iu + side, iv);
        p[0] = r;
        p[1] = g;
        p[2] = b;
      }
  };
  const auto draw = [&](const std::vector<Vec2>& curve, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    for (std::size_t k = 1; k < curve.size(); ++k)
      for (double t = 0; t <= 1.0; t += 0.02)
        dot(curve[k - 1].x() + t * (curve[k].x() - curve[k - 1].x()), curve[k - 1].y() + t * (curve[k].y() - curve[k - 1].y()),
            r, g, b);
  };
  draw(truthCurve(sp), 0, 255, 0);
  for (const double side : {1.5, -1.5}) {  // the road's true edges
    std::vector<Vec2> edge;
    for (double d = -2.0; d <= 16.0; d += 0.05) {
      const Vec2 t = sp.road->centerline.tangentAt(sp.s + d);
      if (const auto p = cam().projectGround(sp.pose.inverseTransform(sp.road->centerline.pointAt(sp.s + d) + side * Vec2(-t.y(), t.x()))))
        edge.push_back(*p);
    }
    draw(edge, 255, 255, 0);
  }
  draw(line.centerline_curve, 0, 0, 255);
  draw(arc.centerline_curve, 255, 0, 0);
  char name[32];
  std::snprintf(name, sizeof name, "/frame_%03zu.png", i);
  writePng(pic, dir + name);
}

/// Per frame, the worst column error of the arc model's and of the straight model's centre curve
/// (each retrained on the first frame of each road, frozen along it), the arc's curvature, its
/// angle error at the bottom row, the first row of its curve, and whether it found a centre line
/// (failed frames count as an error of 1e9 px); the top-row offsets (topRowError()) of both models
/// and the straight model's bottom angle error.
struct ArcVsLine {
  std::vector<double> arc, line, curvature, angle, v_top, top, line_top, line_angle;
  std::vector<double> bottom_sd;  // the arc model's RoadFinding::bottom_column_sd
  std::vector<EdgeRows> edge_rows;  // trueEdgeRowsInMask() of the arc model's mask
  std::vector<std::size_t> failed;
  std::vector<std::string> failed_reason;
  std::vector<double> edge_px;  // the arc fit's ground edges: each one's offset from the true edge, px
};
/// With `bootstrap_s`, each road's models are trained on the frame at that arc length of the road (on
/// its centre line, looking along it) instead of on the road's first pose.
/// `world_options`: the renderer's; `arc_options`: the arc model's (road_model set to Arc here).
ArcVsLine arcVsLine(const std::vector<RoadPose>& poses, const Map& map = park(),
                    std::optional<double> bootstrap_s = std::nullopt, const WorldOptions& world_options = parkWorld(),
                    ClusterPerceptronOptions arc_options = {}) {
  const World world(map, world_options);
  ClusterPerceptronOptions& o = arc_options;
  o.road_model = RoadModel::Arc;
  std::optional<ClusterPerceptron> arc, line;
  ArcVsLine out;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (i == 0 || poses[i].road != poses[i - 1].road) {
      Pose2 at = poses[i].pose;
      if (bootstrap_s) {
        const Polyline2& line = poses[i].road->centerline;
        at = Pose2(line.pointAt(*bootstrap_s), line.headingAt(*bootstrap_s));
      }
      arc = trainedOn(world, at, static_cast<double>(i), o, map);
      line = trainedOn(world, at, static_cast<double>(i), {}, map);
    }
    const Frame f = world.render(cam(), poses[i].pose, static_cast<double>(i));
    const RoadFinding ra = arc->find(f.rgb.data.data(), f.rgb.width, f.rgb.height, true);
    const RoadFinding rl = line->find(f.rgb.data.data(), f.rgb.width, f.rgb.height, false);
    EXPECT_TRUE(rl.ok) << "frame " << i << ": " << rl.reason;
    if (!ra.ok) {
      out.failed.push_back(i);
      out.failed_reason.push_back(ra.reason);
    }
    out.arc.push_back(ra.ok ? worstCurveError(ra, poses[i]) : 1e9);
    out.line.push_back(rl.ok ? worstCurveError(rl, poses[i]) : 1e9);
    out.curvature.push_back(ra.curvature);
    out.bottom_sd.push_back(ra.bottom_column_sd);
    out.angle.push_back(ra.ok ? bottomAngleError(ra, poses[i]) : 180.0);
    out.v_top.push_back(ra.ok ? ra.centerline_curve.front().y() : 0.0);
    out.edge_rows.push_back(trueEdgeRowsInMask(ra.mask, poses[i]));
    out.top.push_back(ra.ok ? topRowError(ra, poses[i]) : 1e9);
    out.line_top.push_back(rl.ok ? topRowError(rl, poses[i]) : 1e9);
    out.line_angle.push_back(rl.ok ? bottomAngleError(rl, poses[i]) : 180.0);
    for (const RoadEdgePoint& g : ra.ground_edges) {
      const auto at = poses[i].road->centerline.project(poses[i].pose.transform(g.p));
      out.edge_px.push_back((at.lateral - 0.5 * g.side * poses[i].road->width) * g.px_per_m);
    }
    if (const char* dir = std::getenv("ARC_PNG_DIR")) writeArcPicture(dir, i, f, ra, rl, poses[i]);
  }
  return out;
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

// Beyond the paper (§9): with the ground-arc model the found centre curve follows the park map's real
// bends far better than the paper's straight model, which cuts them. These bends are not the issue's
// "curves of radius >= 15 m" as written: many frames see a straight running into a bend (curvature
// changing in view) and the map's curves are polylines of 1.5 m chords; the item as written is
// measured on true circles by ArcModelWithinTwoPixelsAndOneDegreeOnCircularCurves. Measured per frame
// here: the worst column error over the block rows where the road's centre is in the image. The
// circle fitted to the edges on the ground, started from the image fit and from a consensus of exact
// circles on the ground, each required to keep the vehicle on the road, puts the median frame within
// 3.2 px and three frames in four within 10 px. Measured: median 3.12, 75 % 9.91, 90 % 49.7 px, worst
// found 386 px (frame 105, which failed before the ground consensus drew 1000 samples instead of 300),
// 1 frame failed (no centre line puts the vehicle on the road); 39 frames <= 2 px, 59 <= 3 px, 80
// <= 5 px, 94 <= 10 px; angle error at the bottom row median 1.37 deg, <= 1 deg on 49 frames. NOT the
// issue's 2 px everywhere, and the test prints each frame off it with its cause: on 38 frames no circle
// on the ground comes within 2 px of the true centre line (bestCircleError(): a straight running into
// a bend, up to 22 px; the map's 1.5 m chords on 15 m bends, 3.0-3.6 px); on the 87 where a circle
// can, the arc model meets 2 px on 36. The rest miss because the mask shows under half of the road's
// true edge rows (shoulders classed as road; the boundary beyond the shoulder is then fitted as the
// road's edge) or, with the edges in view, the circle is extrapolated from the edges (seen only beyond
// ~4.5 m: the 3 m road fills the image, 1.4 m wide at the bottom) to the bottom rows, where 1 cm is
// 3.7 px.
TEST(ClusterPerceptron, ArcModelFollowsCurves) {
  const auto poses = curvePoses(3.0);
  ASSERT_GE(poses.size(), 100u);
  const ArcVsLine e = arcVsLine(poses);
  const std::size_t n = e.arc.size();
  int better = 0;
  for (std::size_t i = 0; i < n; ++i) {
    better += e.arc[i] < e.line[i];
    EXPECT_LE(std::abs(e.curvature[i]), ClusterPerceptronOptions{}.max_curvature) << "frame " << i;
  }
  const auto within = [&](double px) { return std::count_if(e.arc.begin(), e.arc.end(), [&](double x) { return x <= px; }); };
  double worst_found = 0;
  for (const double x : e.arc)
    if (x < 1e9) worst_found = std::max(worst_found, x);
  std::printf("on %zu curve frames, worst column error per frame (failed frames count as 1e9 px): arc model median %.2f "
              "px, 75%% %.2f px, 90%% %.2f px, worst found %.2f px, <= 2 px on %td, <= 3 px on %td, <= 5 px on %td, <= 10 "
              "px on %td; straight model median %.2f px; the arc is better on %d\n",
              n, quantile(e.arc, 0.5), quantile(e.arc, 0.75), quantile(e.arc, 0.9), worst_found, within(2.0),
              within(3.0), within(5.0), within(10.0), quantile(e.line, 0.5), better);
  // The frames off the issue's 2 px, each with its cause: the best any circle can do (no single
  // circle follows a straight running into a bend), and how much of the road's true edges the mask
  // shows (shoulders classed as road hide them; the boundary beyond the shoulder is then taken
  // for the road's edge).
  int circle_reaches = 0, met_where_reachable = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double best = e.arc[i] < 1e9 ? bestCircleError(poses[i], e.v_top[i]) : std::nan("");
    circle_reaches += best <= 2.0;
    met_where_reachable += best <= 2.0 && e.arc[i] <= 2.0;
    if (e.arc[i] <= 2.0) continue;
    const char* cause = e.arc[i] >= 1e9 ? "failed: no centre line puts the vehicle on the road"
                        : best > 2.0   ? "no circle within 2 px of the truth (curvature changing in view, or 15 m bends' chords)"
                        : 2 * e.edge_rows[i].shown < e.edge_rows[i].in_image ? "the mask shows under half the true edges' rows"
                                                                              : "circle off the edges' circle";
    std::printf("  frame %3zu: %7.2f px, bottom angle %5.2f deg, best circle %6.2f px, true edge rows in the mask "
                "%3d / %3d: %s\n",
                i, e.arc[i], e.angle[i], best, e.edge_rows[i].shown, e.edge_rows[i].in_image, cause);
  }
  const auto angle_within = [&](double deg) { return std::count_if(e.angle.begin(), e.angle.end(), [&](double x) { return x <= deg; }); };
  std::printf("a circle reaches 2 px on %d frames, the arc model meets 2 px on %d of them; bottom-row angle error "
              "median %.2f deg, 75%% %.2f deg, <= 1 deg on %td; failed frames %zu\n",
              circle_reaches, met_where_reachable, quantile(e.angle, 0.5), quantile(e.angle, 0.75), angle_within(1.0),
              e.failed.size());
  EXPECT_LE(e.failed.size(), 2u);
  for (const std::string& reason : e.failed_reason)  // only where no fit keeps the vehicle on its road
    EXPECT_NE(reason.find("within half the road's width of the vehicle"), std::string::npos) << reason;
  EXPECT_GE(circle_reaches, static_cast<int>(0.6 * static_cast<double>(n)));
  EXPECT_GE(met_where_reachable, static_cast<int>(0.4 * static_cast<double>(circle_reaches)));
  EXPECT_GE(angle_within(1.0), static_cast<std::ptrdiff_t>(0.35 * static_cast<double>(n)));
  EXPECT_LE(quantile(e.arc, 0.5), 3.5);
  EXPECT_LE(quantile(e.arc, 0.75), 12.0);
  EXPECT_GE(within(3.0), static_cast<std::ptrdiff_t>(0.45 * static_cast<double>(n)));
  EXPECT_GE(within(10.0), static_cast<std::ptrdiff_t>(0.7 * static_cast<double>(n)));
  EXPECT_GE(quantile(e.line, 0.5), 25.0 * quantile(e.arc, 0.5)) << "the straight model cuts the curves";
  EXPECT_GE(better, static_cast<int>(0.85 * static_cast<double>(n)));
}

// On straight stretches the arc model is no worse than the straight one: where the curvature does
// not pay for its parameter (BIC on the edges' residuals) the line on the ground is kept. Measured:
// arc median 0.26 px, 75 % 1.30, 90 % 3.55, worst 166 px; <= 2 px on 19 of 24, <= 3 px on 20, <= 5 px
// on 22, <= 10 px on 23; bottom-row angle median 0.02 deg (worst 26 deg, the worst frame's); line
// median 2.82 px, worst 495 px. The arc's worst frame is a circle through 43 rows of the right edge,
// seen only in the top right corner (the left shoulder is classed as road), extrapolated to the bottom;
// it keeps the vehicle on the road, so the on-road rule does not reject it.
TEST(ClusterPerceptron, ArcModelOnStraightStretches) {
  const auto poses = straightPoses(8.0);
  ASSERT_GE(poses.size(), 20u);
  const ArcVsLine e = arcVsLine(poses);
  int as_good = 0;
  for (std::size_t i = 0; i < e.arc.size(); ++i) as_good += e.arc[i] <= e.line[i] + 1.0;
  const auto within = [&](double px) { return std::count_if(e.arc.begin(), e.arc.end(), [&](double x) { return x <= px; }); };
  std::printf("on %zu straight frames, worst column error per frame: arc model median %.2f px, 75%% %.2f px, 90%% %.2f "
              "px, worst %.2f px, <= 2 px on %td, <= 3 px on %td, <= 5 px on %td, <= 10 px on %td; bottom-row angle "
              "median %.2f deg, worst %.2f deg; straight model median %.2f px, worst %.2f px; the arc within 1 px of "
              "the line on %d\n",
              e.arc.size(), quantile(e.arc, 0.5), quantile(e.arc, 0.75), quantile(e.arc, 0.9), quantile(e.arc, 1.0),
              within(2.0), within(3.0), within(5.0), within(10.0), quantile(e.angle, 0.5), quantile(e.angle, 1.0),
              quantile(e.line, 0.5), quantile(e.line, 1.0), as_good);
  EXPECT_TRUE(e.failed.empty());
  EXPECT_GE(within(2.0), static_cast<std::ptrdiff_t>(0.75 * static_cast<double>(e.arc.size())));
  EXPECT_LE(quantile(e.angle, 0.5), 1.0);
  EXPECT_LE(quantile(e.arc, 0.5), quantile(e.line, 0.5));
  EXPECT_LE(quantile(e.arc, 1.0), quantile(e.line, 1.0));
  EXPECT_GE(as_good, static_cast<int>(0.85 * static_cast<double>(e.arc.size())));
}

/// Scenes of true circular curves, the issue's "curves of radius >= 15 m": for each radius of
/// kCircleRadii a left and a right turn (in that order), each a road of the park's 3 m asphalt between
/// grass: kCircleLeadIn m straight (where the finder is bootstrapped, §4: the outline a trapezoid),
/// then kCircleLength m of the circle, tangent to it. The centre line sampled every 0.2 m (sagitta
/// 0.2² / 8R: 0.33 mm on 15 m); each road 300 m from the next so that none sees another. 41 m of a
/// 15 m circle turn 157 degrees: the road behind a pose never comes back into view.
constexpr double kCircleRadii[] = {15.0, 20.0, 30.0, 50.0};
constexpr double kCircleLeadIn = 14.0, kCircleLength = 41.0;
const Map& circles() {
  static const Map map = [] {
    MapData data;
    data.name = "circular curves";
    data.surfaces = park().data().surfaces;
    int k = 0;
    for (const double radius : kCircleRadii)
      for (const double turn : {1.0, -1.0}) {  // left, right
        const Vec2 o(0.0, 300.0 * k);
        std::vector<Vec2> pts;
        for (int j = 0; j < static_cast<int>(kCircleLeadIn / 0.2); ++j) pts.push_back(o + Vec2(0.2 * j, 0.0));
        const int n = static_cast<int>(std::ceil(kCircleLength / 0.2));
        for (int j = 0; j <= n; ++j) {
          const double a = kCircleLength * j / n / radius;
          pts.push_back(o + Vec2(kCircleLeadIn + radius * std::sin(a), turn * radius * (1.0 - std::cos(a))));
        }
        const std::string id = std::to_string(k);
        data.intersections.push_back({"A" + id, IntersectionKind::End, pts.front(), std::nullopt});
        data.intersections.push_back({"B" + id, IntersectionKind::End, pts.back(), std::nullopt});
        Road road;
        road.id = "C" + id;
        road.from = "A" + id;
        road.to = "B" + id;
        road.centerline = Polyline2(pts);
        road.width = 3.0;
        road.surface = "asphalt";
        road.left = road.right = "grass";
        data.roads.push_back(road);
        ++k;
      }
    return Map(data, "circular curves");
  }();
  return map;
}

/// Poses on the circles every `step` m, from 2 m into the circle to 17 m before the road's end (the
/// centre line is the circle from 2 m behind to 16 m ahead, all the camera sees: its top row is 12 m
/// ahead), with lateral (±0.2 m) and heading (±2 degrees) offsets in a fixed pattern, as straightPoses().
std::vector<RoadPose> circlePoses(double step) {
  std::vector<RoadPose> out;
  int k = 0;
  const double lateral[] = {0.0, 0.2, -0.2, 0.1};
  const double dheading[] = {0.0, 2.0, -2.0, 1.0};
  for (const Road& road : circles().roads()) {
    const Polyline2& line = road.centerline;
    for (double s = kCircleLeadIn + 2.0; s + 17.0 <= line.length() + 1e-9; s += step, ++k) {
      const Vec2 t = line.tangentAt(s), left(-t.y(), t.x());
      const double heading = std::atan2(t.y(), t.x()) + dheading[k % 4] * std::numbers::pi / 180.0;
      out.push_back({Pose2(line.pointAt(s) + lateral[k % 4] * left, heading), &road, s});
    }
  }
  return out;
}

// The issue's item as written: on curves of constant radius >= 15 m (circles(): true circles of 15,
// 20, 30 and 50 m, left and right, 3 m asphalt between grass, the park's shadows; 11 poses on each,
// ±0.2 m and ±2 deg off the centre line) the arc model's centre line within 2 px of the truth (the
// worst column error over the curve's rows where the true centre is in the image; the top-row offset
// is one of them, counted where the true centre is in the image on that row: on 15 m bends it leaves
// the image's side above) and its image angle at the bottom row within 1 degree. The finder is
// bootstrapped on each road's straight lead-in (§4: a trapezoid outline). Bootstrapped on the circle
// itself, the outline touches the image's sides in every row, its per-row widths are the clipped
// extents (1.4-2.8 m of the 3 m road), and the centre lines are put decimetres off the road's edge's
// (median worst column error 137-209 px per radius, measured before the change to 1000 draws).
// Measured: within 2 px and 1 deg on 81 of 88 frames, within 4 px and 1.1 deg on 87; per radius (arc
// | straight model, worst column error median / max): 15 m 0.40 / 3.51 px | 95 / 732 px, 20 m 0.35 /
// 1.23 | 104 / 989, 30 m 0.34 / 136 | 88 / 605, 50 m 0.28 / 2.16 | 61 / 207; bottom angle max 1.02,
// 0.52, 20.3, 0.33 deg; top-row offset max 0.21 px (20 m), 2.65 (30 m), 0.28 (50 m). NOT every frame:
// six miss by 2.1-3.5 px, each seeing the road's edges only from 5-8 m ahead (the 3 m road fills the
// image below), so that the circle is extrapolated to the bottom row 2 m ahead, where 1 cm is 3.7 px;
// one (30 m, right) misses by 136 px: shadowed grass classed as road hides all but the top 51 rows
// of the outer edge, and a circle through the shadows' outline gathers more edges.
// The six are the edges' information, not the fit's: their edges lie on the true edge with the pixel
// quantisation's spread alone (measured against the projected true edges: mean 0.00-0.06 px, RMS
// 0.27-0.30 px on frames 1, 5, 19, 63 (its 51 rows); 0.4-1.3 px on 62, 64, 69), and least squares on
// them leaves the bottom row's column a standard error (RoadFinding::bottom_column_sd) of 0.84-6.0
// px; each miss is within three of its standard errors, which the test asserts. But the edges seen
// were few and far because shaded grass classed as road hid the nearer ones: the masks show 9 949 of
// the 13 527 true edge rows in view; in normalised colour 13 491, and all six pass (the next test).
// Tried and not kept (measured on this test): minimising Σ|r|⁴ over the edges within 1 px of the
// fit (for uniform quantisation noise it converges faster than least squares): 56 of 88 (the mask's
// edges are not independent uniform errors, and the largest residuals are its ragged runs);
// penalising a circle for each row where its edge falls in the image but the mask holds road on
// both sides of it: 75 of 88 and one failed frame (shadowed grass classed as road beyond the true
// edge contradicts the true circle on most 15-20 m frames), frame 63 136 -> 59 px; MSAC in the
// ground consensus (per row side Σ(2² − r²)⁺): 81 of 88 unchanged, frame 63's shadow circle still
// scores higher than the true one (ArcModelOnStraightStretches' worst 166 -> 5.8 px, but
// ArcModelFollowsCurves <= 2/3/5/10 px each one frame fewer). Frame 63 wants a mask that tells the
// shadowed grass from the road, not another fit (normalised colour is one:
// ArcModelInNormalisedColour... below meets 88 of 88): by edge count and by residual the shadows'
// outline is the better circle, and the mask's own classes (road beyond the true edge) move the fit
// only to 59 px. The road filling the image below the nearest edge bounds the centre only to ±0.8 m
// at the bottom row (the 3 m road against the image's 1.4 m): no help at 1 cm.
// Under AddressSanitizer rendering is about ten times slower: the carried-edges drive (450 frames
// rendered) took over the stage's 900 s. There it covers the 15 m left circle alone, the area-sampled
// circles test the 15 m circles, and only their per-frame and edge assertions are checked.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

double circleRadiusOf(const RoadPose& p) {
  return kCircleRadii[static_cast<std::size_t>(p.road - circles().roads().data()) / 2];
}

/// An arcVsLine() on circlePoses(), scored: per radius the worst column errors of both models, every
/// frame off 2 px or 1 degree with its cause, and the counts. With `expect_within_3sd`, each miss
/// where the mask shows the road's true edges is expected within three of its bottom_column_sd.
struct CircleScore {
  int met = 0, within4 = 0, top_met = 0, arc_better = 0;
};
CircleScore scoreCircles(const std::vector<RoadPose>& poses, const ArcVsLine& e, bool expect_within_3sd = true) {
  for (const double radius : kCircleRadii) {
    std::vector<double> arc, top, angle, line, line_top, line_angle;
    for (std::size_t i = 0; i < poses.size(); ++i) {
      if (circleRadiusOf(poses[i]) != radius) continue;
      arc.push_back(e.arc[i]);
      top.push_back(e.top[i]);
      angle.push_back(e.angle[i]);
      line.push_back(e.line[i]);
      line_top.push_back(e.line_top[i]);
      line_angle.push_back(e.line_angle[i]);
    }
    if (arc.empty()) continue;
    std::printf("radius %2.0f m, %zu frames: arc model worst column error median %.2f px, max %.2f px; top-row offset "
                "max %.2f px; bottom angle max %.2f deg | straight model median %.2f px, max %.2f px; top-row max "
                "%.2f px; bottom angle max %.2f deg\n",
                radius, arc.size(), quantile(arc, 0.5), quantile(arc, 1.0), quantile(top, 1.0), quantile(angle, 1.0),
                quantile(line, 0.5), quantile(line, 1.0), quantile(line_top, 1.0), quantile(line_angle, 1.0));
  }
  // Every frame off 2 px or 1 degree, with its cause: where the mask shows under half the rows of the
  // road's true edges (shadowed grass classed as road), the boundary beyond them can gather more edges
  // than the road's; else the circle is extrapolated from the nearest edge the mask shows to the
  // bottom row, 2 m ahead, where 1 cm is 3.7 px.
  CircleScore c;
  long shown = 0, in_image = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    shown += e.edge_rows[i].shown;
    in_image += e.edge_rows[i].in_image;
    c.met += e.arc[i] <= 2.0 && e.angle[i] <= 1.0;
    c.within4 += e.arc[i] <= 4.0 && e.angle[i] <= 1.1;
    c.top_met += e.top[i] <= 2.0;
    c.arc_better += e.arc[i] < e.line[i];
    if (e.arc[i] <= 2.0 && e.angle[i] <= 1.0) continue;
    const EdgeRows& er = e.edge_rows[i];
    std::printf("  frame %2zu (radius %2.0f m, %s, s %4.1f m): column %7.2f px, top row %5.2f px, bottom angle %5.2f deg, "
                "curvature %.4f 1/m; true edge rows in the mask %3d / %3d, the nearest %.1f m ahead; the edges' "
                "quantisation alone leaves the bottom row's column a standard error of %.2f px: %s\n",
                i, circleRadiusOf(poses[i]), (poses[i].road - circles().roads().data()) % 2 == 0 ? "left" : "right",
                poses[i].s, e.arc[i], e.top[i], e.angle[i], e.curvature[i], er.shown, er.in_image, er.nearest_m,
                e.bottom_sd[i],
                e.arc[i] > 4.0 && 2 * er.shown < er.in_image ? "the mask shows under half the true edges' rows"
                                                             : "extrapolated from the edges seen to the bottom row");
    // A miss with the road's edges in the mask is the extrapolation's: within three of its standard
    // errors from quantisation alone (no fit to these edges can be sure of the bottom row's 2 px).
    if (expect_within_3sd && !(e.arc[i] > 4.0 && 2 * er.shown < er.in_image)) {
      EXPECT_LE(e.arc[i], 3.0 * e.bottom_sd[i]) << "frame " << i;
    }
  }
  std::printf("within 2 px and 1 deg on %d of %zu frames, within 4 px and 1.1 deg on %d; top-row offset <= 2 px on %d; "
              "the arc better than the straight model on %d; the masks show %ld of the %ld true edge rows in view\n",
              c.met, poses.size(), c.within4, c.top_met, c.arc_better, shown, in_image);
  return c;
}

TEST(ClusterPerceptron, ArcModelWithinTwoPixelsAndOneDegreeOnCircularCurves) {
  const auto poses = circlePoses(2.0);
  ASSERT_EQ(poses.size(), 8u * 11u);
  const ArcVsLine e = arcVsLine(poses, circles(), 0.5);
  const CircleScore c = scoreCircles(poses, e);
  EXPECT_TRUE(e.failed.empty());
  EXPECT_GE(c.met, 81);
  EXPECT_GE(c.within4, 87);
  EXPECT_GE(c.top_met, 87);
  EXPECT_EQ(c.arc_better, static_cast<int>(poses.size()));
  for (const double radius : {30.0, 50.0}) {
    // On the gentler bends the road's inner edge is in view too: every frame within 3.5 px and 1 degree
    // but where the mask hides the true edges.
    for (std::size_t i = 0; i < poses.size(); ++i)
      if (circleRadiusOf(poses[i]) == radius && 2 * e.edge_rows[i].shown >= e.edge_rows[i].in_image) {
        EXPECT_LE(e.arc[i], 3.5) << "frame " << i;
        EXPECT_LE(e.angle[i], 1.0) << "frame " << i;
      }
  }
}

// The item in normalised colour (ClusterPerceptronOptions::normalized_color, Wallace et al. 1985
// §3.4.3) with 8 clusters: the same circles, poses and point-sampled frames as above, the clusters
// and the perceptron on (R, G, B) / (R + G + B). A tree shadow scales a colour (C1 = k·C2, here tinted
// 12 % toward blue); normalised, the shaded grass keeps the grass's chromaticity instead of joining
// the dark asphalt's cluster, so the mask shows the road's true edges on every frame and the circle
// is fitted to more of them. Measured: within 2 px and 1 deg on 88 of 88 frames (81 in RGB above);
// per radius worst column error median / max 15 m 0.36 / 0.61 px, 20 m 0.18 / 0.77, 30 m 0.33 / 0.75,
// 50 m 0.13 / 0.40; bottom angle max 0.51, 0.50, 0.36, 0.22 deg; the masks show 13 491 of the 13 527
// true edge rows in view (RGB above: 9 949). With the paper's 5 clusters the same 88 here (13 497
// rows), but 5 are too few for two dimensions of colour elsewhere: on the area-sampled frames of the
// next test, with subpixel_edges, 87 of 88 (frame 56, 30 m right: a cluster between the grass's and
// the asphalt's chromaticity classes the far sunlit grass as road in speckles, and the circle bends
// to them: 59.8 px; 88 with 8 or 12 clusters), and the closed loop on park_loop leaves the path at a
// dirt shoulder (ParkLoopStretch.ClusterPerceptronInNormalisedColourStaysOnThePath). Under
// AddressSanitizer, the 15 m circles alone.
TEST(ClusterPerceptron, ArcModelInNormalisedColourWithinTwoPixelsAndOneDegreeOnEveryCircleFrame) {
  auto poses = circlePoses(2.0);
  ASSERT_EQ(poses.size(), 8u * 11u);
  if (kSanitized) std::erase_if(poses, [](const RoadPose& p) { return circleRadiusOf(p) != 15.0; });
  ClusterPerceptronOptions o;
  o.normalized_color = true;
  o.clusters = 8;
  const ArcVsLine e = arcVsLine(poses, circles(), 0.5, parkWorld(), o);
  const CircleScore c = scoreCircles(poses, e);
  EXPECT_TRUE(e.failed.empty());
  EXPECT_EQ(c.met, static_cast<int>(poses.size()));
  EXPECT_EQ(c.top_met, static_cast<int>(poses.size()));
  for (std::size_t i = 0; i < poses.size(); ++i)
    EXPECT_GE(2 * e.edge_rows[i].shown, e.edge_rows[i].in_image) << "frame " << i << ": the mask hides the true edges";
}

// The straight paths of park() in the same configuration (normalised colour, 8 clusters): the arc
// model's whole centre curve, every row where the true centre is in the image, within 2 px of the
// truth and its bottom-row angle within 1 degree on every frame. Measured on the 24 frames: median
// 0.09 px, worst 1.38 px; bottom-row angle median 0.01 deg, worst 0.15 deg (in RGB,
// ArcModelOnStraightStretches: 19 within 2 px, worst 166 px where the left shoulder is classed as road).
TEST(ClusterPerceptron, ArcModelInNormalisedColourWithinTwoPixelsAndOneDegreeOnEveryStraightFrame) {
  const auto poses = straightPoses(8.0);
  ASSERT_GE(poses.size(), 20u);
  ClusterPerceptronOptions o;
  o.normalized_color = true;
  o.clusters = 8;
  const ArcVsLine e = arcVsLine(poses, park(), std::nullopt, parkWorld(), o);
  std::printf("on %zu straight frames in normalised colour, worst column error per frame: arc model median %.2f px, "
              "worst %.2f px; bottom-row angle median %.2f deg, worst %.2f deg\n",
              e.arc.size(), quantile(e.arc, 0.5), quantile(e.arc, 1.0), quantile(e.angle, 0.5), quantile(e.angle, 1.0));
  EXPECT_TRUE(e.failed.empty());
  for (std::size_t i = 0; i < e.arc.size(); ++i) {
    EXPECT_LE(e.arc[i], 2.0) << "frame " << i;
    EXPECT_LE(e.angle[i], 1.0) << "frame " << i;
  }
}

/// The median of |x|.
double medianAbs(std::vector<double> v) {
  for (double& x : v) x = std::abs(x);
  return quantile(v, 0.5);
}

// A camera integrates light over the pixel: with frames rendered so (WorldOptions::paved_edge_samples
// 4) the pixel pair at each class change holds the road's edge by area, and subpixel_edges places
// each edge within the pair by its colours. The same circles and poses as above. Measured: the fits'
// edges off the true edges by a median 0.263 px at the pixel boundaries, 0.064 px placed by colour;
// within 2 px and 1 deg on 74 of 88 frames at the boundaries (a mixed pixel's class follows the
// clusters, not its area), 84 placed by colour (within 4 px and 1.1 deg on 85; per radius median
// 0.35, 0.27, 0.24, 0.20 px). The four misses: frame 1 (15 m left, 7.8 px: the mask shows 57 of the
// 128 true edge rows, the nearest 7.8 m ahead, a standard error of 6.0 px), 62 and 63 (30 m right,
// 155 and 137 px: shadowed grass classed as road), 64 (2.8 px, standard error 2.3 px). Point-sampled
// frames with subpixel_edges (not asserted): 82 of 88.
TEST(ClusterPerceptron, ArcModelWithSubpixelEdgesOnAreaSampledCircularCurves) {
  auto poses = circlePoses(2.0);
  if (kSanitized) std::erase_if(poses, [](const RoadPose& p) { return circleRadiusOf(p) != 15.0; });
  WorldOptions wo = parkWorld();
  wo.paved_edge_samples = 4;
  const ArcVsLine boundary = arcVsLine(poses, circles(), 0.5, wo);
  std::printf("edges at the pixel boundaries:\n");
  const CircleScore cb = scoreCircles(poses, boundary, false);
  ClusterPerceptronOptions subpixel;
  subpixel.subpixel_edges = true;
  const ArcVsLine sub = arcVsLine(poses, circles(), 0.5, wo, subpixel);
  std::printf("edges placed by their pixels' colours:\n");
  const CircleScore cs = scoreCircles(poses, sub);
  std::printf("the fits' ground edges off the true edges, median |offset|: at the pixel boundaries %.3f px (%zu edges), "
              "placed by colour %.3f px (%zu edges)\n",
              medianAbs(boundary.edge_px), boundary.edge_px.size(), medianAbs(sub.edge_px), sub.edge_px.size());
  EXPECT_LT(medianAbs(sub.edge_px), 0.7 * medianAbs(boundary.edge_px));
  EXPECT_TRUE(sub.failed.empty());
  if (kSanitized) return;
  EXPECT_GE(cs.met, 84);
  EXPECT_GT(cs.met, cb.met);
  EXPECT_GE(cs.within4, 85);
}

/// One finder of a carriedDrive(): its carry_frames and the motion its advance() gets (none: the
/// true motion), and per evaluated pose its worst column error, bottom angle error, bottom_column_sd
/// and the carried edges its fit used.
struct DriveFinder {
  int carry_frames = 0;
  std::optional<OdometryNoiseOptions> odometry;
  std::vector<double> column, angle, bottom_sd;
  std::vector<int> carried;
  /// The poses within `px` pixels and `deg` degrees.
  int within(double px = 2.0, double deg = 1.0) const {
    int n = 0;
    for (std::size_t i = 0; i < column.size(); ++i) n += column[i] <= px && angle[i] <= deg;
    return n;
  }
};

/// A drive along each circle of circles(), every `ds` m from 2 m before the circle to its last pose of
/// circlePoses(), weaving ±0.2 m about the centre line (a sine of 30 m wavelength, the heading along
/// the weave: up to 2.4 deg off the road's), every finder bootstrapped on the road's lead-in as
/// arcVsLine()'s and fed the same frames; between frames each finder's advance() gets the true
/// motion, or what an OdometrySensor of its options reports for it (distance and heading change; dt
/// = ds at 1 m/s). Evaluated at the 88 arc lengths of circlePoses(2.0), with this drive's offsets;
/// returns those poses.
std::vector<RoadPose> carriedDrive(double ds, std::vector<DriveFinder>& finders, std::size_t roads) {
  const World world(circles(), parkWorld());
  std::vector<RoadPose> poses;
  for (std::size_t r = 0; r < roads; ++r) {
    const Road& road = circles().roads()[r];
    const Polyline2& line = road.centerline;
    std::vector<ClusterPerceptron> cps;
    std::vector<std::optional<OdometrySensor>> odos;
    for (const DriveFinder& d : finders) {
      ClusterPerceptronOptions o;
      o.road_model = RoadModel::Arc;
      o.carry_frames = d.carry_frames;
      cps.push_back(trainedOn(world, Pose2(line.pointAt(0.5), line.headingAt(0.5)), 0.0, o, circles()));
      odos.emplace_back(d.odometry ? std::optional<OdometrySensor>(*d.odometry) : std::nullopt);
    }
    const auto weave = [&](double q) {
      const Vec2 t = line.tangentAt(q);
      return Vec2(line.pointAt(q) + 0.2 * std::sin(2.0 * std::numbers::pi * q / 30.0) * Vec2(-t.y(), t.x()));
    };
    std::optional<Pose2> last;
    std::vector<RoadFinding> found(finders.size());
    const double s0 = kCircleLeadIn - 2.0, s_end = line.length() - 17.0;
    for (int j = 0; s0 + j * ds <= s_end + 1e-9; ++j) {
      const double s = s0 + j * ds;
      const Vec2 d = weave(s + 0.01) - weave(s - 0.01);
      const Pose2 pose(weave(s), std::atan2(d.y(), d.x()));
      const Frame f = world.render(cam(), pose, s);
      const RoadPose sp{pose, &road, s};
      const double rel = (s - (kCircleLeadIn + 2.0)) / 2.0;
      const bool evaluated = rel > -1e-9 && std::abs(rel - std::round(rel)) < 1e-6;
      if (evaluated) poses.push_back(sp);
      for (std::size_t k = 0; k < finders.size(); ++k) {
        if (last) {
          Pose2 motion = last->inverse() * pose;
          if (odos[k]) {
            const Pose2::Tangent xi = motion.log();
            const Odometry m = odos[k]->measure(xi[0], xi[2], ds);
            motion = Pose2::exp(Pose2::Tangent(m.distance_m, 0.0, m.dheading_rad));
          }
          cps[k].advance(found[k], motion);
        }
        found[k] = cps[k].find(f.rgb.data.data(), f.rgb.width, f.rgb.height, false);
        if (!evaluated) continue;
        DriveFinder& out = finders[k];
        out.column.push_back(found[k].ok ? worstCurveError(found[k], sp) : 1e9);
        out.angle.push_back(found[k].ok ? bottomAngleError(found[k], sp) : 180.0);
        out.bottom_sd.push_back(found[k].bottom_column_sd);
        out.carried.push_back(found[k].carried_edges);
      }
      last = pose;
    }
  }
  return poses;
}

// The issue's item on circles, driven: the arc model with the edges of the last 8 frames carried
// (ClusterPerceptronOptions::carry_frames; Wallace 1985 §3.2 carries the last frame's edges with the
// vehicle's motion) over the same 15-50 m circles as ArcModelWithinTwoPixelsAndOneDegreeOnCircular-
// Curves, a frame every 0.5 m. One frame's mask edges are whole pixels, and where the 3 m road fills
// the image below 5-8 m the circle is extrapolated to the bottom row (2 m ahead, 1 cm = 3.7 px); the
// frames before saw that stretch far ahead, at other sub-pixel phases. Measured (within 2 px and 1 deg
// | within 4 px and 1.1 deg | worst column error):
//   each frame alone                          84 | 85 | 191 px (30 m right: shadowed grass as road)
//   carried, the true motion                  88 | 88 | 0.49 px (the shadow frame's true circle
//                                                              gathers the carried edges)
//   carried, odometry calibrated to 0.3 % scale, 0.01 deg/s gyro bias, 2 mm and 0.01 deg of noise per
//   frame, noise seeds 9-13                   88, 80, 87, 80, 76 | 88, 87, 88, 86, 85 | 1.8-35 px
//   carried, park_loop's odometry (2 %, 0.1 deg/s, 5 mm, 0.075 deg per frame)   26 | 51 | 202 px
// So carrying meets the item when the motion is known to about a millimetre over the 4 m carried (a
// carried edge 4 m ahead moves 7 mm, 2.6 px at the bottom row, per 0.1 deg of heading error; 0.3 %
// of 4 m along a 15 m bend moves it 2.4 mm); with calibrated odometry it trades a few frames of 2-5
// px for a worst case of 1.8-35 px instead of 191; with uncalibrated odometry it does harm. Off by
// default.
TEST(ClusterPerceptron, ArcModelWithCarriedEdgesOnCircularCurves) {
  OdometryNoiseOptions calibrated;
  calibrated.seed = 9;
  calibrated.scale_error = 0.003;
  calibrated.gyro_bias_deg_s = 0.01;
  calibrated.distance_sigma_m = 0.002;
  calibrated.heading_sigma_deg = 0.01;
  OdometryNoiseOptions park_loop = calibrated;  // maps/missions/park_loop.json's, its noise per 0.5 s
  park_loop.scale_error = 0.02;
  park_loop.gyro_bias_deg_s = 0.1;
  park_loop.distance_sigma_m = 0.005;
  park_loop.heading_sigma_deg = 0.075;
  // Finders: each frame alone; carried with the true motion; with calibrated odometry of five noise
  // seeds; with park_loop's odometry.
  std::vector<DriveFinder> finders(8);
  for (std::size_t k = 1; k < finders.size(); ++k) finders[k].carry_frames = 8;
  for (std::size_t k = 2; k < 7; ++k) {
    finders[k].odometry = calibrated;
    finders[k].odometry->seed = 7 + k;
  }
  finders[7].odometry = park_loop;
  const auto poses = carriedDrive(0.5, finders, kSanitized ? 1 : circles().roads().size());
  ASSERT_EQ(poses.size(), kSanitized ? 11u : 88u);
  for (std::size_t k = 0; k < finders.size(); ++k) {
    const DriveFinder& d = finders[k];
    const std::string name = k == 0 ? "each frame alone" : k == 1 ? "carried, true motion" : k == 7 ? "carried, park_loop's odometry"
                                                                  : "carried, calibrated odometry, seed " + std::to_string(d.odometry->seed);
    std::printf("%-40s within 2 px and 1 deg on %2d of %zu, within 4 px and 1.1 deg on %2d; worst column error median "
                "%.2f px, max %.2f px; bottom angle max %.2f deg; carried edges used median %.0f\n",
                name.c_str(), d.within(), poses.size(), d.within(4.0, 1.1), quantile(d.column, 0.5), quantile(d.column, 1.0), quantile(d.angle, 1.0),
                quantile(std::vector<double>(d.carried.begin(), d.carried.end()), 0.5));
  }
  for (std::size_t i = 0; i < poses.size(); ++i) {
    // Carried with the true motion: every frame within 2 px and 1 degree.
    EXPECT_LE(finders[1].column[i], 2.0) << "frame " << i;
    EXPECT_LE(finders[1].angle[i], 1.0) << "frame " << i;
    EXPECT_GT(finders[1].carried[i], 0) << "frame " << i;
    EXPECT_EQ(finders[0].carried[i], 0) << "frame " << i;
  }
  if (kSanitized) return;
  EXPECT_GE(finders[0].within(), 84);
  EXPECT_LT(finders[0].within(), 88);  // alone, not every frame: what carrying adds
  // Calibrated odometry: within 4 px and 1.1 degrees on 85 or more frames whatever the noise's seed
  // (alone: 85, and the shadow frame 191 px off).
  for (std::size_t k = 2; k < 7; ++k)
    EXPECT_GE(finders[k].within(4.0, 1.1), 85) << "seed " << finders[k].odometry->seed;
  EXPECT_LT(finders[7].within(), finders[0].within());  // carrying with poor odometry does harm
}

// advance(): the carried edges move into the new vehicle frame (point ↦ motion⁻¹ · point), those
// behind the vehicle (x < 0) go, and so do frames beyond carry_frames; 0 carries nothing.
TEST(ClusterPerceptron, AdvanceMovesCarriedEdgesWithTheVehicle) {
  ClusterPerceptronOptions o;
  o.carry_frames = 2;
  ClusterPerceptron cp(o);
  RoadFinding r1, r2, r3;
  r1.ground_edges = {{Vec2(5.0, 1.5), 1, 100.0}, {Vec2(0.5, -1.5), -1, 200.0}};
  cp.advance(r1, Pose2(1.0, 0.0, 0.0));  // 1 m ahead: (5, 1.5) -> (4, 1.5); (0.5, -1.5) is behind
  ASSERT_EQ(cp.carried().size(), 1u);
  ASSERT_EQ(cp.carried()[0].size(), 1u);
  EXPECT_DOUBLE_EQ(cp.carried()[0][0].p.x(), 4.0);
  EXPECT_DOUBLE_EQ(cp.carried()[0][0].p.y(), 1.5);
  EXPECT_EQ(cp.carried()[0][0].side, 1);
  EXPECT_EQ(cp.carried()[0][0].px_per_m, 100.0);
  r2.ground_edges = {{Vec2(3.0, 1.0), -1, 50.0}};
  cp.advance(r2, Pose2(0.0, 0.0, std::numbers::pi / 2));  // turned 90 deg left: (x, y) -> (y, -x)
  ASSERT_EQ(cp.carried().size(), 2u);
  EXPECT_NEAR(cp.carried()[0][0].p.x(), 1.5, 1e-12);
  EXPECT_NEAR(cp.carried()[0][0].p.y(), -4.0, 1e-12);
  EXPECT_NEAR(cp.carried()[1][0].p.x(), 1.0, 1e-12);
  EXPECT_NEAR(cp.carried()[1][0].p.y(), -3.0, 1e-12);
  cp.advance(r3, Pose2());  // a third frame: the oldest goes
  ASSERT_EQ(cp.carried().size(), 2u);
  EXPECT_EQ(cp.carried()[0].size(), 1u);
  EXPECT_EQ(cp.carried()[0][0].side, -1);
  EXPECT_TRUE(cp.carried()[1].empty());
  cp.clearCarried();
  EXPECT_TRUE(cp.carried().empty());
  ClusterPerceptron alone;  // carry_frames 0 (the default, the paper)
  alone.advance(r1, Pose2());
  EXPECT_TRUE(alone.carried().empty());
  o.carry_frames = 65;
  try {
    ClusterPerceptron bad(o);
    ADD_FAILURE() << "carry_frames 65 accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("carry_frames"), std::string::npos) << e.what();
  }
}

TEST(ClusterPerceptron, ArcModelFastPathEqualsReference) {
  const World world(park(), parkWorld());
  const auto poses = curvePoses(3.0);
  ClusterPerceptronOptions o;
  o.road_model = RoadModel::Arc;
  ClusterPerceptron fast = trainedOn(world, poses.front().pose, 0.0, o);
  ClusterPerceptron ref = fast;
  ref.setFast(false);
  for (std::size_t i = 0; i < std::min<std::size_t>(poses.size(), 12); ++i) {
    const Frame f = world.render(cam(), poses[i].pose, static_cast<double>(i));
    const RoadFinding a = fast.find(f.rgb.data.data(), f.rgb.width, f.rgb.height, true);
    const RoadFinding b = ref.find(f.rgb.data.data(), f.rgb.width, f.rgb.height, true);
    ASSERT_EQ(a.ok, b.ok) << a.reason << b.reason;
    EXPECT_EQ(a.mask, b.mask) << "frame " << i;
    EXPECT_EQ(a.centerline_curve, b.centerline_curve) << "frame " << i;
    EXPECT_EQ(a.curvature, b.curvature) << "frame " << i;
  }
  // Without the camera the arc model says so.
  ClusterPerceptron no_camera(o);
  const Frame f = world.render(cam(), poses.front().pose, 0.0);
  const Image outline = predictedRoadMask(predictView(park(), poses.front().pose, cam()).view, cam());
  no_camera.trainClusters(f.rgb.data.data(), f.rgb.width, f.rgb.height);
  no_camera.setRowWidths(trapezoidRowWidths(outline));
  no_camera.trainPerceptron(f.rgb.data.data(), f.rgb.width, f.rgb.height, outline.data.data());
  const RoadFinding r = no_camera.find(f.rgb.data.data(), f.rgb.width, f.rgb.height, false);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("setCamera"), std::string::npos) << r.reason;
}

double maskIoU(const Image& found, const Image& truth) {
  double tp = 0, fp = 0, fn = 0;
  for (std::size_t k = 0; k < found.data.size(); ++k) {
    const bool d = found.data[k] != 0, t = truth.data[k] != 0;
    tp += d && t;
    fp += d && !t;
    fn += !d && t;
  }
  return tp / (tp + fp + fn);
}

/// Adaptive cluster management along the first straight road, 1.5 m a frame: `frames` frames of
/// `before`, the first `change` of them, then of `after`; the adaptive finder (track()) against the
/// frozen model of the paper (find()), both trained on frame 0. Per frame: the adaptive result, the
/// cluster count after it, the masks' IoU against the simulator's truth.
struct SceneChangeRun {
  std::vector<RoadFinding> adaptive;
  std::vector<std::size_t> clusters;
  std::vector<double> iou_adaptive, iou_frozen;
  double training_error = 0;  // the frozen model's (the adaptive one's before any retraining)
};
SceneChangeRun runSceneChange(const World& before, const World& after, std::size_t change, std::size_t frames) {
  std::vector<RoadPose> poses;
  const auto all = straightPoses(1.5);
  for (const RoadPose& sp : all)
    if (sp.road == all.front().road && poses.size() < frames) poses.push_back(sp);
  EXPECT_EQ(poses.size(), frames);
  ClusterPerceptronOptions o;
  o.adaptive = true;
  ClusterPerceptron adaptive = trainedOn(before, poses[0].pose, 0.0, o);
  const ClusterPerceptron frozen = adaptive;
  SceneChangeRun run;
  run.training_error = frozen.trainingError();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Frame f = (i < change ? before : after).render(cam(), poses[i].pose, static_cast<double>(i));
    RoadFinding a = adaptive.track(f.rgb.data.data(), f.rgb.width, f.rgb.height, true);
    const RoadFinding z = frozen.find(f.rgb.data.data(), f.rgb.width, f.rgb.height, true);
    run.iou_adaptive.push_back(maskIoU(a.mask, f.mask));
    run.iou_frozen.push_back(maskIoU(z.mask, f.mask));
    run.clusters.push_back(adaptive.means().size());
    std::printf("frame %zu%s: reconstruction error %.1f (reference %.1f, training %.1f)%s, %zu clusters, IoU "
                "adaptive %.4f, frozen %.4f\n",
                i, i < change ? "" : " (new scene)", a.reconstruction_error, a.training_error, run.training_error,
                a.retrained ? " RETRAINED" : "", run.clusters.back(), run.iou_adaptive.back(), run.iou_frozen.back());
    run.adaptive.push_back(std::move(a));
  }
  return run;
}

/// In a copy of the park's data, the road runSceneChange() drives (the first of straightPoses()).
Road& drivenRoad(MapData& data) {
  return data.roads[static_cast<std::size_t>(straightPoses(1.5).front().road - park().roads().data())];
}

/// The masks' IoU from frame `first` of a run on: each model's worst and sum, over n frames (at least 1).
struct IoUFrom {
  double worst_adaptive = 1, worst_frozen = 1, sum_adaptive = 0, sum_frozen = 0, n = 1;
};
IoUFrom iouFrom(const SceneChangeRun& run, std::size_t first) {
  IoUFrom r;
  for (std::size_t i = first; i < run.iou_adaptive.size(); ++i) {
    r.worst_adaptive = std::min(r.worst_adaptive, run.iou_adaptive[i]);
    r.worst_frozen = std::min(r.worst_frozen, run.iou_frozen[i]);
    r.sum_adaptive += run.iou_adaptive[i];
    r.sum_frozen += run.iou_frozen[i];
  }
  r.n = static_cast<double>(std::max<std::size_t>(1, run.iou_adaptive.size() - std::min(first, run.iou_adaptive.size())));
  return r;
}

// Beyond the paper (§9, adaptive cluster management): the scene changes under the vehicle (another
// world seed, a camera whose colours turn: the TV transmission's hue shift). The clusters trained
// before no longer reconstruct the frames: the error rises past the threshold (3x the recent
// frames' median) on the first or second new frame (2.4x on the first, 3.3x on the second), the
// finder retrains there from the road it last trusted, and finds the road afterwards, where the
// frozen model of the paper degrades.
TEST(ClusterPerceptron, AdaptiveClustersRetrainOnASceneChange) {
  const World before(park(), parkWorld());
  WorldOptions wo = parkWorld();
  wo.seed = 7;
  wo.tv_color_shift = true;
  wo.tv_hue_shift_rad = 1.5;
  wo.shadow_density = 0.7;
  const World after(park(), wo);
  const std::size_t change = 5, frames = 14;
  const SceneChangeRun run = runSceneChange(before, after, change, frames);
  std::size_t retrained_at = frames;
  int retrains = 0;
  for (std::size_t i = 0; i < frames; ++i)
    if (run.adaptive[i].retrained) {
      retrained_at = std::min(retrained_at, i);
      ++retrains;
    }
  EXPECT_EQ(retrains, 1);
  EXPECT_TRUE(retrained_at == change || retrained_at == change + 1) << "retrained at frame " << retrained_at;
  const IoUFrom u = iouFrom(run, retrained_at);
  std::printf("from the retraining on: IoU adaptive mean %.4f worst %.4f; frozen mean %.4f worst %.4f\n",
              u.sum_adaptive / u.n, u.worst_adaptive, u.sum_frozen / u.n, u.worst_frozen);
  EXPECT_GE(u.worst_adaptive, 0.92);
  EXPECT_LT(u.worst_frozen, 0.9) << "the frozen model degrades on the new scene";
  EXPECT_GE(u.sum_adaptive, u.sum_frozen + 0.03 * u.n);
}

// Adaptive cluster management adds a cluster when a new colour enters: after the change the path's
// left shoulder is a blue flower bed, far from every colour the clusters were trained on, while every
// old surface stays in view. The first new frame's error is 3.8x the recent median: the finder adds
// one cluster at the new colour (the clusters then move) and retrains once. NOT a demonstration of
// a better mask: the frozen model already calls this blue not road (its IoU after the change is
// the adaptive one's within 0.002), so the test asserts the cluster count and that the adaptation
// costs nothing.
TEST(ClusterPerceptron, AdaptiveClustersAddOneForANewColour) {
  const World before(park(), parkWorld());
  MapData data = park().data();
  data.surfaces.emplace_back("flowers", Appearance{Vec3(40, 45, 110), Vec3(8, 8, 10)});
  drivenRoad(data).left = "flowers";
  const Map changed(data, "park with a flower bed");
  const World after(changed, parkWorld());
  const std::size_t change = 5, frames = 12;
  const SceneChangeRun run = runSceneChange(before, after, change, frames);
  for (std::size_t i = 0; i < frames; ++i) {
    EXPECT_EQ(run.adaptive[i].retrained, i == change) << "frame " << i;
    EXPECT_EQ(run.clusters[i], i < change ? 5u : 6u) << "frame " << i;
  }
  const IoUFrom u = iouFrom(run, change);
  std::printf("new colour: %d cluster(s) added; IoU after the change: adaptive mean %.4f worst %.4f, frozen mean %.4f\n",
              run.adaptive[change].clusters_added, u.sum_adaptive / u.n, u.worst_adaptive, u.sum_frozen / u.n);
  EXPECT_EQ(run.adaptive[change].clusters_added, 1);
  EXPECT_GE(u.worst_adaptive, 0.89);
  EXPECT_GE(u.sum_adaptive, u.sum_frozen - 0.005 * u.n);
}

// The trigger on an unchanged world: frames differ from the training frame (another mix of
// surfaces and shadows), so their error is a multiple of the training error; against the recent
// frames' median it stays well inside the threshold, and nothing is retrained.
TEST(ClusterPerceptron, AdaptiveTriggerQuietOnAnUnchangedWorld) {
  const World world(park(), parkWorld());
  const std::size_t frames = 20;
  const SceneChangeRun run = runSceneChange(world, world, frames, frames);
  double vs_training = 0, vs_reference = 0;
  for (std::size_t i = 0; i < frames; ++i) {
    EXPECT_FALSE(run.adaptive[i].retrained) << "frame " << i;
    vs_training = std::max(vs_training, run.adaptive[i].reconstruction_error / run.training_error);
    vs_reference = std::max(vs_reference, run.adaptive[i].reconstruction_error / run.adaptive[i].training_error);
  }
  std::printf("unchanged world, %zu frames: error at most %.2fx the training error, %.2fx the recent median\n",
              frames, vs_training, vs_reference);
  EXPECT_LT(vs_reference, 0.75 * ClusterPerceptronOptions{}.adaptive_error_ratio);
}

// Beyond the paper (§9): the perceptron on raw R, G, B. On the park, asphalt is bluer than grass,
// dirt and their shadows, which one linear unit separates well; its lookup table is exact too.
TEST(ClusterPerceptron, RawRgbPerceptronLearnsTheRoadAndItsTableIsExact) {
  const World world(park(), parkWorld());
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
// skylight tint (12 % toward blue). Measured (IoU of the road mask against the truth): RGB sunlit
// 0.9991, shaded 0.9141, tinted 0.9141; normalised sunlit 0.9999, shaded 0.9985, tinted 0.9987.
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
  EXPECT_LT(rgb_shade, 0.95);  // the issue's bar, which RGB meets sunlit and misses in the shade
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

// The lookup table stays exact in normalised colour: every one of the 2^24 colours (68.3 frames of
// them) gets the reference path's class, for the clusters' perceptron and for raw_rgb's. And a colour
// and its double have the same normalised colour to the bit, so the same output.
TEST(ClusterPerceptron, NormalisedColourTableIsExactForEveryColour) {
  const World world(park(), parkWorld());
  const Pose2 pose = straightPoses(10.0).front().pose;
  const int w = cam().width(), h = cam().height();
  const std::uint32_t per_frame = static_cast<std::uint32_t>(w) * static_cast<std::uint32_t>(h);
  for (const bool raw : {false, true}) {
    ClusterPerceptronOptions o;
    o.normalized_color = true;
    o.raw_rgb = raw;
    const ClusterPerceptron fast = trainedOn(world, pose, 0.0, o);
    ClusterPerceptron ref = fast;
    ref.setFast(false);
    std::size_t differing = 0, road = 0, total = 0;
    Image frame(w, h, 3);
    for (std::uint32_t first = 0; first < (1u << 24); first += per_frame) {
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
    int halved_differ = 0;
    for (int r = 0; r < 128; ++r)
      for (int g = 0; g < 128; ++g)
        for (int b = 0; b < 128; ++b)
          halved_differ += ref.outputReference(static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(g),
                                               static_cast<std::uint8_t>(b)) !=
                           ref.outputReference(static_cast<std::uint8_t>(2 * r), static_cast<std::uint8_t>(2 * g),
                                               static_cast<std::uint8_t>(2 * b));
    std::printf("normalised colour%s: %zu of %zu colours differ between the table and the reference, %.1f %% road; "
                "%d colours differ from their doubles\n",
                raw ? ", raw_rgb" : "", differing, total, 100.0 * static_cast<double>(road) / static_cast<double>(total),
                halved_differ);
    EXPECT_EQ(differing, 0u);
    EXPECT_GT(road, total / 100);
    EXPECT_LT(road, total - total / 100);
    EXPECT_EQ(halved_differ, 0);
  }
}

TEST(ClusterPerceptron, FastPathEqualsReferenceOn100Frames) {
  const World world(park(), parkWorld());
  const std::vector<Pose2> poses = visiontest::roadPoses(park(), 5.0);
  ASSERT_GE(poses.size(), 100u);
  ClusterPerceptron fast = trainedOn(world, straightPoses(10.0).front().pose, 0.0);
  ClusterPerceptron ref = fast;
  ref.setFast(false);
  std::size_t differing = 0, total = 0;
  for (std::size_t i = 0; i < 100; ++i) {
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

TEST(ClusterPerceptron, ParkPipelineRegisteredAndFindsTheCentreLine) {
  registerBuiltinPipelines();
  bool found = false;
  for (const PipelineInfo& info : listPipelines())
    if (info.name == "cluster-perceptron") {
      found = true;
      EXPECT_GE(info.options.size(), 10u);
    }
  ASSERT_TRUE(found);
  auto p = createPipeline("cluster-perceptron", R"({"clusters": 5, "fast": true})");
  EXPECT_THROW(p->configure(R"({"clusters": 31})"), InvalidInput);
  EXPECT_THROW(p->configure(R"({"nope": 1})"), InvalidInput);
  EXPECT_NO_THROW(createPipeline("cluster-perceptron", R"({"arc": true, "subpixel_edges": true})"));
  EXPECT_THROW(p->configure(R"({"subpixel_edges": 2})"), InvalidInput);
  EXPECT_THROW(p->configure(R"({"normalized_color": 1})"), InvalidInput);
  const World world(park(), parkWorld());
  const auto poses = straightPoses(6.0);
  for (std::size_t i = 0; i < std::min<std::size_t>(poses.size(), 8); ++i) {
    const Frame f = world.render(cam(), poses[i].pose, static_cast<double>(i));
    const Prediction pred = predictView(park(), poses[i].pose, cam());
    VisionFrame vf{f.rgb.width, f.rgb.height, f.rgb.data.data(), &cam(), static_cast<double>(i)};
    const DetectedObject d = p->detect(vf, pred.view);
    ASSERT_EQ(d.status, DetectedObject::Status::Ok) << d.reason;
    ASSERT_TRUE(d.centerline_vehicle.has_value());
    ASSERT_GE(d.region_image.size(), 4u);
    // The truth on the ground: the road's centre line in the vehicle frame.
    const Segment2 truth{poses[i].pose.inverseTransform(poses[i].road->centerline.pointAt(poses[i].s - 2.0)),
                         poses[i].pose.inverseTransform(poses[i].road->centerline.pointAt(poses[i].s + 25.0))};
    EXPECT_LT(truth.distanceTo(d.centerline_vehicle->a) + 0, 0.15) << "frame " << i;
    EXPECT_LT(std::abs(std::sin(d.centerline_vehicle->heading() - truth.heading())), std::sin(2.0 * std::numbers::pi / 180))
        << "frame " << i;
    EXPECT_GT(d.confidence, 0.3);
  }
  // Without a predicted road: the default trapezoid bootstraps it.
  p->reset();
  const Frame f = world.render(cam(), poses.front().pose, 0.0);
  VisionFrame vf{f.rgb.width, f.rgb.height, f.rgb.data.data(), &cam(), 0.0};
  const DetectedObject d = p->detect(vf, PredictedObject{});
  EXPECT_EQ(d.status, DetectedObject::Status::Ok) << d.reason;
  // A grey frame is clustered on its texture features, which normalized_color leaves alone: the same
  // answer with it as without (normalised, R = G = B would be one grey and the texture gone).
  Image grey = f.rgb;
  for (std::size_t i = 0; i < grey.data.size(); i += 3) std::fill_n(&grey.data[i], 3, grey.data[i + 1]);
  const VisionFrame gf{grey.width, grey.height, grey.data.data(), &cam(), 0.0};
  const Prediction pred = predictView(park(), poses.front().pose, cam());
  const DetectedObject plain = createPipeline("cluster-perceptron", "{}")->detect(gf, pred.view);
  const DetectedObject normalised =
      createPipeline("cluster-perceptron", R"({"normalized_color": true})")->detect(gf, pred.view);
  ASSERT_EQ(plain.status, DetectedObject::Status::Ok) << plain.reason;
  ASSERT_EQ(normalised.status, DetectedObject::Status::Ok) << normalised.reason;
  EXPECT_EQ(plain.centerline_vehicle->a, normalised.centerline_vehicle->a);
  EXPECT_EQ(plain.centerline_vehicle->b, normalised.centerline_vehicle->b);
  EXPECT_EQ(plain.confidence, normalised.confidence);
}

// Grey frames: the feature image that stands in for R, G, B. A 40 x 20 frame, flat 100 on the left
// half, a checkerboard of 110 and 100 on the right half ((u + v) even: 110).
TEST(ClusterPerceptron, GreyTextureFeaturesMeasureMeanGrainAndTexture) {
  Image grey(40, 20, 3);
  for (int v = 0; v < 20; ++v)
    for (int u = 0; u < 40; ++u) {
      const std::uint8_t g = u < 20 ? 100 : ((u + v) % 2 == 0 ? 110 : 100);
      std::fill(grey.pixel(u, v), grey.pixel(u, v) + 3, g);
    }
  EXPECT_TRUE(isGreyFrame(grey.data.data(), 40, 20));
  const Image f = greyTextureFeatures(grey.data.data(), 40, 20, 7);
  ASSERT_EQ(f.channels, 3);
  // Deep in the flat half: mean 100, no grain, no texture.
  EXPECT_EQ(f.pixel(5, 10)[0], 100);
  EXPECT_EQ(f.pixel(5, 10)[1], 0);
  EXPECT_EQ(f.pixel(5, 10)[2], 0);
  // In the checkerboard, (30, 10) is even: its 7 x 7 box holds 25 of 110 and 24 of 100, mean
  // 5150 / 49 = 105.1, standard deviation sqrt(11071.43 − 105.10²) = 5.0, times 4 = 20; every
  // pixel's 4-neighbour Laplacian is ±40, times 4 = 160.
  EXPECT_EQ(f.pixel(30, 10)[0], 105);
  EXPECT_EQ(f.pixel(30, 10)[1], 160);
  EXPECT_EQ(f.pixel(30, 10)[2], 20);
  EXPECT_THROW(greyTextureFeatures(grey.data.data(), 40, 20, 6), InvalidInput);
  grey.pixel(3, 4)[1] = 101;  // one pixel with colour: not a grey frame
  EXPECT_FALSE(isGreyFrame(grey.data.data(), 40, 20));
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
    ClusterPerceptron cp(o);
    cp.trainClusters(frame.data.data(), 100, 100);
    cp.trainPerceptron(frame.data.data(), 100, 100, outline.data.data());
    EXPECT_EQ(cp.outputReference(50, 50, 50) > 0, balance) << "balance " << balance;
    EXPECT_LT(cp.outputReference(200, 200, 200), 0) << "balance " << balance;
  }
}

// Adaptive cluster management where it pays: the path changes from asphalt to brick (another of
// the park's own surfaces, never in view while training). The frozen clusters give the brick to
// a cluster the perceptron learnt as not road, so the frozen model of the paper loses much of the
// path (IoU mean 0.65, worst 0.38 over the 7 new frames). The adaptive finder sees the error rise
// (939 against a recent median of 34), adds clusters at the unexplained colours (5 -> 8), retrains
// the perceptron on the road it last found, and keeps the path (IoU mean 0.97, worst 0.92) from the
// first new frame on.
TEST(ClusterPerceptron, AdaptiveClustersKeepAPathThatTurnsToBrick) {
  const World before(park(), parkWorld());
  MapData data = park().data();
  drivenRoad(data).surface = "brick";
  const Map changed(data, "park with a brick path");
  const World after(changed, parkWorld());
  const std::size_t change = 5, frames = 12;
  const SceneChangeRun run = runSceneChange(before, after, change, frames);
  for (std::size_t i = 0; i < frames; ++i) EXPECT_EQ(run.adaptive[i].retrained, i == change) << "frame " << i;
  const IoUFrom u = iouFrom(run, change);
  std::printf("brick path: %d cluster(s) added; IoU after the change: adaptive mean %.4f worst %.4f, frozen mean "
              "%.4f worst %.4f\n",
              run.adaptive[change].clusters_added, u.sum_adaptive / u.n, u.worst_adaptive, u.sum_frozen / u.n,
              u.worst_frozen);
  EXPECT_GE(run.adaptive[change].clusters_added, 1);
  EXPECT_GE(u.worst_adaptive, 0.9);
  EXPECT_LT(u.worst_frozen, 0.5) << "the frozen model loses the brick path";
  EXPECT_GE(u.sum_adaptive, u.sum_frozen + 0.2 * u.n);
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

