// The cluster-perceptron's runtime (Jochem & Baluja 1993 §5-6): every pixel classified and its road
// certainty summed per block (classifyFrame(), cluster_perceptron_classify.cpp), then the Hough over
// (top-row intercept × angle × curvature step) with its sub-block refinement; then find() hands the
// centre model to the edge refinement (cluster_perceptron_edges.cpp, cluster_perceptron_arc.cpp).
// The Hough's hot loop (houghSearch) stays in this file with find(). See cluster_perceptron.h.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cluster_perceptron_internal.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav {

namespace {

/// Per-thread scratch of find(), reused from frame to frame so that a frame costs no allocation.
FrameScratch& scratch() {
  thread_local FrameScratch s;
  return s;
}

/// Round half away from zero, without libm's call (|x| < 2³¹).
inline std::int32_t roundToInt(double x) {
  return x >= 0 ? static_cast<std::int32_t>(x + 0.5) : -static_cast<std::int32_t>(-x + 0.5);
}

struct HoughPeak {
  std::int64_t sum = std::numeric_limits<std::int64_t>::min();
  int x = 0, shift = 0, bend = 0;
};

/// The Hough's accumulation (§5): for every bend q and shift s, row i of the kernel sums `S`
/// (`rows` × 3·cols, column c of the image at index cols + c) moved by offsets[(q·shifts + s)·rows + i]
/// blocks and summed column by column; the largest column sum over the columns x_lo[s]..x_hi[s],
/// first in (q, s, x) order (none: sum stays the lowest int64). Exact integer arithmetic; built for
/// AVX2 too where the processor has it.
__attribute__((target_clones("avx2", "default"))) HoughPeak houghSearch(const std::int32_t* S, int rows, int cols,
                                                                         const int* offsets, int shifts, int bends,
                                                                         const int* x_lo, const int* x_hi) {
  HoughPeak best;
  const int ext = 3 * cols;
  std::vector<std::int32_t> acc(static_cast<std::size_t>(cols));
  for (int q = 0; q < bends; ++q)
    for (int s = 0; s < shifts; ++s) {
      if (x_lo[s] > x_hi[s]) continue;
      std::fill(acc.begin(), acc.end(), 0);
      const int* off = offsets + (static_cast<std::size_t>(q) * shifts + s) * rows;
      for (int i = 0; i < rows; ++i) {
        const std::int32_t* __restrict srow = S + static_cast<std::size_t>(i) * ext + cols + off[i];
        const int x0 = std::max(0, -cols - off[i]), x1 = std::min(cols, 2 * cols - off[i]);
        std::int32_t* __restrict a = acc.data();
        for (int x = x0; x < x1; ++x) a[x] += srow[x];
      }
      for (int x = x_lo[s]; x <= x_hi[s]; ++x)
        if (acc[x] > best.sum) best = {acc[x], x, s, q};
    }
  return best;
}

/// The road mask of the certainties: 255 where the certainty is above 127.
Image roadMask(const std::vector<std::uint8_t>& cert, int width, int height) {
  Image mask(width, height, 1);
  for (std::size_t i = 0; i < cert.size(); ++i) mask.data[i] = cert[i] > 127 ? 255 : 0;
  return mask;
}

/// One frame's Hough problem (§5) on the grid of blocks (`bs` pixels square, `cols` × `rows`).
struct HoughGrid {
  int bs = 0, cols = 0, rows = 0;
  std::vector<double> sc;  // per block: signed certainty, -127.5..+127.5
  std::vector<double> wb;  // per block row: the bootstrap's road width, blocks
  std::vector<int> rr;     // the road block rows (at least a block wide), top to bottom
  std::vector<double> tr;  // per road row: t, from 0 on the top road row to 1 on the bottom one
  std::vector<double> gb;  // per road row: the arc's offset per curvature step, blocks (0: the line)
};

/// The grid of a frame's block sums: signed certainties, and the road rows with their widths.
HoughGrid houghGrid(const std::vector<std::uint32_t>& bsum, const std::vector<double>& row_widths, int width,
                    int height, int bs) {
  HoughGrid g;
  g.bs = bs;
  const int cols = g.cols = (width + bs - 1) / bs, rows = g.rows = (height + bs - 1) / bs;
  // Signed certainty per block: -127.5..+127.5.
  g.sc.assign(bsum.size(), 0.0);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int npx = (std::min(width, (c + 1) * bs) - c * bs) * (std::min(height, (r + 1) * bs) - r * bs);
      g.sc[static_cast<std::size_t>(r) * cols + c] =
          static_cast<double>(bsum[static_cast<std::size_t>(r) * cols + c]) / (npx * static_cast<double>(kCertaintyMax)) * 255.0 - 127.5;
    }
  // Road rows and their widths in blocks.
  g.wb.assign(rows, 0.0);
  for (int r = 0; r < rows; ++r) {
    const int vc = std::min(height - 1, r * bs + bs / 2);
    g.wb[r] = row_widths[vc] / bs;
    if (g.wb[r] >= 1.0) g.rr.push_back(r);
  }
  if (g.rr.size() < 2) return g;
  const int r0 = g.rr.front(), rl = g.rr.back();
  const double span = std::max(1, rl - r0);
  g.tr.resize(g.rr.size());
  for (std::size_t i = 0; i < g.rr.size(); ++i) g.tr[i] = (g.rr[i] - r0) / span;
  g.gb.assign(g.rr.size(), 0.0);
  return g;
}

/// Per-row horizontal summation kernel over an extended column range [-cols, 2 cols), in fixed
/// point (1/1024) so that the Hough's sums are exact integers, in any order, and vectorise; and the
/// largest sum a centre line can reach (`max_possible`).
std::vector<std::int32_t> kernelSums(const HoughGrid& g, double& max_possible) {
  const int cols = g.cols, ext = 3 * cols;
  std::vector<std::int32_t> S(g.rr.size() * ext, 0);
  std::vector<double> prefix(static_cast<std::size_t>(cols) + 1);
  max_possible = 0;
  for (std::size_t i = 0; i < g.rr.size(); ++i) {
    const int r = g.rr[i];
    prefix[0] = 0;
    for (int c = 0; c < cols; ++c) prefix[c + 1] = prefix[c] + g.sc[static_cast<std::size_t>(r) * cols + c];
    const int k = std::max(1, static_cast<int>(std::lround(g.wb[r])));
    max_possible += 127.5 * std::min(k, cols) / k;
    for (int x = 0; x < ext; ++x) {
      const int centre = x - cols;
      const int lo = std::clamp(centre - k / 2, 0, cols), hi = std::clamp(centre - k / 2 + k, 0, cols);
      // Rows weigh the same. A kernel wholly off the image sums 0 (two thirds of the range): no division.
      S[i * ext + x] = lo == hi ? 0 : roundToInt((prefix[hi] - prefix[lo]) / k * 1024.0);
    }
  }
  return S;
}

/// The arc model's basis on the model's rows (its offset per unit curvature) and the road rows' offset
/// per curvature step `dk` (1/m); the reason when the camera does not fit the frame, else nothing.
const char* setArcBasis(HoughGrid& g, CentreModel& model, const std::vector<double>& row_x,
                        const std::vector<double>& row_b, int height, double dk) {
  if (static_cast<int>(row_x.size()) != height) return "the arc model needs the camera (setCamera) of the frame's size";
  const int bs = g.bs;
  model.arc = ArcBasis(row_x, row_b, model.v0, model.v1);
  for (std::size_t i = 0; i < g.rr.size(); ++i) g.gb[i] = dk * model.arc(g.rr[i] * bs + (bs - 1) / 2.0) / bs;
  for (int v = g.rr.front() * bs; v < height; ++v)
    if (!std::isfinite(row_x[v]) || !std::isfinite(row_b[v])) return "arc model: the road rows reach the horizon";
  return nullptr;
}

/// The prior's window (ClusterPerceptronOptions::prior_px): the centre line's columns on the top and
/// the bottom road rows (v0, v1; the arc's offset vanishes on both, so bends do not move them) within
/// prior_px of the prior's. Without a prior (or with prior_px 0) every centre line is in it.
struct PriorWindow {
  bool windowed = false;
  double top = 0, bottom = 0, px = 0;
  bool admits(double u_top, double u_bottom) const {
    return !windowed || (std::abs(u_top - top) <= px && std::abs(u_bottom - bottom) <= px);
  }
};

PriorWindow priorWindow(const std::optional<Segment2>& prior, double prior_px, const CentreModel& model) {
  PriorWindow w;
  w.windowed = prior && prior_px > 0 && std::abs(prior->b.y() - prior->a.y()) > 1e-6;
  w.px = prior_px;
  if (w.windowed) {
    const auto at = [&](double v) {
      return prior->a.x() + (prior->b.x() - prior->a.x()) * (v - prior->a.y()) / (prior->b.y() - prior->a.y());
    };
    w.top = at(model.v0);
    w.bottom = at(model.v1);
  }
  return w;
}

/// The coarse Hough (§5): road row i (t_i from 0 at the top road row to 1 at the bottom one) is
/// shifted by round(s·t_i + q·g_i) blocks and the columns summed: s in [−M, M] the bottom row's shift
/// (the line's angle), q in [−Q, Q] the curvature's step (the arc model, g_i the row's arc offset per
/// step; Q = 0 for the paper's straight trapezoid). Only lines in the prior's window count.
HoughPeak coarseHough(const HoughGrid& g, const std::vector<std::int32_t>& S, int M, int Q, const PriorWindow& window) {
  const int cols = g.cols, bs = g.bs;
  std::vector<int> offsets(g.rr.size() * static_cast<std::size_t>(2 * M + 1) * (2 * Q + 1));
  for (int q = -Q, j = 0; q <= Q; ++q)
    for (int s = -M; s <= M; ++s)
      for (std::size_t i = 0; i < g.rr.size(); ++i, ++j)
        offsets[j] = roundToInt(s * g.tr[i] + q * g.gb[i]);
  // Block coordinate X (continuous) ↔ column X · bs − 0.5; the coarse Hough's line has X = x + 0.5 on
  // the top road row and x + 0.5 + s on the bottom one.
  std::vector<int> x_lo(2 * M + 1, 0), x_hi(2 * M + 1, cols - 1);
  if (window.windowed) {
    const double reach = window.px / bs, top = (window.top + 0.5) / bs - 0.5, bottom = (window.bottom + 0.5) / bs - 0.5;
    for (int s = -M; s <= M; ++s) {
      x_lo[s + M] = std::max({0, static_cast<int>(std::ceil(top - reach)), static_cast<int>(std::ceil(bottom - s - reach))});
      x_hi[s + M] = std::min({cols - 1, static_cast<int>(std::floor(top + reach)), static_cast<int>(std::floor(bottom - s + reach))});
    }
  }
  return houghSearch(S.data(), static_cast<int>(g.rr.size()), cols, offsets.data(), 2 * M + 1, 2 * Q + 1, x_lo.data(),
                     x_hi.data());
}

/// Sub-block refinement: the same Hough sum, with each block's certainty spread evenly over its width
/// and the kernel exactly the row's road width, evaluated at fractional intercepts, shifts (and, with
/// `bends`, curvature steps) around the coarse maximum `f` (X, shift, step), coarse to fine. The
/// continuous kernel sum is P(x + W/2) − P(x − W/2), P the running integral of the row.
Vec3 refineSubBlock(const HoughGrid& grid, Vec3 f, bool bends, const PriorWindow& window) {
  const int cols = grid.cols, bs = grid.bs;
  const std::vector<int>& rr = grid.rr;
  std::vector<double> P(rr.size() * (static_cast<std::size_t>(cols) + 1), 0.0);
  for (std::size_t i = 0; i < rr.size(); ++i) {
    const double* row = grid.sc.data() + static_cast<std::size_t>(rr[i]) * cols;
    double* pr = P.data() + i * (cols + 1);
    for (int c = 0; c < cols; ++c) pr[c + 1] = pr[c] + row[c];
  }
  auto integral = [&](std::size_t i, double x) {
    const double* pr = P.data() + i * (cols + 1);
    if (x <= 0) return 0.0;
    if (x >= cols) return pr[cols];
    const int c = static_cast<int>(x);
    return pr[c] + (x - c) * (pr[c + 1] - pr[c]);
  };
  auto score = [&](double X, double sft, double bend) {
    double total = 0;
    for (std::size_t i = 0; i < rr.size(); ++i) {
      const double x = X + sft * grid.tr[i] + bend * grid.gb[i], hw = 0.5 * grid.wb[rr[i]];
      total += (integral(i, x + hw) - integral(i, x - hw)) / (2.0 * hw);
    }
    return total;
  };
  // Pattern search: move to the best of the ± step neighbours in each parameter until none is
  // better, then halve the step (0.5 → 0.25 → 0.125 blocks).
  double fbest = score(f[0], f[1], f[2]);
  for (double step = 0.5; step >= 0.125; step /= 2) {
    for (int moves = 0; moves < 32; ++moves) {
      Vec3 next = f;
      for (int d = 0; d < (bends ? 3 : 2); ++d)
        for (const double sign : {-1.0, 1.0}) {
          Vec3 g = f;
          g[d] += sign * step;
          if (!window.admits(g[0] * bs - 0.5, (g[0] + g[1]) * bs - 0.5)) continue;
          const double val = score(g[0], g[1], g[2]);
          if (val > fbest) {
            fbest = val;
            next = g;
          }
        }
      if (next == f) break;
      f = next;
    }
  }
  return f;
}

/// The centre line sampled every block row from v_top down to the bottom row: the image model's, or
/// the arc model's ground circle taken to the image where it has not turned back.
std::vector<Vec2> centreCurve(const CentreModel& model, const std::optional<GroundArc>& ground, const RowGeometry& rows,
                              int v_top, int height, int bs) {
  std::vector<Vec2> curve;
  for (int v = v_top;; v = std::min(height - 1, v + bs)) {
    if (!ground) {
      curve.emplace_back(model.u(v), v);
    } else if (const double y = ground->at(rows.x[v]); std::isfinite(y)) {
      curve.emplace_back(rows.a[v] + rows.b[v] * y, v);
    }
    if (v >= height - 1) break;
  }
  return curve;
}

RoadFinding failed(RoadFinding res, const char* reason) {
  res.reason = reason;
  return res;
}

}  // namespace

RoadFinding ClusterPerceptron::find(const std::uint8_t* rgb, int width, int height, bool want_mask,
                                    const std::optional<Segment2>& prior) const {
  RoadFinding res;
  if (!trained_) return failed(std::move(res), "not trained");
  if (static_cast<int>(row_widths_.size()) != height)
    return failed(std::move(res), "frame height differs from the bootstrap frame's");
  // §6: every pixel's road certainty, summed per block.
  FrameScratch& scr = scratch();
  const long long road_px =
      classifyFrame(*this, LutView{lut_.data(), sub_offset_.data(), sub_.data()}, rgb, width, height, scr);
  if (want_mask) {
    res.mask = roadMask(scr.cert, width, height);
    res.certainty = Image(width, height, 1);
    std::copy(scr.cert.begin(), scr.cert.end(), res.certainty.data.begin());
  }
  if (static_cast<double>(road_px) < opt_.min_road_fraction * width * height)
    return failed(std::move(res), "no road-coloured pixels");
  // §5: the Hough over the road block rows.
  const int bs = opt_.block_size;
  HoughGrid grid = houghGrid(scr.bsum, row_widths_, width, height, bs);
  if (grid.rr.size() < 2) return failed(std::move(res), "the bootstrap road outline has fewer than 2 block rows");
  double max_possible = 0;
  const std::vector<std::int32_t> S = kernelSums(grid, max_possible);
  // Continuous block coordinate X ↔ pixel u = X · bs − 0.5; rows at their block centres.
  CentreModel model;
  model.v0 = grid.rr.front() * bs + (bs - 1) / 2.0;
  model.v1 = std::max(model.v0 + 1.0, grid.rr.back() * bs + (bs - 1) / 2.0);
  const bool arc = opt_.road_model == RoadModel::Arc;
  const int Q = arc ? opt_.curvature_steps : 0;
  const double dk = opt_.max_curvature / opt_.curvature_steps;  // curvature per step, 1/m
  if (arc) {
    if (const char* why = setArcBasis(grid, model, row_x_, row_b_, height, dk)) return failed(std::move(res), why);
  }
  const PriorWindow window = priorWindow(prior, opt_.prior_px, model);
  const int M = std::min(opt_.max_shift_blocks, 2 * grid.cols);
  const HoughPeak peak = coarseHough(grid, S, M, Q, window);
  if (peak.sum == std::numeric_limits<std::int64_t>::min())
    return failed(std::move(res), "no centre line within prior_px of the prior");
  res.intercept_col = peak.x;
  res.shift = peak.shift - M;
  const Vec3 f = refineSubBlock(grid, Vec3(peak.x + 0.5, peak.shift - M, peak.bend - Q), Q > 0, window);
  model.p = Vec3(f[0] * bs - 0.5, f[1] * bs, arc ? f[2] * dk : 0.0);
  res.confidence = std::clamp(static_cast<double>(peak.sum) / 1024.0 / std::max(1.0, max_possible), 0.0, 1.0);

  // Beyond the paper: the Hough answer is good to about a block; the road's edges put it to the pixel
  // (the image model, or the arc model's circle on the ground).
  const int v_top = grid.rr.front() * bs;
  const RowGeometry geo{row_x_, row_a_, row_b_};
  std::optional<GroundArc> ground;
  if (opt_.refine_edges) {
    const int degree = Q > 0 ? 2 : 1;
    model = edgeConsensusModel(scr.cert.data(), width, height, v_top, row_widths_, model, degree, opt_,
                               [&](const CentreModel& m) { return window.admits(m.u(m.v0), m.u(m.v1)); });
    if (arc) ground = refineOnGround(scr.cert.data(), rgb, width, height, v_top, model, geo, row_widths_, opt_, carried_, res);
    if (!ground) fitModelToEdges(scr.cert.data(), width, height, v_top, row_widths_, degree, opt_.max_curvature, model, res);
  }
  // No ground fit: the image fit stands, unless its centre line, taken to the ground, leaves the
  // vehicle off the road: then the road-coloured area holds no road the vehicle could be on
  // (shoulders classed as road, no edge of the road in view), and the frame fails rather than steer by it.
  if (arc && !ground && leavesTheVehicleOffRoad(model, geo, row_widths_, v_top, height, opt_.max_curvature))
    return failed(std::move(res), "arc model: no centre line within half the road's width of the vehicle");
  res.centerline_curve = centreCurve(model, ground, geo, v_top, height, bs);
  if (res.centerline_curve.size() < 2) return failed(std::move(res), "arc model: the circle turns back above the bottom rows");
  res.centerline_image = Segment2{res.centerline_curve.front(), res.centerline_curve.back()};
  res.curvature = ground ? ground->k : arc ? model.p[2] : 0.0;
  res.ok = true;
  return res;
}

}  // namespace mapnav
