// Finding the predicted landmarks in a frame (landmarks.h).
#include "mapnav/vision/landmarks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "mapnav/core/error.h"
#include "subpixel.h"

namespace mapnav {

const OptionTable<LandmarkFinderOptions>& landmarkFinderOptionTable() {
  using O = LandmarkFinderOptions;
  static const OptionTable<O> table =
      OptionTable<O>("LandmarkFinderOptions")
          .field("gate_sigma", &O::gate_sigma, above(0),
                 "the search about the predicted base: this many sigma of the pose's covariance seen in the image")
          .field("min_search_px", &O::min_search_px, atLeast(1), "... at least this far each way, px")
          .field("max_search_px", &O::max_search_px, OptionRule{.max = 500}, "... at most this far each way, px")
          .field("probe_height_m", &O::probe_height_m, above(0),
                 "something standing is compared with its sides from its base up this far (or its height), m")
          .field("min_probe_in_frame", &O::min_probe_in_frame, aboveUpTo(0, 1),
                 "at least this fraction of that height must be in the frame")
          .field("side_px", &O::side_px, inRange(1, 50), "the strips beside it that must differ from it, px")
          .field("below_px", &O::below_px, inRange(1, 50), "the ground in front of its base compared with it, px")
          .field("rim_step_px", &O::rim_step_px, inRange(0.5, 10),
                 "a manhole cover's rim: the colour this far inside it against this far outside, px")
          .field("min_contrast", &O::min_contrast, atLeast(0),
                 "found when the colour steps at its sides and foot (or round a rim) are at least this, levels")
          .field("min_peak_ratio", &O::min_peak_ratio, atLeast(1),
                 "found only where it explains the frame this many times better than the best place clear of it")
          .field("base_sigma_u_px", &O::base_sigma_u_px, above(0),
                 "the standard deviation of a found base across the image, px, at least")
          .field("base_sigma_v_px", &O::base_sigma_v_px, above(0), "... and up the image, px, at least")
          .check("max_search_px", [](const O& o) { return o.max_search_px >= o.min_search_px; }, ">= min_search_px");
  return table;
}

void LandmarkFinderOptions::validate() const { landmarkFinderOptionTable().validate(*this); }

namespace {

// Prefix sums along each row of the three channels and of their squares' sum: the mean colour and
// spread of a run of pixels in O(1), of a sheared strip (a vertical in the world seen leaning) in
// O(rows). Each row is summed when a strip first asks for it (a frame's landmarks look at a few
// hundred rows of narrow columns; summing the whole frame up front, in a zeroed buffer of 8 MB at
// 512 x 480, was the landmark finder's largest cost).
class RowSums {
 public:
  explicit RowSums(const VisionFrame& f)
      : f_(f), w_(f.width), h_(f.height), s_(new double[static_cast<std::size_t>(w_ + 1) * h_ * 4]),
        done_(static_cast<std::size_t>(h_), 0) {}

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
      const double* row = sums(v);
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
  // Row v's prefix sums, summed on first use.
  const double* sums(int v) const {
    double* row = &s_[static_cast<std::size_t>(v) * (w_ + 1) * 4];
    if (done_[static_cast<std::size_t>(v)]) return row;
    const std::uint8_t* px = f_.rgb + static_cast<std::size_t>(v) * w_ * 3;
    row[0] = row[1] = row[2] = row[3] = 0;
    for (int u = 0; u < w_; ++u) {
      const double r = px[3 * u], g = px[3 * u + 1], b = px[3 * u + 2];
      row[4 * (u + 1)] = row[4 * u] + r;
      row[4 * (u + 1) + 1] = row[4 * u + 1] + g;
      row[4 * (u + 1) + 2] = row[4 * u + 2] + b;
      row[4 * (u + 1) + 3] = row[4 * u + 3] + r * r + g * g + b * b;
    }
    done_[static_cast<std::size_t>(v)] = 1;
    return row;
  }

  const VisionFrame& f_;
  int w_, h_;
  std::unique_ptr<double[]> s_;       // uninitialised: a row is written before it is read
  mutable std::vector<char> done_;    // the rows summed
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

// What something standing whose base is seen at image row `v` (column u) looks like there: its
// width and the height of its probed part, px; and the ground point under it.
struct RowShape {
  double width = 0, probe = 0;
  double lean = 0;  ///< du/dv of the vertical through the base, seen in the image
  Vec2 ground = Vec2::Zero();
};

std::optional<RowShape> shapeAt(const Camera& camera, const PredictedLandmark& l, double u, double v, double probe_m) {
  const auto g = camera.backproject(Vec2(u, v));
  if (!g) return std::nullopt;
  const auto width = groundWidthPx(camera, *g, l.radius_m);
  const auto top = camera.project(Vec3(g->x(), g->y(), std::min(probe_m, l.height_m)));
  if (!width || !top) return std::nullopt;
  const double probe = v - top->y();
  return RowShape{*width, probe, probe > 0 ? (u - top->x()) / probe : 0.0, *g};
}

double distance(const std::optional<RowSums::Stats>& a, const std::optional<RowSums::Stats>& b) {
  return a && b ? (a->mean - b->mean).norm() : -std::numeric_limits<double>::infinity();
}

// How well an upright landmark with its base's visible front edge at (u, v) explains the frame, in
// colour levels: the least of
// - in each third of its probed height, its colour's distance from the strips on either side (a
//   blob of shade or a tuft of grass differs from its sides over part of that height, not all);
// - its lowest rows' distance from the ground just in front of its base (its foot: higher up the
//   body, the rows below are the body again);
// less the most its thirds differ from one another: something standing is the same colour all the
// way up (its shading runs across it, not up it), while a strip across a slanting boundary between
// two surfaces holds more of one surface at the top than at the bottom. Its strips lean as the
// vertical through it does. All of it and its side strips must be in the frame, and at least
// min_probe_in_frame of its probed height: a landmark cut by the frame's side edge cannot be told
// from the ground beside it, nor its centre found.
double uprightScore(const RowSums& in, int u, int v, const RowShape& s, const LandmarkFinderOptions& o) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double hw = std::max(1.0, s.width / 2);
  const int probe = std::min(v, std::max(3, static_cast<int>(std::lround(s.probe))));  // what the frame holds of it
  const double reach = hw + o.side_px + std::abs(s.lean) * probe;
  if (u - reach < 0 || u + reach > in.width() || v + o.below_px > in.height() || probe < 3 ||
      probe < o.min_probe_in_frame * s.probe) {
    return -kInf;
  }
  double score = kInf, spread = 0;
  std::optional<RowSums::Stats> thirds[3];
  const double e = std::min(o.side_px, hw);  // the strips either side of each of its sides
  for (int k = 0; k < 3; ++k) {
    const int top = v - probe + k * probe / 3, bottom = k == 2 ? v : v - probe + (k + 1) * probe / 3;
    thirds[k] = in.strip(u - hw, u + hw, top, bottom, s.lean, v);
    score = std::min({score,
                      distance(in.strip(u - hw, u - hw + e, top, bottom, s.lean, v), in.strip(u - hw - o.side_px, u - hw, top, bottom, s.lean, v)),
                      distance(in.strip(u + hw - e, u + hw, top, bottom, s.lean, v), in.strip(u + hw, u + hw + o.side_px, top, bottom, s.lean, v))});
  }
  const int foot = std::max(2, probe / 6);
  score = std::min(score, distance(in.strip(u - hw, u + hw, v - foot, v, s.lean, v),
                                   in.strip(u - hw, u + hw, v, v + static_cast<int>(o.below_px), 0.0, v)));
  for (int a = 0; a < 3; ++a) {
    for (int b = a + 1; b < 3; ++b) spread = std::max(spread, distance(thirds[a], thirds[b]));
  }
  return score - spread;
}

// A flat landmark (a manhole cover) is found by its rim: the circle on the ground seen as an ellipse,
// with the colour just inside it against just outside at kRimPoints places round it. Offsets are
// from the projection of its centre, px; pixel centres at integers.
constexpr int kRimPoints = 32;
struct Rim {
  std::array<Vec2, kRimPoints> inner, outer;
};

// The rim of a cover of radius r centred on the ground at g, its samples step_px inside and outside.
std::optional<Rim> rimAt(const Camera& camera, const Vec2& g, double r, double step_px) {
  const auto c = camera.projectGround(g);
  if (!c) return std::nullopt;
  Rim rim;
  for (int k = 0; k < kRimPoints; ++k) {
    const Vec2 dir = unitVector(2 * kPi * k / kRimPoints);
    const auto p = camera.projectGround(g + r * dir), out = camera.projectGround(g + (r + 0.01) * dir);
    if (!p || !out || (*out - *p).norm() < 1e-9) return std::nullopt;
    const Vec2 n = (*out - *p).normalized();
    rim.inner[k] = *p - *c - step_px * n;
    rim.outer[k] = *p - *c + step_px * n;
  }
  return rim;
}

// The frame's colour at a point (pixel centres at integers), bilinear; the caller keeps it inside.
Vec3 colourAt(const VisionFrame& f, const Vec2& p) {
  const int u = static_cast<int>(std::floor(p.x())), v = static_cast<int>(std::floor(p.y()));
  const double a = p.x() - u, b = p.y() - v;
  const std::uint8_t* row0 = f.rgb + (static_cast<std::size_t>(v) * f.width + u) * 3;
  const std::uint8_t* row1 = row0 + static_cast<std::size_t>(f.width) * 3;
  Vec3 out;
  for (int ch = 0; ch < 3; ++ch) {
    out[ch] = (1 - b) * ((1 - a) * row0[ch] + a * row0[3 + ch]) + b * ((1 - a) * row1[ch] + a * row1[3 + ch]);
  }
  return out;
}

// How well a cover's rim placed about the centre q explains the frame: the colour step across it
// that all but the weakest fifth of the rim shows (a shadow's edge or a crack shows one only along
// part of it), levels; -infinity when the rim leaves the frame.
double rimScore(const VisionFrame& f, const Vec2& q, const Rim& rim) {
  std::array<double, kRimPoints> step{};
  for (int k = 0; k < kRimPoints; ++k) {
    const Vec2 a = q + rim.inner[k], b = q + rim.outer[k];
    if (std::min({a.x(), a.y(), b.x(), b.y()}) < 0 || std::max(a.x(), b.x()) > f.width - 1.001 ||
        std::max(a.y(), b.y()) > f.height - 1.001) {
      return -std::numeric_limits<double>::infinity();
    }
    step[k] = (colourAt(f, a) - colourAt(f, b)).norm();
  }
  std::nth_element(step.begin(), step.begin() + kRimPoints / 5, step.end());
  return step[kRimPoints / 5];
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
  const double row = std::isfinite(*top) ? v - reach - 1 + double(k) + parabolaPeak(step[k - 1], step[k], step[k + 1]) : double(v);
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

// The scores of the places searched about the predicted base (u0, v0): ±ru columns and ±rv rows,
// with a border of one more each way so that the best place's neighbours are known. NaN: not scored.
class SearchGrid {
 public:
  SearchGrid(int u0, int v0, int ru, int rv)
      : u0_(u0), v0_(v0), ru_(ru), rv_(rv), s_(static_cast<std::size_t>(2 * ru + 3) * (2 * rv + 3), kNaN) {}

  /// Scores the places with score(du, dv): every second one each way, then every one within 3 of
  /// the best three of those that lie more than 3 apart (a landmark's score falls by a third 1 px
  /// off its peak: the best of the coarse places can be a lesser peak, or one the frame's edge cuts).
  template <class Score>
  void fill(Score&& score) {
    std::vector<std::pair<double, Eigen::Vector2i>> coarse;
    for (int dv = -rv_ - 1; dv <= rv_ + 1; dv += 2) {
      for (int du = -ru_ - 1; du <= ru_ + 1; du += 2) {
        at(du, dv) = score(du, dv);
        if (std::abs(du) <= ru_ && std::abs(dv) <= rv_ && at(du, dv) > -kInf) coarse.emplace_back(at(du, dv), Eigen::Vector2i(du, dv));
      }
    }
    std::sort(coarse.begin(), coarse.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<Eigen::Vector2i> refined;
    for (const auto& [value, b] : coarse) {
      if (refined.size() == 3) break;
      if (std::any_of(refined.begin(), refined.end(), [&](const Eigen::Vector2i& r) { return (r - b).cwiseAbs().maxCoeff() <= 3; })) continue;
      refined.push_back(b);
      for (int dv = std::max(-rv_ - 1, b.y() - 3); dv <= std::min(rv_ + 1, b.y() + 3); ++dv) {
        for (int du = std::max(-ru_ - 1, b.x() - 3); du <= std::min(ru_ + 1, b.x() + 3); ++du) {
          if (std::isnan(at(du, dv))) at(du, dv) = score(du, dv);
        }
      }
    }
  }
  double& at(int du, int dv) { return s_[static_cast<std::size_t>(dv + rv_ + 1) * (2 * ru_ + 3) + (du + ru_ + 1)]; }
  int u0() const { return u0_; }
  int v0() const { return v0_; }
  int ru() const { return ru_; }
  int rv() const { return rv_; }

  /// The best place within the search (not its border), as (du, dv), and its score.
  std::pair<Eigen::Vector2i, double> best() {
    double best = -kInf;
    Eigen::Vector2i b(0, 0);
    for (int dv = -rv_; dv <= rv_; ++dv) {
      for (int du = -ru_; du <= ru_; ++du) {
        if (at(du, dv) > best) best = at(du, dv), b = Eigen::Vector2i(du, dv);
      }
    }
    return {b, best};
  }
  /// The best score more than clear_u columns or clear_v rows from (du, dv) within the search.
  double runnerUp(int du, int dv, int clear_u, int clear_v) {
    double best = -kInf;
    for (int j = -rv_; j <= rv_; ++j) {
      for (int i = -ru_; i <= ru_; ++i) {
        if ((std::abs(i - du) > clear_u || std::abs(j - dv) > clear_v) && at(i, j) > best) best = at(i, j);
      }
    }
    return best;
  }
  /// Whether every neighbour of (du, dv) could be scored: a peak, not the edge of what could be (the
  /// frame's border cutting it off there).
  bool peak(int du, int dv) {
    return std::isfinite(at(du - 1, dv)) && std::isfinite(at(du + 1, dv)) && std::isfinite(at(du, dv - 1)) &&
           std::isfinite(at(du, dv + 1));
  }

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  int u0_, v0_, ru_, rv_;
  std::vector<double> s_;
};

DetectedLandmark notFound(DetectedLandmark out, const char* reason) {
  out.reason = reason;
  return out;
}

// Something standing: its base's front edge searched for with uprightScore, then refined.
DetectedLandmark findUpright(const RowSums& sums, const Camera& camera, const PredictedLandmark& l, SearchGrid& grid,
                             const LandmarkFinderOptions& o, DetectedLandmark out) {
  std::vector<std::optional<RowShape>> shapes;  // each row's, by dv + rv + 1
  for (int dv = -grid.rv() - 1; dv <= grid.rv() + 1; ++dv) shapes.push_back(shapeAt(camera, l, grid.u0(), grid.v0() + dv, o.probe_height_m));
  grid.fill([&](int du, int dv) {
    const auto& shape = shapes[static_cast<std::size_t>(dv + grid.rv() + 1)];
    return shape ? uprightScore(sums, grid.u0() + du, grid.v0() + dv, *shape, o) : -std::numeric_limits<double>::infinity();
  });
  const auto [b, best] = grid.best();
  out.score = std::clamp(best / (2 * o.min_contrast), 0.0, 1.0);
  if (!(best >= o.min_contrast) || !grid.peak(b.x(), b.y())) {
    return notFound(out, "nothing standing out from the ground beside it near its prediction");
  }
  const int u = grid.u0() + b.x(), v = grid.v0() + b.y();
  const auto best_shape = shapeAt(camera, l, u, v, o.probe_height_m);
  if (!best_shape) return notFound(out, "its place found is not on the ground");
  const int clear_u = std::max(3, static_cast<int>(best_shape->width)), clear_v = std::max(3, static_cast<int>(best_shape->probe / 3));
  if (best < o.min_peak_ratio * grid.runnerUp(b.x(), b.y(), clear_u, clear_v)) {
    return notFound(out, "as much like it elsewhere near its prediction: ambiguous");
  }
  const Vec2 found(refinedMiddleColumn(sums, u, v, *best_shape), refinedBaseRow(sums, u, v, *best_shape));
  const auto shape = shapeAt(camera, l, found.x(), found.y(), o.probe_height_m);
  if (!shape) return notFound(out, "its place found is not on the ground");
  // The row found is its base's front edge: the centre is a radius further away.
  const Vec2 sight = (shape->ground - camera.center().head<2>()).normalized();
  const auto centre = camera.projectGround(shape->ground + sight * l.radius_m);
  if (!centre) return notFound(out, "its place found is not on the ground");
  out.found = true;
  out.image_base = *centre;
  const double su = std::hypot(o.base_sigma_u_px, 0.25 * shape->width);
  out.covariance = Vec2(su * su, o.base_sigma_v_px * o.base_sigma_v_px).asDiagonal();
  return out;
}

// A cover: the centre whose rim (rimAt) shows the strongest colour step all round. The search
// reuses the rim drawn at the middle of each block of 8 columns of a row (a cover seen from the side
// slants); the best place's neighbourhood is then scored again with each place's own rim.
DetectedLandmark findCover(const VisionFrame& f, const Camera& camera, const PredictedLandmark& l, SearchGrid& grid,
                           const LandmarkFinderOptions& o, DetectedLandmark out) {
  auto exactScore = [&](const Vec2& q) {
    const auto g = camera.backproject(q);
    const auto rim = g ? rimAt(camera, *g, l.radius_m, o.rim_step_px) : std::nullopt;
    return rim ? rimScore(f, q, *rim) : -std::numeric_limits<double>::infinity();
  };
  const int blocks = (2 * grid.ru() + 3 + 7) / 8;
  std::vector<std::optional<std::optional<Rim>>> rims(static_cast<std::size_t>(blocks) * (2 * grid.rv() + 3));
  grid.fill([&](int du, int dv) {
    const int block = (du + grid.ru() + 1) / 8;
    auto& rim = rims[static_cast<std::size_t>(dv + grid.rv() + 1) * blocks + block];
    if (!rim) {
      const auto g = camera.backproject(Vec2(grid.u0() - grid.ru() - 1 + 8 * block + 4, grid.v0() + dv));
      rim = g ? rimAt(camera, *g, l.radius_m, o.rim_step_px) : std::nullopt;
    }
    return *rim ? rimScore(f, Vec2(grid.u0() + du, grid.v0() + dv), **rim) : -std::numeric_limits<double>::infinity();
  });
  auto [b, best] = grid.best();
  for (int i = -1; i <= 1; ++i) {  // the neighbourhood with each place's own rim
    for (int j = -1; j <= 1; ++j) grid.at(b.x() + i, b.y() + j) = exactScore(Vec2(grid.u0() + b.x() + i, grid.v0() + b.y() + j));
  }
  best = grid.at(b.x(), b.y());
  out.score = std::clamp(best / (2 * o.min_contrast), 0.0, 1.0);
  if (!(best >= o.min_contrast) || !grid.peak(b.x(), b.y())) {
    return notFound(out, "no rim differing from the paving all round it near its prediction");
  }
  out.found = true;
  out.image_base = Vec2(grid.u0() + b.x() + parabolaPeak(grid.at(b.x() - 1, b.y()), best, grid.at(b.x() + 1, b.y())),
                        grid.v0() + b.y() + parabolaPeak(grid.at(b.x(), b.y() - 1), best, grid.at(b.x(), b.y() + 1)));
  out.covariance = Vec2(o.base_sigma_u_px * o.base_sigma_u_px, o.base_sigma_v_px * o.base_sigma_v_px).asDiagonal();
  return out;
}

DetectedLandmark findOne(const VisionFrame& f, const RowSums& sums, const PredictedLandmark& l, const Mat3& pose_covariance,
                         const LandmarkFinderOptions& o) {
  DetectedLandmark out;
  out.id = l.id;
  const Camera& camera = *f.camera;
  const Vec2 sigma = basePixelSigma(camera, l, pose_covariance);
  const int ru = static_cast<int>(std::ceil(std::clamp(o.gate_sigma * sigma.x(), o.min_search_px, o.max_search_px)));
  const int rv = static_cast<int>(std::ceil(std::clamp(o.gate_sigma * sigma.y(), o.min_search_px, o.max_search_px)));
  SearchGrid grid(static_cast<int>(std::lround(l.image_base.x())), static_cast<int>(std::lround(l.image_base.y())), ru, rv);
  if (l.height_m <= 0) return findCover(f, camera, l, grid, o, out);
  return findUpright(sums, camera, l, grid, o, out);
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
    out.push_back(findOne(frame, sums, l, prediction.pose_covariance, options));
  }
  return out;
}

}  // namespace mapnav
