// The arc model's evaluation against the simulator's truth (see cluster_perceptron_arc_eval.h).
#include "cluster_perceptron_arc_eval.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include <gtest/gtest.h>

#include "mapnav/image/png.h"
#include "mapnav/sim/world.h"

namespace mapnav::visiontest {

namespace {

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

}  // namespace

std::vector<Vec2> truthCurve(const RoadPose& sp) {
  std::vector<Vec2> truth;
  for (double d = -2.0; d <= 16.0; d += 0.05)
    if (const auto p = cam().projectGround(sp.pose.inverseTransform(sp.road->centerline.pointAt(sp.s + d))))
      truth.push_back(*p);
  return truth;
}

std::optional<double> columnAt(const std::vector<Vec2>& curve, double v) {
  for (std::size_t k = 1; k < curve.size(); ++k)
    if ((curve[k - 1].y() - v) * (curve[k].y() - v) <= 0 && curve[k - 1].y() != curve[k].y())
      return curve[k - 1].x() + (v - curve[k - 1].y()) / (curve[k].y() - curve[k - 1].y()) * (curve[k].x() - curve[k - 1].x());
  return std::nullopt;
}

double worstCurveError(const RoadFinding& r, const RoadPose& sp) {
  const std::vector<Vec2> truth = truthCurve(sp);
  double worst = 0;
  for (const Vec2& p : r.centerline_curve)
    if (const auto u = columnAt(truth, p.y()); u && *u >= 0 && *u < cam().width())
      worst = std::max(worst, std::abs(p.x() - *u));
  return worst;
}

double bottomAngleError(const RoadFinding& r, const RoadPose& sp) {
  if (r.centerline_curve.size() < 2) return 180.0;
  const Vec2 a = r.centerline_curve[r.centerline_curve.size() - 2], b = r.centerline_curve.back();
  const std::vector<Vec2> curve = truthCurve(sp);
  const auto truthAt = [&](double v) { return columnAt(curve, v).value_or(std::nan("")); };
  const double found = std::atan2(b.x() - a.x(), b.y() - a.y());
  const double truth = std::atan2(truthAt(b.y()) - truthAt(a.y()), b.y() - a.y());
  return std::isfinite(truth) ? std::abs(found - truth) * 180.0 / std::numbers::pi : 180.0;
}

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

double topRowError(const RoadFinding& r, const RoadPose& sp) {
  if (r.centerline_curve.empty()) return 1e9;
  const Vec2 top = r.centerline_curve.front();
  const auto u = columnAt(truthCurve(sp), top.y());
  if (!u) return 1e9;
  return *u >= 0 && *u < cam().width() ? std::abs(top.x() - *u) : 0.0;
}

ArcVsLine arcVsLine(const std::vector<RoadPose>& poses, const Map& map,
                    std::optional<double> bootstrap_s, const WorldOptions& world_options,
                    ClusterPerceptronOptions arc_options) {
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

}  // namespace mapnav::visiontest
