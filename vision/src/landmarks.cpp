// Finding the predicted landmarks in a frame (landmarks.h).
#include "mapnav/vision/landmarks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "mapnav/core/error.h"
#include "mapnav/core/options.h"

namespace mapnav {

void LandmarkFinderOptions::validate() const {
  auto require = [](bool ok, const char* field, double value, const char* rule) {
    requireOption(ok, "LandmarkFinderOptions", field, value, rule);
  };
  require(std::isfinite(gate_sigma) && gate_sigma > 0, "gate_sigma", gate_sigma, "finite and > 0");
  require(std::isfinite(min_search_px) && min_search_px >= 1, "min_search_px", min_search_px, "finite and >= 1");
  require(std::isfinite(max_search_px) && max_search_px >= min_search_px && max_search_px <= 500, "max_search_px",
          max_search_px, "finite, >= min_search_px and <= 500");
  require(std::isfinite(probe_height_m) && probe_height_m > 0, "probe_height_m", probe_height_m, "finite and > 0");
  require(std::isfinite(side_px) && side_px >= 1 && side_px <= 50, "side_px", side_px, "in [1, 50]");
  require(std::isfinite(below_px) && below_px >= 1 && below_px <= 50, "below_px", below_px, "in [1, 50]");
  require(std::isfinite(min_contrast) && min_contrast >= 0, "min_contrast", min_contrast, "finite and >= 0");
  require(std::isfinite(base_sigma_u_px) && base_sigma_u_px > 0, "base_sigma_u_px", base_sigma_u_px, "finite and > 0");
  require(std::isfinite(base_sigma_v_px) && base_sigma_v_px > 0, "base_sigma_v_px", base_sigma_v_px, "finite and > 0");
}

namespace {

// Prefix sums along each row of the three channels and of their squares' sum: the mean colour and
// spread of a run of pixels in O(1), of a sheared strip (a vertical in the world seen leaning) in
// O(rows).
class RowSums {
 public:
  explicit RowSums(const VisionFrame& f) : w_(f.width), h_(f.height), s_(static_cast<std::size_t>(w_ + 1) * h_ * 4, 0.0) {
    for (int v = 0; v < h_; ++v) {
      const std::uint8_t* px = f.rgb + static_cast<std::size_t>(v) * w_ * 3;
      double* row = &s_[static_cast<std::size_t>(v) * (w_ + 1) * 4];
      for (int u = 0; u < w_; ++u) {
        const double r = px[3 * u], g = px[3 * u + 1], b = px[3 * u + 2];
        row[4 * (u + 1)] = row[4 * u] + r;
        row[4 * (u + 1) + 1] = row[4 * u + 1] + g;
        row[4 * (u + 1) + 2] = row[4 * u + 2] + b;
        row[4 * (u + 1) + 3] = row[4 * u + 3] + r * r + g * g + b * b;
      }
    }
  }

  /// The mean colour and the colour's standard deviation (root of the channels' summed variances)
  /// over the rows [v0, v1), row v taking the columns [u0 + shift(v), u1 + shift(v)) with
  /// shift(v) = round(slope (v - v_ref)); clipped to the frame; nullopt when that is empty.
  struct Stats {
    Vec3 mean;
    double spread;
  };
  std::optional<Stats> strip(double u0, double u1, int v0, int v1, double slope, int v_ref) const {
    double sum[4] = {0, 0, 0, 0};
    long n = 0;
    for (int v = std::max(v0, 0); v < std::min(v1, h_); ++v) {
      const double shift = slope * (v - v_ref);
      const int a = std::clamp(static_cast<int>(std::lround(u0 + shift)), 0, w_);
      const int b = std::clamp(static_cast<int>(std::lround(u1 + shift)), 0, w_);
      if (b <= a) continue;
      const double* row = &s_[static_cast<std::size_t>(v) * (w_ + 1) * 4];
      for (int c = 0; c < 4; ++c) sum[c] += row[4 * b + c] - row[4 * a + c];
      n += b - a;
    }
    if (n == 0) return std::nullopt;
    const Vec3 mean = Vec3(sum[0], sum[1], sum[2]) / double(n);
    return Stats{mean, std::sqrt(std::max(0.0, sum[3] / double(n) - mean.squaredNorm()))};
  }

  int width() const { return w_; }
  int height() const { return h_; }

 private:
  int w_, h_;
  std::vector<double> s_;
};

// The pixel standard deviations of the predicted base that the pose's covariance implies: a pose
// error (dx, dy, dheading) moves a vehicle-frame point p by J = [[-1, 0, p.y], [0, -1, -p.x]].
Vec2 basePixelSigma(const Camera& camera, const PredictedLandmark& l, const Mat3& pose_covariance) {
  Eigen::Matrix<double, 2, 3> j;
  j << -1, 0, l.vehicle.y(), 0, -1, -l.vehicle.x();
  const Mat2 ground = j * pose_covariance * j.transpose();
  Mat2 jp = Mat2::Zero();  // d(pixel) / d(ground point), central differences of 1 cm
  for (int k = 0; k < 2; ++k) {
    const Vec2 d = 0.01 * Vec2::Unit(k);
    const auto a = camera.projectGround(l.vehicle + d), b = camera.projectGround(l.vehicle - d);
    if (a && b) jp.col(k) = (*a - *b) / 0.02;
  }
  const Mat2 px = jp * ground * jp.transpose();
  return Vec2(std::sqrt(std::max(0.0, px(0, 0))), std::sqrt(std::max(0.0, px(1, 1))));
}

// What a landmark whose base is seen at image row `v` (column u) looks like there: its width, the
// height of its probed part, and (flat) its vertical extent, px; and the ground point under it.
struct RowShape {
  double width = 0, probe = 0, depth = 0;
  double lean = 0;  ///< du/dv of the vertical through the base, seen in the image
  Vec2 ground = Vec2::Zero();
};

std::optional<RowShape> shapeAt(const Camera& camera, const PredictedLandmark& l, double u, double v, double probe_m) {
  const auto g = camera.backproject(Vec2(u, v));
  if (!g) return std::nullopt;
  const Vec2 sight = (*g - camera.center().head<2>()).normalized();
  const auto width = groundWidthPx(camera, *g, l.radius_m);
  const auto near = camera.projectGround(*g - sight * l.radius_m), far = camera.projectGround(*g + sight * l.radius_m);
  const auto top = camera.project(Vec3(g->x(), g->y(), std::min(probe_m, l.height_m)));
  if (!width || !near || !far || !top) return std::nullopt;
  const double probe = v - top->y();
  return RowShape{*width, probe, std::abs(near->y() - far->y()), probe > 0 ? (u - top->x()) / probe : 0.0, *g};
}

double distance(const std::optional<RowSums::Stats>& a, const std::optional<RowSums::Stats>& b) {
  return a && b ? (a->mean - b->mean).norm() : -std::numeric_limits<double>::infinity();
}

// How well an upright landmark with its base's visible front edge at (u, v) explains the frame: the
// least of its colour's distances from the strips beside it and from the ground in front of it,
// less the difference between its upper and lower halves. Something standing is the same colour
// all the way up (its shading runs across it, not up it); a strip across a slanting boundary
// between two surfaces differs from both sides too, but holds more of one surface at the top than
// at the bottom. Its strips lean as the vertical through it does.
double uprightScore(const RowSums& in, int u, int v, const RowShape& s, const LandmarkFinderOptions& o) {
  const double hw = std::max(1.0, s.width / 2);
  const int probe = std::max(2, static_cast<int>(std::lround(s.probe))), mid = v - probe / 2;
  // All of it and its side strips in the frame, and at least half its probed height: a landmark cut
  // by the frame's edge cannot be told from the ground beside it, nor its centre found.
  const double reach = hw + o.side_px + std::abs(s.lean) * probe;
  if (u - reach < 0 || u + reach > in.width() || v + o.below_px > in.height() || v - probe / 2 < 0) {
    return -std::numeric_limits<double>::infinity();
  }
  const auto body = in.strip(u - hw, u + hw, v - probe, v, s.lean, v);
  const double d = std::min({distance(body, in.strip(u - hw - o.side_px, u - hw, v - probe, v, s.lean, v)),
                             distance(body, in.strip(u + hw, u + hw + o.side_px, v - probe, v, s.lean, v)),
                             distance(body, in.strip(u - hw, u + hw, v, v + static_cast<int>(o.below_px), 0.0, v))});
  const double halves = distance(in.strip(u - hw, u + hw, v - probe, mid, s.lean, v), in.strip(u - hw, u + hw, mid, v, s.lean, v));
  return std::isfinite(halves) ? d - halves : d;
}

// The same for a flat mark centred at (u, v): its inner part against the strips all round it.
double flatScore(const RowSums& in, int u, int v, const RowShape& s, const LandmarkFinderOptions& o) {
  const double hu = std::max(1.0, 0.35 * s.width), ou = 0.5 * s.width + 1;
  const int hv = std::max(1, static_cast<int>(std::lround(0.35 * s.depth))), ov = static_cast<int>(std::lround(0.5 * s.depth)) + 1;
  const int side = static_cast<int>(o.side_px);
  if (u - ou - side < 0 || u + ou + side > in.width() || v - ov - side < 0 || v + ov + side > in.height()) {
    return -std::numeric_limits<double>::infinity();  // all of it and the paving round it in the frame
  }
  const auto body = in.strip(u - hu, u + hu, v - hv, v + hv + 1, 0.0, v);
  const double d = std::min({distance(body, in.strip(u - ou - o.side_px, u - ou, v - hv, v + hv + 1, 0.0, v)),
                             distance(body, in.strip(u + ou, u + ou + o.side_px, v - hv, v + hv + 1, 0.0, v)),
                             distance(body, in.strip(u - hu, u + hu, v - ov - side, v - ov, 0.0, v)),
                             distance(body, in.strip(u - hu, u + hu, v + ov + 1, v + ov + 1 + side, 0.0, v))});
  return body ? d - body->spread : d;
}

// The offset of a parabola's vertex through (-1, a), (0, b), (1, c) from 0, within ±0.5.
double vertex(double a, double b, double c) {
  const double d = a - 2 * b + c;
  if (!std::isfinite(d) || d >= 0) return 0;
  return std::clamp(0.5 * (a - c) / d, -0.5, 0.5);
}

// An upright landmark's base front edge row (image coordinates, pixel centres at integers) refined
// from the best place (u, v) of the search: the row, within 5 of v, where the colour of the middle of its
// band changes most (3 rows above against 3 below): its foot against the ground in front, which a
// lit or shaded patch of that ground (a canopy's shadow edge) pulls the search's place off by a few
// rows.
double refinedBaseRow(const RowSums& in, int u, int v, const RowShape& s) {
  const double hw = std::max(1.0, s.width / 2);
  const int reach = 5;
  std::vector<double> step;  // step[k]: the change at the boundary above row v - reach - 1 + k
  for (int b = v - reach - 1; b <= v + reach + 1; ++b) {
    step.push_back(distance(in.strip(u - 0.6 * hw, u + 0.6 * hw, b - 3, b, s.lean, v),
                            in.strip(u - 0.6 * hw, u + 0.6 * hw, b, b + 3, s.lean, v)));
  }
  const auto top = std::max_element(step.begin() + 1, step.end() - 1);
  const auto k = static_cast<std::size_t>(top - step.begin());
  const double row = std::isfinite(*top) ? v - reach - 1 + double(k) + vertex(step[k - 1], step[k], step[k + 1]) : double(v);
  return row - 0.5;
}

// The column of an upright landmark's middle refined from the search's u: the strongest colour
// change within 3 columns of each predicted side (columns averaged over its probed rows, leaning),
// and the middle between the two.
double refinedMiddleColumn(const RowSums& in, int u, int v, const RowShape& s) {
  const double hw = std::max(1.0, s.width / 2);
  const int probe = std::max(2, static_cast<int>(std::lround(s.probe)));
  auto edgeNear = [&](double c0) {
    double best = -1, at = c0;
    for (int c = static_cast<int>(std::lround(c0)) - 3; c <= static_cast<int>(std::lround(c0)) + 3; ++c) {
      const double g = distance(in.strip(c - 2, c, v - probe, v, s.lean, v), in.strip(c, c + 2, v - probe, v, s.lean, v));
      if (g > best) best = g, at = c;
    }
    return at;  // the boundary between columns at - 1 and at
  };
  return 0.5 * (edgeNear(u - hw) + edgeNear(u + hw)) - 0.5;
}

DetectedLandmark findOne(const RowSums& sums, const Camera& camera, const PredictedLandmark& l, const Mat3& pose_covariance,
                         const LandmarkFinderOptions& o) {
  DetectedLandmark out;
  out.id = l.id;
  const bool upright = l.height_m > 0;
  const Vec2 sigma = basePixelSigma(camera, l, pose_covariance);
  const int ru = static_cast<int>(std::ceil(std::clamp(o.gate_sigma * sigma.x(), o.min_search_px, o.max_search_px)));
  const int rv = static_cast<int>(std::ceil(std::clamp(o.gate_sigma * sigma.y(), o.min_search_px, o.max_search_px)));
  const int u0 = static_cast<int>(std::lround(l.image_base.x())), v0 = static_cast<int>(std::lround(l.image_base.y()));
  // Where the frame's side edge may cut it off, part of it could be taken for all of it.
  const double half = l.width_px / 2 + o.side_px;
  if (u0 - ru - half < 0 || u0 + ru + half > camera.width()) {
    out.reason = "too near the frame's side edge to be told whole";
    return out;
  }
  std::vector<double> score(static_cast<std::size_t>(2 * ru + 3) * (2 * rv + 3), -std::numeric_limits<double>::infinity());
  auto at = [&](int du, int dv) -> double& { return score[static_cast<std::size_t>(dv + rv + 1) * (2 * ru + 3) + (du + ru + 1)]; };
  double best = -std::numeric_limits<double>::infinity();
  int bu = 0, bv = 0;
  for (int dv = -rv - 1; dv <= rv + 1; ++dv) {
    const auto shape = shapeAt(camera, l, u0, v0 + dv, o.probe_height_m);
    if (!shape) continue;
    for (int du = -ru - 1; du <= ru + 1; ++du) {
      const double s = upright ? uprightScore(sums, u0 + du, v0 + dv, *shape, o) : flatScore(sums, u0 + du, v0 + dv, *shape, o);
      at(du, dv) = s;
      if (std::abs(du) <= ru && std::abs(dv) <= rv && s > best) best = s, bu = du, bv = dv;
    }
  }
  out.score = std::clamp(best / (2 * o.min_contrast), 0.0, 1.0);
  // A peak, not the edge of what could be scored (the frame's border cutting it off there).
  const bool peak = std::isfinite(at(bu - 1, bv)) && std::isfinite(at(bu + 1, bv)) && std::isfinite(at(bu, bv - 1)) &&
                    std::isfinite(at(bu, bv + 1));
  if (!(best >= o.min_contrast) || !peak) {
    out.reason = upright ? "nothing standing out from the ground beside it near its prediction"
                         : "no patch differing from the paving all round it near its prediction";
    return out;
  }
  Vec2 found(u0 + bu + vertex(at(bu - 1, bv), at(bu, bv), at(bu + 1, bv)) - 0.5,
             v0 + bv + vertex(at(bu, bv - 1), at(bu, bv), at(bu, bv + 1)) - 0.5);  // pixel centres at integers
  if (upright) {
    if (const auto best_shape = shapeAt(camera, l, u0 + bu, v0 + bv, o.probe_height_m)) {
      found.y() = refinedBaseRow(sums, u0 + bu, v0 + bv, *best_shape);
      found.x() = refinedMiddleColumn(sums, u0 + bu, v0 + bv, *best_shape);
    }
  }
  const auto shape = shapeAt(camera, l, found.x(), found.y(), o.probe_height_m);
  if (!shape) return out;
  out.found = true;
  out.image_base = found;
  if (upright) {  // the row found is its base's front edge: the centre is a radius further away
    const Vec2 sight = (shape->ground - camera.center().head<2>()).normalized();
    if (const auto centre = camera.projectGround(shape->ground + sight * l.radius_m)) out.image_base = *centre;
  }
  const double su = std::hypot(o.base_sigma_u_px, 0.25 * shape->width);
  out.covariance = Vec2(su * su, o.base_sigma_v_px * o.base_sigma_v_px).asDiagonal();
  return out;
}

}  // namespace

std::vector<DetectedLandmark> findLandmarks(const VisionFrame& frame, const PredictedObject& prediction,
                                            const LandmarkFinderOptions& options) {
  options.validate();
  if (frame.rgb == nullptr || frame.camera == nullptr || frame.width <= 0 || frame.height <= 0) {
    throw InvalidInput("findLandmarks: the frame needs its pixels and its camera");
  }
  std::vector<DetectedLandmark> out;
  if (prediction.landmarks.empty()) return out;
  const RowSums sums(frame);
  for (const PredictedLandmark& l : prediction.landmarks) {
    out.push_back(findOne(sums, *frame.camera, l, prediction.pose_covariance, options));
  }
  return out;
}

}  // namespace mapnav
