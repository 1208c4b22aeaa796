// The cluster-perceptron's arc model on the ground (beyond the paper, §9): the camera's row geometry,
// the road's edges taken to the ground (placed within their pixel pair by colour where asked), the
// circle fitted to them (a consensus of exact circles, then robust Gauss-Newton; the line where the
// curvature does not pay). Free functions on explicit inputs; ClusterPerceptron::setCamera() and
// advance(), which keep the tables and the carried edges, are in cluster_perceptron_runtime.cpp. See
// cluster_perceptron.h.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "cluster_perceptron_internal.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav {

RowTables rowTablesOf(const Camera& camera) {
  // Pin-hole, tilt only: the ground point (x, y) is at depth Z = (x − cx)·cos φ + h·sin φ and height
  // Y = −(x − cx)·sin φ + h·cos φ in the camera frame, so its row v = v_c + f·Y/Z depends on x alone,
  // and its column u = u_c − f·(y − cy)/Z is affine in y at that row: b_r = −f/Z.
  const int h = camera.height();
  RowTables t;
  t.x.assign(static_cast<std::size_t>(h), std::nan(""));
  t.a.assign(static_cast<std::size_t>(h), std::nan(""));
  t.b.assign(static_cast<std::size_t>(h), std::nan(""));
  for (int v = 0; v < h; ++v) {
    const auto g = camera.backproject(Vec2(camera.intrinsics().cx, v));
    if (!g) continue;
    const auto p0 = camera.projectGround(Vec2(g->x(), 0.0)), p1 = camera.projectGround(Vec2(g->x(), 1.0));
    if (!p0 || !p1) continue;
    t.x[v] = g->x();
    t.a[v] = p0->x();
    t.b[v] = p1->x() - p0->x();
  }
  return t;
}

namespace {

/// The column of the edge of a candidate (`u` the first pixel of the class that begins, the boundary
/// u − 0.5) within the pair of pixels u − 1, u by their colours (ClusterPerceptronOptions::
/// subpixel_edges): the class that begins fills [x, u + 0.5] of the pair, x = u + 0.5 − Σ share, each
/// pixel's share its place, clamped to [0, 1], on the colour line from the ending class's pure pixels
/// (u − 3, u − 2) to the beginning class's (u + 1, u + 2). The boundary where their colours differ by
/// under 16 levels. `u` is in [3, width − 3], as rowCandidates() gives it.
double subpixelEdge(const std::uint8_t* row_rgb, int u) {
  double from[3], to[3], d2 = 0;
  for (int c = 0; c < 3; ++c) {
    from[c] = 0.5 * (row_rgb[3 * (u - 3) + c] + row_rgb[3 * (u - 2) + c]);
    to[c] = 0.5 * (row_rgb[3 * (u + 1) + c] + row_rgb[3 * (u + 2) + c]);
    d2 += (to[c] - from[c]) * (to[c] - from[c]);
  }
  if (d2 < 16.0 * 16.0) return u - 0.5;
  double share = 0;
  for (const int k : {u - 1, u}) {
    double dot = 0;
    for (int c = 0; c < 3; ++c) dot += (row_rgb[3 * k + c] - from[c]) * (to[c] - from[c]);
    share += std::clamp(dot / d2, 0.0, 1.0);
  }
  return u + 0.5 - share;
}

/// How many row sides of `edges` (in row order, `.v` the row) hold an edge that `near` accepts: each
/// image row, and the row's columns per metre of lateral offset (a residual in metres there, × this,
/// is one in pixels: rows weigh by their ground resolution).
struct GroundEdge {
  double x, y, side, px_per_m;
  int v;
};

/// The residuals (pixels) of edges from the road of centre line `arc` and width w, and with `jac`
/// their derivatives by (y0, θ, κ).
double edgeResidual(const GroundArc& arc, double w, const GroundEdge& e, double c, double s, Vec3* jac = nullptr) {
  const double r = (arc.offset(e.x, e.y, c, s, jac) - 0.5 * e.side * w) * e.px_per_m;
  if (jac != nullptr) *jac *= e.px_per_m;
  return r;
}

/// Robust Gauss-Newton (Huber weights, `huber` pixels) of the arc's y0, θ and, when `curved`, κ (else
/// κ stays as it is) to the edges. False when there are fewer than `per_parameter` edges per parameter
/// or the system is singular.
bool fitGroundArc(const std::vector<GroundEdge>& edges, double w, bool curved, double huber, GroundArc& arc,
                  int per_parameter = 4) {
  const int m = curved ? 3 : 2;
  if (static_cast<int>(edges.size()) < per_parameter * m) return false;
  for (int it = 0; it < 10; ++it) {
    const double c = std::cos(arc.th), s = std::sin(arc.th);
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Vec3 g = Vec3::Zero(), J;
    for (const GroundEdge& e : edges) {
      const double r = edgeResidual(arc, w, e, c, s, &J);
      const double wt = std::abs(r) <= huber ? 1.0 : huber / std::abs(r);
      A += wt * J * J.transpose();
      g += wt * r * J;
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(A.topLeftCorner(m, m));
    if (ldlt.info() != Eigen::Success) return false;
    Vec3 delta = Vec3::Zero();
    delta.head(m) = -ldlt.solve(g.head(m));
    if (!delta.allFinite()) return false;
    arc.y0 += delta[0];
    arc.th += delta[1];
    arc.k += delta[2];
    if (std::abs(delta[0]) < 1e-5 && std::abs(delta[1]) < 1e-6 && std::abs(delta[2]) < 1e-7) break;
  }
  return std::isfinite(arc.y0) && std::abs(arc.th) < 1.4 && std::isfinite(arc.k);
}

/// Σ r² of the edges (pixels²).
double sumSquares(const std::vector<GroundEdge>& edges, double w, const GroundArc& arc) {
  const double c = std::cos(arc.th), s = std::sin(arc.th);
  double sum = 0;
  for (const GroundEdge& e : edges) sum += std::pow(edgeResidual(arc, w, e, c, s), 2);
  return sum;
}

/// How many rows' left and right edges (each at most once) have a candidate within `tol` pixels of the
/// road of centre line `arc` and width w.
int groundSupport(const std::vector<GroundEdge>& edges, double w, const GroundArc& arc, double tol) {
  const double c = std::cos(arc.th), s = std::sin(arc.th);
  return rowSideSupport(
      edges, [](const GroundEdge& e) { return e.side > 0; },
      [&](const GroundEdge& e) { return std::abs(edgeResidual(arc, w, e, c, s)) <= tol; });
}

/// The vehicle stands on the road: the centre line passes within half the road's width w of it
/// (|y0| ≤ w/2 at x = 0). A hard physical constraint on every fit, not a pull toward any answer: a
/// circle through one shoulder's edges (the dirt/grass boundary 2.5 m out, or a single edge taken for
/// the other side's) that puts the vehicle off its road is not the road.
bool onRoad(const GroundArc& arc, double w) { return std::abs(arc.y0) <= 0.5 * w; }

/// Edge consensus on the ground (RANSAC, seeded): the circle whose road edges pass exactly through three
/// edge candidates in rows at least 16 apart (Gauss-Newton from the ground parabola y = y0 + t·x + c·x²/2
/// through them, each moved half the width to the centre: θ = atan t, κ = c·cos³θ), kept when more
/// rows' edges (and `carried` edges of earlier frames) lie within 2 px of it than of `start` (up to
/// 1000 draws). The image's consensus fits a parabola in the image, which on 15 m bends misses the far
/// edges by more than its tolerance, so that the refinement from it can lock onto a few stray edges;
/// this one finds where most of the road's edges are.
GroundArc groundConsensus(const std::vector<GroundEdge>& edges, const std::vector<GroundEdge>& carried, double w,
                          const GroundArc& start, double max_curvature, std::uint64_t seed) {
  constexpr double tol = 2.0;
  const auto support = [&](const GroundArc& h) {
    const double c = std::cos(h.th), s = std::sin(h.th);
    int n = groundSupport(edges, w, h, tol);
    for (const GroundEdge& e : carried) n += std::abs(edgeResidual(h, w, e, c, s)) <= tol;
    return n;
  };
  GroundArc best = start;
  int best_n = onRoad(start, w) ? support(start) : -1;
  if (edges.size() < 3) return best;
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, edges.size() - 1);
  // At most kMaxDraws draws, fewer when the draws needed for 99.9 % confidence (from the best support
  // so far) are fewer. On a bend the camera may see the road's outer edge alone, on 60 of 200
  // candidates' rows and only beyond 10 m: three of them 16 rows apart come in about one draw in 100,
  // and 300 draws missed the circle on 5 of 88 frames of true 15-20 m circles.
  constexpr int kMaxDraws = 1000;
  int needed = kMaxDraws;
  std::vector<GroundEdge> three(3);
  for (int it = 0; it < std::min(kMaxDraws, needed); ++it) {
    Eigen::Matrix3d A;
    Vec3 rhs;
    std::array<int, 3> rows{};
    bool ok = true;
    for (int k = 0; k < 3 && ok; ++k) {
      const GroundEdge& e = edges[pick(rng)];
      three[static_cast<std::size_t>(k)] = e;
      for (int j = 0; j < k; ++j) ok = ok && std::abs(e.v - rows[static_cast<std::size_t>(j)]) >= 16;
      rows[static_cast<std::size_t>(k)] = e.v;
      A.row(k) = Vec3(1.0, e.x, 0.5 * e.x * e.x).transpose();
      rhs[k] = e.y - 0.5 * e.side * w;
    }
    if (!ok) continue;
    const Vec3 p = A.partialPivLu().solve(rhs);
    if (!p.allFinite()) continue;
    GroundArc h;
    h.y0 = p[0];
    h.th = std::atan(p[1]);
    h.k = p[2] * std::pow(std::cos(h.th), 3);
    if (!fitGroundArc(three, w, true, std::numeric_limits<double>::infinity(), h, 1) || std::abs(h.k) > max_curvature ||
        !onRoad(h, w))
      continue;
    const int n = support(h);
    if (n > best_n) {
      best_n = n;
      best = h;
      const double frac = std::min(0.99, static_cast<double>(n) / static_cast<double>(edges.size() + carried.size()));
      needed = static_cast<int>(std::ceil(std::log(0.001) / std::log(1.0 - std::pow(frac, 3))));
    }
  }
  return best;
}

/// The bootstrap's road width on the ground, m (a flat road of constant width: its rows agree, the
/// median is taken); 0 when no row from v_top has a width.
double groundWidth(const RowGeometry& rows, const std::vector<double>& row_widths, int v_top, int height) {
  std::vector<double> ws;
  for (int v = v_top; v < height; ++v)
    if (row_widths[v] > 0) ws.push_back(row_widths[v] / std::abs(rows.b[v]));
  if (ws.empty()) return 0.0;
  std::nth_element(ws.begin(), ws.begin() + ws.size() / 2, ws.end());
  return ws[ws.size() / 2];
}

/// An image centre model taken to the ground: its centre columns from v_top down, fitted by
/// y = y0 + t·x + c·x²/2, then by the circle (on 15 m bends the parabola's curvature at x = 0 puts
/// the far edges tens of pixels off). False when the fit is singular.
bool groundCircleOf(const CentreModel& model, const RowGeometry& rows, int v_top, int height, double max_curvature,
                    GroundArc& arc) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Vec3 rhs = Vec3::Zero();
  for (int v = v_top; v < height; v += 4) {
    const Vec3 phi(1.0, rows.x[v], 0.5 * rows.x[v] * rows.x[v]);
    A += phi * phi.transpose();
    rhs += phi * ((model.u(v) - rows.a[v]) / rows.b[v]);
  }
  const Vec3 p = A.ldlt().solve(rhs);
  if (!p.allFinite()) return false;
  arc.y0 = p[0];
  arc.th = std::atan(p[1]);
  arc.k = std::clamp(p[2] * std::pow(std::cos(arc.th), 3), -max_curvature, max_curvature);
  std::vector<GroundEdge> centre;
  for (int v = v_top; v < height; v += 4)
    centre.push_back({rows.x[v], (model.u(v) - rows.a[v]) / rows.b[v], 0.0, std::abs(rows.b[v]), v});
  GroundArc circle = arc;
  if (fitGroundArc(centre, 0.0, true, std::numeric_limits<double>::infinity(), circle) && std::abs(circle.k) <= max_curvature)
    arc = circle;
  return true;
}

/// The standard error (pixels) of the column of `arc` at row v when fitted by least squares to `sel`,
/// each edge off by its pixel quantisation alone (uniform over one pixel: σ² = 1/12 px²): gᵀ(JᵀJ)⁻¹g/12,
/// J the edges' residual derivatives (pixels) by y0, θ and, on a circle, κ, and g the column's.
double bottomColumnSd(const std::vector<GroundEdge>& sel, double w, const GroundArc& arc, const RowGeometry& rows,
                      int v) {
  const int m = arc.k != 0.0 ? 3 : 2;
  const double c = std::cos(arc.th), s = std::sin(arc.th);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m, m);
  Vec3 J;
  for (const GroundEdge& e : sel) {
    edgeResidual(arc, w, e, c, s, &J);
    A += J.head(m) * J.head(m).transpose();
  }
  // The column's derivatives, numerically (at() is the closed form of the centre line's offset).
  const double x = rows.x[v], h = 1e-7, y = arc.at(x);
  Eigen::VectorXd g(m);
  for (int k = 0; k < m; ++k) {
    GroundArc p = arc;
    (k == 0 ? p.y0 : k == 1 ? p.th : p.k) += h;
    g[k] = (p.at(x) - y) / h * std::abs(rows.b[v]);
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(A);
  if (ldlt.info() != Eigen::Success || !std::isfinite(y)) return std::numeric_limits<double>::infinity();
  const Eigen::VectorXd ag = ldlt.solve(g);
  return std::sqrt(std::max(0.0, g.dot(ag)) / 12.0);
}

/// This frame's edge candidates of every road row (from v_top down) taken to the ground, each placed
/// within its pixel pair by colour when `rgb` is given (subpixelEdge()), else at the pixel boundary.
std::vector<GroundEdge> groundCandidates(const std::uint8_t* cimg, const std::uint8_t* rgb, int width, int height,
                                         int v_top, const RowGeometry& rows) {
  std::vector<GroundEdge> all;
  std::vector<EdgeCandidate> cands;
  for (int v = v_top; v < height; ++v) {
    cands.clear();
    rowCandidates(cimg + static_cast<std::size_t>(v) * width, width, v, 0, width, cands);
    for (const EdgeCandidate& e : cands) {
      const double u =
          rgb != nullptr ? subpixelEdge(rgb + static_cast<std::size_t>(v) * width * 3, static_cast<int>(e.u + 0.5)) : e.u;
      all.push_back({rows.x[v], (u - rows.a[v]) / rows.b[v], e.left ? 1.0 : -1.0, std::abs(rows.b[v]), v});
    }
  }
  return all;
}

/// The edges a ground fit chooses from: this frame's candidates (`all`), earlier frames' (`carried`,
/// row −1), the road rows [v_top, height), the bootstrap's road width w0 (m), and per row side the
/// scratch of the nearest candidate.
struct GroundEdges {
  std::vector<GroundEdge> all;
  const std::vector<GroundEdge>& carried;
  int v_top, height;
  double w0;
  std::vector<int> best;       // per row side (2v left, 2v + 1 right): the nearest candidate, −1 none
  std::vector<double> best_r;  // its residual, pixels
};

/// A ground fit: the road's centre arc, its width (m), the edges it used and the rows they lie in.
struct GroundFit {
  GroundArc arc;
  double w = 0;
  std::vector<GroundEdge> sel;
  int rows_used = 0;
};

/// The edges of `fit`'s road within `tol` pixels: in each row and side the candidate nearest the
/// model's edge, and the carried edges as they are (each was one row side's). The width becomes the
/// median of the rows where both edges show (at least 8 of them), within [0.8, 1.25] × the bootstrap's.
void selectEdges(GroundEdges& in, double tol, GroundFit& fit) {
  std::fill(in.best.begin(), in.best.end(), -1);
  const double c = std::cos(fit.arc.th), s = std::sin(fit.arc.th);
  for (std::size_t i = 0; i < in.all.size(); ++i) {
    const double r = std::abs(edgeResidual(fit.arc, fit.w, in.all[i], c, s));
    const std::size_t slot = 2 * static_cast<std::size_t>(in.all[i].v) + (in.all[i].side > 0 ? 0 : 1);
    if (r <= tol && (in.best[slot] < 0 || r < in.best_r[slot])) {
      in.best[slot] = static_cast<int>(i);
      in.best_r[slot] = r;
    }
  }
  fit.sel.clear();
  fit.rows_used = 0;
  std::vector<double> widths;  // the rows where both edges show: their offsets' difference
  for (int v = in.v_top; v < in.height; ++v) {
    const int l = in.best[2 * static_cast<std::size_t>(v)], r = in.best[2 * static_cast<std::size_t>(v) + 1];
    fit.rows_used += l >= 0 || r >= 0;
    if (l >= 0) fit.sel.push_back(in.all[static_cast<std::size_t>(l)]);
    if (r >= 0) fit.sel.push_back(in.all[static_cast<std::size_t>(r)]);
    if (l >= 0 && r >= 0) {
      const GroundEdge &el = in.all[static_cast<std::size_t>(l)], &er = in.all[static_cast<std::size_t>(r)];
      widths.push_back(fit.arc.offset(el.x, el.y, c, s) - fit.arc.offset(er.x, er.y, c, s));
    }
  }
  if (widths.size() >= 8) {
    std::nth_element(widths.begin(), widths.begin() + widths.size() / 2, widths.end());
    fit.w = std::clamp(widths[widths.size() / 2], 0.8 * in.w0, 1.25 * in.w0);
  }
  // Earlier frames' edges (v < 0) near the model's edges, as they are: each was one row side's.
  for (const GroundEdge& e : in.carried)
    if (std::abs(edgeResidual(fit.arc, fit.w, e, c, s)) <= tol) fit.sel.push_back(e);
}

/// The refinement from a start (`fit`'s arc and width): the edges selected within a tolerance that
/// narrows from 4 to 1 px and the circle fitted to them (beyond max_curvature, the line part with the
/// curvature at its bound); false when too few edges support it.
bool refineFrom(GroundEdges& in, double max_curvature, GroundFit& fit) {
  for (const double tol : {4.0, 2.5, 1.5, 1.0}) {
    selectEdges(in, tol, fit);
    GroundArc fitted = fit.arc;
    if (!fitGroundArc(fit.sel, fit.w, true, 0.6, fitted)) return false;
    if (std::abs(fitted.k) > max_curvature) {
      // Beyond the searched range: the line part with the curvature at its bound.
      fitted = fit.arc;
      fitted.k = std::clamp(fitted.k, -max_curvature, max_curvature);
      if (!fitGroundArc(fit.sel, fit.w, false, 0.6, fitted)) return false;
    }
    fit.arc = fitted;
  }
  return true;
}

/// The straight line fitted to `fit`'s edges replaces its circle when the curvature does not pay for
/// its parameter (BIC: n ln(RSS/n) + p ln n) and the line keeps the vehicle on the road.
void preferLineWhereCurvatureDoesNotPay(GroundFit& fit) {
  GroundArc line = fit.arc;
  line.k = 0;
  if (fitGroundArc(fit.sel, fit.w, false, 0.6, line) && onRoad(line, fit.w)) {
    const double n = static_cast<double>(fit.sel.size());
    const double bic_arc = n * std::log(sumSquares(fit.sel, fit.w, fit.arc) / n + 1e-12) + 3.0 * std::log(n);
    const double bic_line = n * std::log(sumSquares(fit.sel, fit.w, line) / n + 1e-12) + 2.0 * std::log(n);
    if (bic_line <= bic_arc) fit.arc = line;
  }
}

/// The arc model's edge refinement on the ground. The edge candidates of every road row taken to the
/// ground, the circle fitted to them by robust Gauss-Newton (in each row the left and right candidates
/// nearest the model's edges, within a tolerance that narrows from 4 to 1 px; the width from the rows
/// where both edges show, else the bootstrap's), from two starts: the circle nearest the image fit's
/// (`model`, a ground parabola) and the ground consensus's (groundConsensus()); the one that ends with
/// more edges wins; a fit that puts the vehicle off the road (onRoad()) does not count. Earlier frames'
/// edges (`carried`, row −1: ClusterPerceptronOptions::carry_frames) join every selection and the
/// consensus's support where they lie within the tolerance, each as one row side's edge. Then the
/// straight line fitted to the same edges, kept when the curvature does not pay for its parameter (BIC:
/// n ln(RSS/n) + p ln n) and it keeps the vehicle on the road. Nothing when too few edges support either
/// fit. The fit's `sel`: the winning fit's edges (this frame's, with their rows, and the carried ones
/// it kept).
std::optional<GroundFit> refineGroundArc(const std::uint8_t* cimg, const std::uint8_t* rgb, int width, int height,
                                         int v_top, const CentreModel& model, const RowGeometry& rows,
                                         const std::vector<double>& row_widths, double max_curvature,
                                         std::uint64_t seed, const std::vector<GroundEdge>& carried) {
  const double w0 = groundWidth(rows, row_widths, v_top, height);
  GroundFit fit;
  fit.w = w0;
  if (!(w0 > 0) || !groundCircleOf(model, rows, v_top, height, max_curvature, fit.arc)) return std::nullopt;
  GroundEdges in{groundCandidates(cimg, rgb, width, height, v_top, rows), carried, v_top, height, w0,
                 std::vector<int>(2 * static_cast<std::size_t>(height), -1),
                 std::vector<double>(2 * static_cast<std::size_t>(height))};
  // From the image fit's circle, and from the ground consensus's (which has to beat the first's
  // refined circle); the one that ends with more edges wins.
  bool ok = refineFrom(in, max_curvature, fit) && onRoad(fit.arc, fit.w);
  GroundFit fit2;
  fit2.arc = groundConsensus(in.all, carried, w0, fit.arc, max_curvature, seed);
  fit2.w = w0;
  const bool ok2 = refineFrom(in, max_curvature, fit2) && onRoad(fit2.arc, fit2.w);
  if (ok2 && (!ok || fit2.sel.size() > fit.sel.size())) {
    fit = std::move(fit2);
    ok = true;
  }
  if (!ok) return std::nullopt;
  preferLineWhereCurvatureDoesNotPay(fit);
  return fit;
}

}  // namespace

std::optional<GroundArc> refineOnGround(const std::uint8_t* cimg, const std::uint8_t* rgb, int width, int height,
                                        int v_top, const CentreModel& model, const RowGeometry& rows,
                                        const std::vector<double>& row_widths, const ClusterPerceptronOptions& opt,
                                        const std::vector<std::vector<RoadEdgePoint>>& carried, RoadFinding& res) {
  std::vector<GroundEdge> carried_edges;
  for (const auto& frame : carried)
    for (const RoadEdgePoint& e : frame)
      carried_edges.push_back({e.p.x(), e.p.y(), static_cast<double>(e.side), e.px_per_m, -1});
  const std::optional<GroundFit> fit =
      refineGroundArc(cimg, opt.subpixel_edges ? rgb : nullptr, width, height, v_top, model, rows, row_widths,
                      opt.max_curvature, opt.seed, carried_edges);
  if (!fit) return std::nullopt;
  res.refined = true;
  res.edge_rows = fit->rows_used;
  res.bottom_column_sd = bottomColumnSd(fit->sel, fit->w, fit->arc, rows, height - 1);
  for (const GroundEdge& e : fit->sel) {
    if (e.v < 0) ++res.carried_edges;
    else res.ground_edges.push_back({Vec2(e.x, e.y), e.side > 0 ? 1 : -1, e.px_per_m});
  }
  return fit->arc;
}

bool leavesTheVehicleOffRoad(const CentreModel& model, const RowGeometry& rows, const std::vector<double>& row_widths,
                             int v_top, int height, double max_curvature) {
  const double w0 = groundWidth(rows, row_widths, v_top, height);
  GroundArc g;
  return w0 > 0 && groundCircleOf(model, rows, v_top, height, max_curvature, g) && !onRoad(g, w0);
}

}  // namespace mapnav
