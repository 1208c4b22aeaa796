// The cluster-perceptron's Hough (Jochem & Baluja 1993 §5): on the grid of a frame's block sums of
// road certainty (classifyFrame(), cluster_perceptron_classify.cpp), every road row's summation
// kernel, the coarse search over (top-row intercept × angle × curvature step) in exact integers and
// its sub-block refinement; houghCentre() hands find() the centre model it starts the edge
// refinement from. Free functions on explicit inputs: no member of ClusterPerceptron is here. See
// cluster_perceptron.h.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "cluster_perceptron_internal.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav {

namespace {

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

/// The window of a prior centre line (an image line) for `model`'s top and bottom road rows.
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

}  // namespace

HoughAnswer houghCentre(const std::vector<std::uint32_t>& bsum, const std::vector<double>& row_widths,
                        const RowGeometry& rows, int width, int height, const ClusterPerceptronOptions& opt,
                        const std::optional<Segment2>& prior) {
  HoughAnswer ans;
  const int bs = opt.block_size;
  HoughGrid grid = houghGrid(bsum, row_widths, width, height, bs);
  if (grid.rr.size() < 2) return ans.fails("the bootstrap road outline has fewer than 2 block rows");
  double max_possible = 0;
  const std::vector<std::int32_t> S = kernelSums(grid, max_possible);
  // Continuous block coordinate X ↔ pixel u = X · bs − 0.5; rows at their block centres.
  CentreModel& model = ans.model;
  model.v0 = grid.rr.front() * bs + (bs - 1) / 2.0;
  model.v1 = std::max(model.v0 + 1.0, grid.rr.back() * bs + (bs - 1) / 2.0);
  const bool arc = opt.road_model == RoadModel::Arc;
  const int Q = arc ? opt.curvature_steps : 0;
  const double dk = opt.max_curvature / opt.curvature_steps;  // curvature per step, 1/m
  if (arc) {
    if (const char* why = setArcBasis(grid, model, rows.x, rows.b, height, dk)) return ans.fails(why);
  }
  ans.window = priorWindow(prior, opt.prior_px, model);
  const int M = std::min(opt.max_shift_blocks, 2 * grid.cols);
  const HoughPeak peak = coarseHough(grid, S, M, Q, ans.window);
  if (peak.sum == std::numeric_limits<std::int64_t>::min()) return ans.fails("no centre line within prior_px of the prior");
  ans.intercept_col = peak.x;
  ans.shift = peak.shift - M;
  const Vec3 f = refineSubBlock(grid, Vec3(peak.x + 0.5, peak.shift - M, peak.bend - Q), Q > 0, ans.window);
  model.p = Vec3(f[0] * bs - 0.5, f[1] * bs, arc ? f[2] * dk : 0.0);
  ans.confidence = std::clamp(static_cast<double>(peak.sum) / 1024.0 / std::max(1.0, max_possible), 0.0, 1.0);
  ans.v_top = grid.rr.front() * bs;
  return ans;
}

}  // namespace mapnav
