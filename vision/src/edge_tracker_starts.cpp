// The edge tracker's start points (see edge_tracker.h): from the prediction's interest segments (the
// nearest road's left and right edges, each in the band its side colours choose, with the expected
// contrast sign), from the edges carried from the last frame, or from the options.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "edge_tracker_internal.h"
#include "mapnav/geometry/clip.h"
#include "mapnav/vision/edge_tracker.h"

namespace mapnav {

bool normalised(GreyBand b) { return b == GreyBand::NormalizedGreen || b == GreyBand::NormalizedRed; }

namespace {

/// Clips segment a→b to the box [lo, hi]; false when nothing is left.
bool clipSegment(Vec2& a, Vec2& b, const Vec2& lo, const Vec2& hi) {
  double t0 = 0, t1 = 1;
  const Vec2 d = b - a;
  for (int k = 0; k < 2; ++k) {
    for (int side = 0; side < 2; ++side) {
      const double p = side == 0 ? -d[k] : d[k];
      const double q = side == 0 ? a[k] - lo[k] : hi[k] - a[k];
      if (std::abs(p) < 1e-12) {
        if (q < 0) return false;
        continue;
      }
      const double r = q / p;
      if (p < 0) t0 = std::max(t0, r);
      else t1 = std::min(t1, r);
    }
  }
  if (t0 > t1) return false;
  const Vec2 a0 = a;
  a = a0 + t0 * d;
  b = a0 + t1 * d;
  return true;
}

/// The near end of an image segment clipped to the image, directed up the image.
/// The start is kept `margin` px from the image's sides, so that the step model fits in the image.
/// The edge's band: o.band, or with o.band_from_prediction the one its predicted side colours choose
/// (see EdgeTrackerOptions::band_from_prediction); their difference in it gives the expected contrast sign.
std::optional<EdgeStart> startFromSegment(const InterestSegment& s, const Camera& cam, int w, int h,
                                      const EdgeTrackerOptions& o, double margin = 16) {
  Vec2 a = s.image.a, b = s.image.b;
  // Recompute from the ground so that a clipped image segment is not an issue for curved lenses.
  const auto pa = cam.projectGround(s.vehicle.a), pb = cam.projectGround(s.vehicle.b);
  if (pa && pb) {
    a = *pa;
    b = *pb;
  }
  if (!clipSegment(a, b, Vec2(margin, 1), Vec2(w - 1.0 - margin, h - 2.0))) return std::nullopt;
  if ((b - a).norm() < 4) return std::nullopt;
  EdgeStart st;
  // Walking a → b on the ground is walking up the image when a is the lower end; then the image's
  // right of the edge is the segment's right side.
  const bool forward = a.y() >= b.y();
  if (forward) {
    st.point = a;
    st.direction = (b - a).normalized();
  } else {
    st.point = b;
    st.direction = (a - b).normalized();
  }
  st.label = s.id;
  const bool colours = s.left_rgb.norm() > 0 || s.right_rgb.norm() > 0;
  auto sideStep = [&](GreyBand b) {  // right side − left side, in band b
    return bandLevel(s.right_rgb.x(), s.right_rgb.y(), s.right_rgb.z(), b) -
           bandLevel(s.left_rgb.x(), s.left_rgb.y(), s.left_rgb.z(), b);
  };
  GreyBand band = o.band;
  if (colours && o.band_from_prediction && normalised(band)) {
    const double green = std::abs(sideStep(GreyBand::NormalizedGreen)), red = std::abs(sideStep(GreyBand::NormalizedRed));
    band = red > green ? GreyBand::NormalizedRed : GreyBand::NormalizedGreen;
    // Gravel against asphalt differs in brightness only: no normalised band separates them.
    if (std::max(green, red) < o.min_normalised_step && std::abs(sideStep(GreyBand::Luminance)) > std::max(green, red))
      band = GreyBand::Luminance;
  }
  st.band = band;
  const double diff = sideStep(band) * (forward ? 1 : -1);
  if (colours && std::abs(diff) >= 3) st.polarity = diff > 0 ? 1 : -1;
  return st;
}

/// Start points from the prediction: the road whose edge comes nearest the vehicle, its segments on
/// each side, nearest first (the lowest near end in the image), as {vehicle-left, vehicle-right};
/// false when neither is in the image. On a tight curve a narrow lens sees one edge only: the other
/// is then left empty.
bool startsFromPrediction(const PredictedObject& pred, const Camera& cam, int w, int h, const EdgeTrackerOptions& o,
                          std::vector<EdgeStart>& left, std::vector<EdgeStart>& right) {
  // The road: the nearest of those with both edges in the image, else the nearest. Past the end of
  // a road its last few metres of one edge can be the nearest thing in view, beside the next road
  // (park_loop's I2): tracing that stub alone loses the frame.
  const InterestSegment* nearest = nullptr;
  double best = std::numeric_limits<double>::infinity();
  bool both = false;
  for (const InterestSegment& s : pred.segments) {
    if (s.side != "left" && s.side != "right") continue;
    const double d = s.vehicle.distanceTo(Vec2::Zero());
    if ((both && d >= best) || !startFromSegment(s, cam, w, h, o)) continue;  // no better than the road found
    const bool pair = std::any_of(pred.segments.begin(), pred.segments.end(), [&](const InterestSegment& t) {
      return t.owner == s.owner && (t.side == "left" || t.side == "right") && t.side != s.side && startFromSegment(t, cam, w, h, o);
    });
    if ((pair && !both) || (pair == both && d < best)) {
      best = d;
      nearest = &s;
      both = pair;
    }
  }
  if (nearest == nullptr) return false;
  std::vector<std::pair<const InterestSegment*, EdgeStart>> side[2];  // road's left, right
  for (const InterestSegment& s : pred.segments) {
    if (s.owner != nearest->owner || (s.side != "left" && s.side != "right")) continue;
    if (auto st = startFromSegment(s, cam, w, h, o)) side[s.side == "left" ? 0 : 1].emplace_back(&s, std::move(*st));
  }
  for (auto& v : side)
    std::stable_sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.second.point.y() > b.second.point.y(); });
  // Which is the vehicle's left: with both, the larger y at the nearest segments' midpoints; with
  // one, the road's left is the vehicle's when the road runs forward (its segments point a → b).
  bool road_left_is_vehicle_left = true;
  if (!side[0].empty() && !side[1].empty()) {
    road_left_is_vehicle_left =
        side[0].front().first->vehicle.pointAt(0.5).y() >= side[1].front().first->vehicle.pointAt(0.5).y();
  } else {
    const InterestSegment* one = !side[0].empty() ? side[0].front().first : side[1].front().first;
    road_left_is_vehicle_left = (one->vehicle.b - one->vehicle.a).x() >= 0;
  }
  for (int k = 0; k < 2; ++k) {
    const bool vehicle_left = (k == 0) == road_left_is_vehicle_left;
    for (auto& [segment, st] : side[k]) (vehicle_left ? left : right).push_back(std::move(st));
  }
  return true;
}

/// The leftmost and the rightmost column of the ring on image row v.
std::optional<std::pair<double, double>> rowCrossings(const Polygon2& ring, double v) {
  const Segment2 row{Vec2(-1e6, v), Vec2(1e6, v)};
  const std::vector<Interval> in = intervalsInside(row, ring);
  if (in.empty()) return std::nullopt;
  return std::pair{row.pointAt(in.front().first).x(), row.pointAt(in.back().second).x()};
}

/// Start points from the prediction's first road region (a prediction without interest segments):
/// its leftmost and rightmost columns half a window above its lowest row in the image, directed to
/// its sides' columns at its highest row; the first window searches o.start_search_m either side.
/// False when the region is not seen (fewer than 3 of its corners project, or it is under 8 rows).
bool startsFromRegion(const PredictedObject& pred, const Camera& cam, int w, int h, const EdgeTrackerOptions& o,
                      EdgeStarts& s) {
  if (pred.regions.empty() || pred.regions.front().vehicle.empty()) return false;
  Polygon2 ring;
  for (const Vec2& g : pred.regions.front().vehicle.front())
    if (const auto p = cam.projectGround(g)) ring.push_back(*p);
  if (ring.size() < 3) return false;
  double bottom = -std::numeric_limits<double>::infinity(), top = -bottom;
  for (const Vec2& p : ring) {
    bottom = std::max(bottom, p.y());
    top = std::min(top, p.y());
  }
  bottom = std::min(bottom, h - 1.0);
  top = std::max(top, 0.0);
  const double v0 = std::max(top, bottom - 0.5 * paramsFor(o, w, h).along_px);
  const auto lo = rowCrossings(ring, v0), hi = rowCrossings(ring, top + 1e-6);
  if (!lo || !hi || bottom - top < 8) return false;
  const std::string id = pred.regions.front().id;
  auto start = [&](double u0, double u1, const char* side) {
    EdgeStart st;
    st.point = Vec2(std::clamp(u0, 0.0, w - 1.0), v0);
    st.direction = (Vec2(u1, top) - Vec2(u0, v0)).normalized();
    st.label = id + "." + side;
    st.band = o.band;
    // The search: o.start_search_m outward on the ground at the start's range, and inward up to
    // the region's centre (the road lies between its edges).
    const auto g = cam.backproject(st.point);
    const auto q = g ? cam.projectGround(*g + Vec2(0, o.start_search_m)) : std::nullopt;
    const double reach = q ? std::abs(q->x() - st.point.x()) : w;
    const double centre = 0.5 * (lo->first + lo->second);
    st.search_lo_u = side[0] == 'l' ? st.point.x() - reach : centre;
    st.search_hi_u = side[0] == 'l' ? centre : st.point.x() + reach;
    return st;
  };
  s.left = start(lo->first, hi->first, "left");
  s.right = start(lo->second, hi->second, "right");
  s.source = "region";
  return true;
}

}  // namespace

std::optional<EdgeStart> startFromCarried(const std::vector<Vec2>& ground, const std::optional<std::string>& label,
                                      const Camera& cam, int w, int h) {
  std::vector<Vec2> px;
  for (const Vec2& g : ground) {
    const auto p = cam.projectGround(g);
    if (p && p->x() >= 1 && p->y() >= 1 && p->x() <= w - 2 && p->y() <= h - 2) px.push_back(*p);
  }
  if (px.size() < 2) return std::nullopt;
  std::sort(px.begin(), px.end(), [](const Vec2& a, const Vec2& b) { return a.y() > b.y(); });
  EdgeStart st;
  st.point = px[0];
  st.direction = (px[std::min<std::size_t>(px.size() - 1, 2)] - px[0]).normalized();
  st.label = label;
  return st;
}

EdgeStarts chooseStarts(const PredictedObject& pred, const Camera& cam, int w, int h, const EdgeTrackerOptions& o,
                        const std::optional<EdgeStart>& carried_left, const std::optional<EdgeStart>& carried_right) {
  EdgeStarts s;
  s.left.band = s.right.band = o.band;
  if (startsFromPrediction(pred, cam, w, h, o, s.left_next, s.right_next)) {
    s.source = "prediction";
    s.trace_left = !s.left_next.empty();
    s.trace_right = !s.right_next.empty();
    if (s.trace_left) s.left = s.left_next.front();
    if (s.trace_right) s.right = s.right_next.front();
  } else if (carried_left && carried_right) {
    s.left = *carried_left;
    s.right = *carried_right;
    s.left.band = s.right.band = o.band;
    s.source = "carried";
  } else if (!startsFromRegion(pred, cam, w, h, o, s)) {
    const double sv = o.start_v >= 0 ? o.start_v : h - 1 - 0.5 * paramsFor(o, w, h).along_px;
    s.left.point = Vec2(o.start_left_u >= 0 ? o.start_left_u : 0.25 * w, sv);
    s.right.point = Vec2(o.start_right_u >= 0 ? o.start_right_u : 0.75 * w, sv);
    s.left.direction = Vec2(std::sin(o.start_left_angle_deg * kDeg), -std::cos(o.start_left_angle_deg * kDeg));
    s.right.direction = Vec2(std::sin(o.start_right_angle_deg * kDeg), -std::cos(o.start_right_angle_deg * kDeg));
    s.source = "options";
  }
  return s;
}

}  // namespace mapnav
