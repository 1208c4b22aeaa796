#include "mapnav/localization/relocalize.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/localization/pose_filter.h"

namespace mapnav {

const OptionTable<RelocalizeOptions>& relocalizeOptionTable() {
  using O = RelocalizeOptions;
  static const OptionTable<O> table =
      OptionTable<O>("RelocalizeOptions")
          .field("search_below", &O::search_below, inRange(0, 1),
                 "search when the detected region agrees with the prediction by less than this IoU (0: never)")
          .field("max_area_ratio", &O::max_area_ratio, atLeast(1),
                 "... and its area is within this ratio of the predicted paved area's, either way")
          .field("along_m", &O::along_m, atLeast(0), "hypotheses up to this far along the estimate's heading, m")
          .field("across_m", &O::across_m, atLeast(0), "... and across it, m")
          .field("step_m", &O::step_m, above(0), "... in steps of this, m")
          .field("heading_deg", &O::heading_deg, atLeast(0), "... turned by up to this, degrees")
          .field("heading_step_deg", &O::heading_step_deg, above(0), "... in steps of this, degrees")
          .field("min_agreement", &O::min_agreement, aboveUpTo(0, 1), "the winner's IoU at least")
          .field("min_gain", &O::min_gain, aboveUpTo(0, 1), "the winner's IoU above the estimate's by at least")
          .field("tie", &O::tie, inRange(0, 0.999999), "hypotheses within this IoU of the best tie with it")
          .field("max_across_sigma_m", &O::max_across_sigma_m, above(0),
                 "the ties spread across the road by at most this (1-sigma, m) for a clear winner")
          .field("max_heading_sigma_deg", &O::max_heading_sigma_deg, above(0),
                 "... and in heading by at most this (1-sigma, degrees)")
          .field("max_lost_frames", &O::max_lost_frames, atLeast(1),
                 "the Map stands at most this many frames for a winner to be confirmed, then gives up")
          .field("cell_m", &O::cell_m, above(0), "the ground grid's cell, m");
  return table;
}

namespace {

/// Cells of a grid on the ground (vehicle frame) over a box, each set when its centre is inside.
class GroundGrid {
 public:
  GroundGrid(const Polygon2& footprint, double cell) : cell_(cell) {
    Vec2 lo = footprint.front(), hi = footprint.front();
    for (const Vec2& p : footprint) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    origin_ = lo;
    cols_ = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / cell)));
    rows_ = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / cell)));
  }
  std::vector<std::uint8_t> empty() const { return std::vector<std::uint8_t>(static_cast<std::size_t>(rows_) * cols_, 0); }

  /// Sets the cells whose centres `ring` holds (even-odd: a ring that crosses itself counts its
  /// overlaps out), by scan lines: each row's crossings sorted and filled between pairs.
  void fill(const Polygon2& ring, std::vector<std::uint8_t>& cells) const {
    if (ring.size() < 3) return;
    std::vector<double> xs;
    for (int r = 0; r < rows_; ++r) {
      const double y = origin_.y() + (r + 0.5) * cell_;
      xs.clear();
      for (std::size_t i = 0; i < ring.size(); ++i) {
        const Vec2& a = ring[i];
        const Vec2& b = ring[(i + 1) % ring.size()];
        if ((a.y() <= y) == (b.y() <= y)) continue;  // half-open: a vertex on the line counts once
        xs.push_back(a.x() + (y - a.y()) / (b.y() - a.y()) * (b.x() - a.x()));
      }
      std::sort(xs.begin(), xs.end());
      std::uint8_t* row = cells.data() + static_cast<std::size_t>(r) * cols_;
      for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
        // Cells whose centre x0 + (c + 0.5) cell lies in [xs[k], xs[k + 1]), clamped to the grid
        // before the conversion (a region's far vertices back-projected near the horizon lie km away).
        const auto column = [&](double x) {
          return static_cast<int>(std::clamp(std::ceil((x - origin_.x()) / cell_ - 0.5), 0.0, double(cols_)));
        };
        const int c0 = column(xs[k]), c1 = column(xs[k + 1]);
        for (int c = c0; c < c1; ++c) row[c] ^= 1;
      }
    }
  }

 private:
  double cell_;
  Vec2 origin_;
  int cols_ = 0, rows_ = 0;
};

/// The cells of the view's paved area (every region's rings, OR-ed).
std::vector<std::uint8_t> pavedCells(const GroundGrid& grid, const PredictedObject& view) {
  std::vector<std::uint8_t> paved = grid.empty();
  std::vector<std::uint8_t> ring = grid.empty();
  for (const PredictedRegion& region : view.regions) {
    for (const Polygon2& p : region.vehicle) {
      std::fill(ring.begin(), ring.end(), 0);
      grid.fill(p, ring);
      for (std::size_t i = 0; i < paved.size(); ++i) paved[i] |= ring[i];
    }
  }
  return paved;
}

/// The detected cells `a` against the paved cells `b`, within `within`.
RegionAgreement compare(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                        const std::vector<std::uint8_t>& within) {
  std::size_t both = 0, either = 0, na = 0, nb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    both += a[i] & b[i] & within[i];
    either += (a[i] | b[i]) & within[i];
    na += a[i] & within[i];
    nb += b[i] & within[i];
  }
  RegionAgreement out;
  if (either > 0 && na > 0 && nb > 0) out.iou = static_cast<double>(both) / static_cast<double>(either);
  if (nb > 0) out.area_ratio = static_cast<double>(na) / static_cast<double>(nb);
  return out;
}

/// The detected region and the footprint on the footprint's grid.
struct Scene {
  GroundGrid grid;
  std::vector<std::uint8_t> footprint, detected;
  Scene(const Polygon2& fp, const Polygon2& region, double cell) : grid(fp, cell) {
    footprint = grid.empty();
    grid.fill(fp, footprint);
    detected = grid.empty();
    grid.fill(region, detected);
  }
  RegionAgreement agreement(const PredictedObject& view) const {
    return compare(detected, pavedCells(grid, view), footprint);
  }
};

/// -n, ..., n steps of `step` covering +-range.
std::vector<double> steps(double range, double step) {
  const int n = static_cast<int>(std::floor(range / step + 1e-9));
  std::vector<double> out;
  for (int k = -n; k <= n; ++k) out.push_back(k * step);
  return out;
}

}  // namespace

void RelocalizeOptions::validate() const { relocalizeOptionTable().validate(*this); }

RegionAgreement regionAgreement(const PredictedObject& view, const Polygon2& detected, double cell_m) {
  if (view.footprint.size() < 3 || detected.size() < 3 || !(cell_m > 0)) return {};
  return Scene(view.footprint, detected, cell_m).agreement(view);
}

RelocalizeResult relocalize(ViewPredictor& predictor, const Camera& camera, const Pose2& estimate,
                            const Polygon2& detected, const RelocalizeOptions& options) {
  options.validate();
  RelocalizeResult out;
  out.pose = estimate;
  const Prediction here = predictor.predict(estimate, camera);
  if (here.view.footprint.size() < 3 || detected.size() < 3) {
    out.reason = "nothing to compare: no view footprint or no detected region";
    return out;
  }
  const Scene scene(here.view.footprint, detected, options.cell_m);
  out.estimate = scene.agreement(here.view);
  struct Hypothesis {
    Vec3 offset;  // along, across (m), heading (rad) in the estimate's axes
    double iou;
  };
  std::vector<Hypothesis> tried;
  const Mat2 axes = estimate.rotation();
  for (const double dh : steps(degToRad(options.heading_deg), degToRad(options.heading_step_deg)))
    for (const double da : steps(options.along_m, options.step_m))
      for (const double dc : steps(options.across_m, options.step_m)) {
        const Pose2 h(estimate.translation() + axes * Vec2(da, dc), estimate.heading() + dh);
        tried.push_back({Vec3(da, dc, dh), scene.agreement(predictor.predict(h, camera).view).iou});
      }
  out.hypotheses = tried.size();
  for (const Hypothesis& h : tried) out.best = std::max(out.best, h.iou);
  // The ties: their mean is the pose, their spread (and the grid's resolution) the covariance.
  Vec3 mean = Vec3::Zero();
  for (const Hypothesis& h : tried)
    if (h.iou >= out.best - options.tie) mean += h.offset, ++out.ties;
  mean /= static_cast<double>(out.ties);
  Mat3 cov = Mat3::Zero();
  for (const Hypothesis& h : tried)
    if (h.iou >= out.best - options.tie) cov += (h.offset - mean) * (h.offset - mean).transpose();
  cov /= static_cast<double>(out.ties);
  const double s = options.step_m, r = degToRad(options.heading_step_deg);
  cov += Vec3(s * s / 12, s * s / 12, r * r / 12).asDiagonal();  // a uniform cell's variance
  out.spread = cov.diagonal().cwiseSqrt();
  out.covariance = rotatePoseCovariance(cov, axes);  // the estimate's axes onto the world's
  out.pose = Pose2(estimate.translation() + axes * mean.head<2>(), estimate.heading() + mean.z());
  std::string found = strprintf(
      "best IoU %.2f against the estimate's %.2f over %zu hypotheses; %zu tie, their mean %+.2f m along, %+.2f m "
      "across, %+.1f deg, 1-sigma %.2f m along, %.2f m across, %.1f deg",
      out.best, out.estimate.iou, out.hypotheses, out.ties, mean.x(), mean.y(), radToDeg(mean.z()), out.spread.x(),
      out.spread.y(), radToDeg(out.spread.z()));
  found += strprintf(" (the region's area %.2f times the predicted paved area's)", out.estimate.area_ratio);
  if (!out.estimate.roadSized(options.max_area_ratio)) {
    out.reason = found + ": the region is not the road's size, Vision's error (max_area_ratio " +
                 strprintf("%g", options.max_area_ratio) + ")";
  } else if (out.best < options.min_agreement) {
    out.reason = found + ": nothing explains the region (min_agreement " + strprintf("%g", options.min_agreement) + ")";
  } else if (out.best - out.estimate.iou < options.min_gain) {
    out.reason = found + ": the estimate explains it about as well";
  } else if (out.spread.y() > options.max_across_sigma_m || out.spread.z() > degToRad(options.max_heading_sigma_deg)) {
    out.reason = found + ": no clear winner across the road or in heading";
  } else {
    out.clear = true;
    out.reason = found;
  }
  return out;
}

}  // namespace mapnav
