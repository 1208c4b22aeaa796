// The edge tracker's tracing and evaluation (Wallace et al. 1985, 3.1-3.2): an edge followed up the
// image from a start point window by window, the paper's measures of the trace (3.2.1: contrast height,
// edge width, smoothness, consistency), and the edges carried into the next frame. See edge_tracker.h.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

#include "edge_tracker_internal.h"
#include "mapnav/vision/edge_tracker.h"

namespace mapnav {

double edgeMedian(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

EdgeTracker::EdgeTracker(EdgeTrackerOptions options) : options_(std::move(options)) { options_.validate(); }

void EdgeTracker::setOptions(const EdgeTrackerOptions& options) {
  options.validate();
  options_ = options;
}

OrientedEdgeParams paramsFor(const EdgeTrackerOptions& o, int width, int height) {
  OrientedEdgeParams p;
  p.along_px = std::max(4, static_cast<int>(std::lround(o.window_rows * height / 480.0)));
  p.across_px = std::max(8, static_cast<int>(std::lround(o.window_cols * width / 512.0)));
  p.step_half_width_px = std::max(1, static_cast<int>(std::lround(o.step_half_width_px * width / 512.0)));
  p.angle_search_deg = o.angle_search_deg;
  p.angle_step_deg = o.angle_step_deg;
  return p;
}

namespace {

/// The paper's evaluation of a trace (3.2.1) into e.eval.
void evaluate(TrackedEdge& e, double max_turn_deg) {
  EdgeEvaluation& ev = e.eval;
  const std::size_t n = e.matches.size();
  if (n == 0) return;
  std::vector<double> c;
  for (const EdgeMatch& m : e.matches) {
    c.push_back(std::abs(m.contrast));
    ev.contrast += std::abs(m.contrast);
    ev.width_px += m.width_px;
  }
  ev.contrast /= static_cast<double>(n);
  ev.width_px /= static_cast<double>(n);
  double ss = 0;
  int cnt = 0;
  for (std::size_t i = 1; i + 1 < e.image.size(); ++i) {
    const Segment2 chord{e.image[i - 1], e.image[i + 1]};
    const double d = chord.distanceTo(e.image[i]);
    ss += d * d;
    ++cnt;
  }
  ev.smoothness = cnt > 0 ? std::sqrt(ss / cnt) : 0;
  const double med = edgeMedian(c);
  int good = 0;
  for (std::size_t i = 0; i < n; ++i) {
    bool ok = c[i] >= 0.5 * med && c[i] <= 2 * med;
    if (i >= 2) {
      const Vec2 a = (e.image[i - 1] - e.image[i - 2]).normalized(), b = (e.image[i] - e.image[i - 1]).normalized();
      const double turn = std::acos(std::clamp(a.dot(b), -1.0, 1.0)) / kDeg;
      ok = ok && turn <= max_turn_deg / 2;
    }
    if (ok) ++good;
  }
  ev.consistency = static_cast<double>(good) / static_cast<double>(n);
  // Score: contrast saturating at 20 grey levels, times consistency, less for a rough trace.
  ev.score = std::clamp(ev.contrast / 20.0, 0.0, 1.0) * ev.consistency * std::exp(-ev.smoothness / 4.0);
}

}  // namespace

EdgeMatch EdgeTracker::searchRow(const GreyImage& image, const Vec2& at, const Vec2& dir, const OrientedEdgeParams& p,
                                 int polarity, double lo, double hi) const {
  OrientedEdgeParams wide = p;
  wide.angle_search_deg = std::max(p.angle_search_deg, options_.start_angle_search_deg);
  wide.angle_step_deg = std::max(p.angle_step_deg, 2.0);
  EdgeMatch best;
  auto strength = [&](const EdgeMatch& m) { return polarity == 0 ? std::abs(m.contrast) : polarity * m.contrast; };
  const double spacing = 0.5 * p.across_px;
  lo = std::max(lo, 0.0);
  hi = std::min(hi, image.width - 1.0);
  for (double u = lo; u <= hi + 0.5 * spacing; u += spacing) {
    EdgeMatch m = orientedEdge(image, Vec2(std::min(u, hi), at.y()), dir, wide, polarity);
    if (!m.found || m.point.x() < lo || m.point.x() > hi) continue;
    if (!best.found || strength(m) > strength(best)) best = std::move(m);
  }
  return best;
}

TrackedEdge EdgeTracker::trace(const GreyImage& image, const Vec2& start, const Vec2& direction,
                               int expected_polarity, bool gate, double search_lo_u,
                               double search_hi_u) const {
  TrackedEdge e;
  e.start = start;
  e.start_direction = direction.normalized();
  OrientedEdgeParams p = paramsFor(options_, image.width, image.height);
  const double step = options_.step_fraction * p.along_px;
  auto inside = [&](const Vec2& q) {
    return q.x() >= -0.5 && q.y() >= -0.5 && q.x() <= image.width - 0.5 && q.y() <= image.height - 0.5;
  };
  Vec2 dir = e.start_direction;
  if (dir.y() > 0) dir = -dir;  // trace up the image
  // The start point and, when no step is found there, the next few predicted points along the
  // start direction: a start clipped into an image corner has most of its window outside.
  EdgeMatch m;
  for (int k = 0; k < 4; ++k) {
    const Vec2 at = start + k * step * dir;
    if (!inside(at)) break;
    m = search_lo_u <= search_hi_u ? searchRow(image, at, dir, p, expected_polarity, search_lo_u, search_hi_u)
                                   : orientedEdge(image, at, dir, p, expected_polarity);
    if (m.found && std::abs(m.contrast) >= options_.min_contrast) break;
  }
  if (!m.found || std::abs(m.contrast) < options_.min_contrast) {
    e.stop_reason = "no step edge at the start point";
    return e;
  }
  const int polarity = m.contrast > 0 ? 1 : -1;
  // gate_search: after the first point, only steps the trace can reach without turning more than
  // max_turn_deg. Off by default: under heavy shadow it turns "edge lost" into a wrong trace.
  if (options_.gate_search || gate) p.max_offset_px = step * std::tan(std::min(options_.max_turn_deg, 80.0) * kDeg);
  m.profile.clear();
  e.image.push_back(m.point);
  e.matches.push_back(m);
  while (static_cast<int>(e.image.size()) < options_.max_points) {
    const Vec2 predicted = e.image.back() + step * dir;
    if (!inside(predicted)) {
      e.reached_top = true;
      e.stop_reason = "the search window left the image";
      break;
    }
    EdgeMatch next = orientedEdge(image, predicted, dir, p, polarity);
    if (!next.found || std::abs(next.contrast) < options_.min_contrast) {
      e.stop_reason = "edge contrast lost";
      break;
    }
    const Vec2 moved = next.point - e.image.back();
    if (moved.norm() < 0.25 * step) {
      e.stop_reason = "edge did not advance";
      break;
    }
    const Vec2 nd = moved.normalized();
    const double turn = std::acos(std::clamp(nd.dot(dir), -1.0, 1.0)) / kDeg;
    if (turn > options_.max_turn_deg) {
      e.stop_reason = "edge turned too sharply";
      break;
    }
    next.profile.clear();
    e.image.push_back(next.point);
    e.matches.push_back(next);
    dir = nd;  // theta = atan2(c_i - c_{i-1}, r_i - r_{i-1})
  }
  if (e.stop_reason.empty()) e.stop_reason = "max_points reached";
  evaluate(e, options_.max_turn_deg);
  return e;
}

void EdgeTracker::advance(const Pose2& motion) {
  auto carry = [&](const std::optional<Carried>& last) -> std::optional<Carried> {
    if (!last) return std::nullopt;
    Carried c;
    c.label = last->label;
    for (const Vec2& g : last->ground) c.ground.push_back(motion.inverseTransform(g));
    return c;
  };
  carried_left_ = carry(last_left_);
  carried_right_ = carry(last_right_);
}

void EdgeTracker::reset() {
  carried_left_.reset();
  carried_right_.reset();
  last_left_.reset();
  last_right_.reset();
  report_ = {};
}

}  // namespace mapnav
