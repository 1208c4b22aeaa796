// The cluster-perceptron's image edge refinement (beyond the paper): the Hough answer is good to about
// a block; the road's edges in the mask put the centre model to the pixel. Edge candidates per row, the
// model most of them support (edge consensus), and the robust fit of the centre model to the edges
// near it. See cluster_perceptron.h.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <vector>

#include <Eigen/Dense>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "cluster_perceptron_internal.h"

namespace mapnav {

bool fitCentreModel(const std::vector<Vec2>& vu, int degree, double k, CentreModel& model) {
  const int m = degree + 1;
  if (static_cast<int>(vu.size()) < 4 * m) return false;
  // The samples' basis (1, t, arc) once: it does not depend on the coefficients (model.uAt() of it
  // is model.u()).
  thread_local std::vector<Vec3> basis;
  basis.clear();
  for (const Vec2& s : vu) basis.push_back(model.basis(s.x()));
  for (int it = 0; it < 8; ++it) {
    // The weighted normal equations in plain arrays (Eigen's run-time-sized blocks cost more than the
    // sums): element by element the products and sums of A += w·φφᵀ and rhs += w·φ·(u − fixed part).
    std::array<std::array<double, 3>, 3> a{};
    std::array<double, 3> b{};
    for (std::size_t i = 0; i < vu.size(); ++i) {
      const Vec3& phi = basis[i];
      const double y = vu[i].y();
      const double r = std::abs(y - model.uAt(phi));
      const double w = r <= k ? 1.0 : k / r;
      const double rest = y - (m < 3 ? model.p[2] * phi[2] : 0.0);
      for (int row = 0; row < m; ++row) {
        const double wphi = w * phi[row];
        for (int col = 0; col < m; ++col) a[row][col] += wphi * phi[col];
        b[row] += wphi * rest;
      }
    }
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Vec3 rhs = Vec3::Zero();
    for (int row = 0; row < m; ++row) {
      for (int col = 0; col < m; ++col) A(row, col) = a[row][col];
      rhs[row] = b[row];
    }
    Vec3 p = Vec3(0.0, 0.0, m < 3 ? model.p[2] : 0.0);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(A.topLeftCorner(m, m));
    if (ldlt.info() != Eigen::Success) return false;
    p.head(m) = ldlt.solve(rhs.head(m));
    if (!p.allFinite()) return false;
    const double change = (p - model.p).cwiseAbs().maxCoeff();
    model.p = p;
    if (change < 1e-3) break;
  }
  return true;
}

namespace {

/// Bit j: pixel u0 + j of the row is road (certainty > 127, the byte's top bit), for the 32 pixels
/// from u0 ≥ 0; the pixels at or beyond `width` read as not road (nothing is read past the row).
std::uint32_t roadBits32(const std::uint8_t* row, int width, int u0) {
  const std::uint8_t* p = row + u0;
  std::array<std::uint8_t, 32> tail{};
  if (u0 + 32 > width) {
    std::copy(p, row + width, tail.begin());
    p = tail.data();
  }
#ifdef __SSE2__
  const auto half = [](const std::uint8_t* q) {
    return static_cast<std::uint32_t>(_mm_movemask_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(q))));
  };
  return half(p) | half(p + 16) << 16;
#else
  std::uint32_t bits = 0;
  for (int j = 0; j < 32; ++j) bits |= static_cast<std::uint32_t>(p[j] >> 7) << j;
  return bits;
#endif
}

}  // namespace

void rowCandidates(const std::uint8_t* row, int width, int v, int lo, int hi, std::vector<EdgeCandidate>& out) {
  // A candidate at u: the class changes between u − 1 and u, and not between u − 3 and u − 1 nor
  // between u and u + 2. 27 columns per 32 pixels' bits (bit j: column base − 3 + j, j in 3..29).
  const int u0 = std::max(3, lo), u1 = std::min(width - 3, hi);
  for (int base = u0; base <= u1; base += 27) {
    const std::uint32_t road = roadBits32(row, width, base - 3);
    const std::uint32_t change = road ^ (road << 1);  // bit j: pixels j − 1 and j differ (j ≥ 1)
    const int last = std::min(29, u1 - base + 3);
    const std::uint32_t window = (0xFFFFFFFFu >> (31 - last)) & ~7u;  // bits 3..last
    for (std::uint32_t c = change & ~(change << 1) & ~(change << 2) & ~(change >> 1) & ~(change >> 2) & window; c != 0;
         c &= c - 1) {
      const int k = __builtin_ctz(c);
      out.push_back({v, base - 3 + k - 0.5, ((road >> k) & 1u) != 0});
    }
  }
}

namespace {

/// What edgeSupport() computes per candidate that the consensus's hypotheses share (their rows v0, v1
/// and arc basis are the Hough model's; only the coefficients differ), in arrays that vectorise: the
/// row's t and arc offset, the candidate's column and edge offset from the centre (∓ half the row's
/// width); and the row sides (the candidates are in row order): 1 in `first` for the first candidate
/// of its row side, and for the others (`later`, in order) the first of their side.
struct SupportTerms {
  std::vector<double> t, arc, u, side;
  std::vector<std::int64_t> first;
  std::vector<std::uint8_t> left;
  std::vector<std::pair<int, int>> later;  // (candidate, the first candidate of its row side)
  SupportTerms(const std::vector<EdgeCandidate>& cands, const std::vector<double>& widths, const CentreModel& m) {
    int last_v = -1;
    std::array<int, 2> opens{-1, -1};  // the current row's first left and right candidate
    for (const EdgeCandidate& e : cands) {
      const int i = static_cast<int>(t.size());
      t.push_back(m.t(e.v));
      arc.push_back(m.arc.x ? m.arc(e.v) : 0.0);
      u.push_back(e.u);
      side.push_back((e.left ? -0.5 : 0.5) * widths[e.v]);
      left.push_back(e.left);
      if (e.v != last_v) opens = {-1, -1};
      last_v = e.v;
      int& open = opens[e.left ? 0 : 1];
      first.push_back(open < 0);
      if (open >= 0) later.emplace_back(i, open);
      if (open < 0) open = i;
    }
  }
};

/// edgeSupport()'s near tests: all ones in `hit` where candidate i lies within `tol` of its edge under
/// the coefficients (a, b, k). Built for AVX-512 too where the processor has it, with the products
/// and sums kept apart (no fused multiply-add: the same doubles as CentreModel::u()).
__attribute__((target_clones("avx512f", "default"), optimize("fp-contract=off"))) void nearTests(
    const SupportTerms& terms, double a, double b, double k, bool arc, double tol, std::int64_t* __restrict hit) {
  const std::size_t n = terms.t.size();
  const double *__restrict t = terms.t.data(), *__restrict g = terms.arc.data(), *__restrict u = terms.u.data(),
               *__restrict side = terms.side.data();
  if (arc) {
    for (std::size_t i = 0; i < n; ++i) hit[i] = std::abs(u[i] - ((a + t[i] * b + k * g[i]) + side[i])) > tol ? 0 : -1;
  } else {
    for (std::size_t i = 0; i < n; ++i) hit[i] = std::abs(u[i] - ((a + t[i] * b + 0.0) + side[i])) > tol ? 0 : -1;
  }
}

/// How many candidates lie within `tol` pixels of the road edges the model with coefficients `p` puts
/// at centre ∓ width/2 (each row counts a left and a right edge at most once: rowSideSupport()'s count).
/// The same arithmetic as CentreModel::u() on the shared terms, so the same count; first every
/// candidate's test (nearTests(), vectorised: it was most of the consensus's time), then the count.
int edgeSupport(const SupportTerms& terms, const Vec3& p, bool arc, double tol) {
  thread_local std::vector<std::int64_t> near;  // all ones where near
  const std::size_t n = terms.t.size();
  near.resize(n);
  const std::int64_t* const hit = near.data();
  nearTests(terms, p[0], p[1], p[2], arc, tol, near.data());
  // A row side counts once: its first candidate when near, else the first near one after it (few
  // rows hold two candidates on a side).
  std::int64_t count = 0;
  for (std::size_t i = 0; i < n; ++i) count += hit[i] & terms.first[i];
  for (const auto& [i, open] : terms.later) {
    if (hit[i] == 0) continue;
    bool earlier = false;
    for (int j = open; j < i && !earlier; ++j) earlier = terms.left[j] == terms.left[i] && hit[j] != 0;
    count += !earlier;
  }
  return static_cast<int>(count);
}

}  // namespace

int edgeSupportCount(const std::vector<EdgeCandidate>& cands, const std::vector<double>& widths,
                     const CentreModel& model, const Vec3& p, double tol) {
  return edgeSupport(SupportTerms(cands, widths, model), p, model.arc.x != nullptr, tol);
}

namespace {

/// Edge consensus (RANSAC, seeded): models through the centres implied by `degree + 1` random edge
/// candidates in different rows, kept when more candidates support them than support `model` and
/// `allowed` admits them.
CentreModel edgeConsensus(const std::vector<EdgeCandidate>& cands, const std::vector<double>& widths,
                          const CentreModel& model, int degree, std::uint64_t seed, int iterations, double tol,
                          double max_curvature, const std::function<bool(const CentreModel&)>& allowed) {
  CentreModel best = model;
  const SupportTerms terms(cands, widths, model);
  const bool arc = model.arc.x != nullptr;
  int best_n = edgeSupport(terms, model.p, arc, tol);
  if (cands.size() < static_cast<std::size_t>(degree + 1)) return best;
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, cands.size() - 1);
  const int m = degree + 1;
  // Adaptive: stop once a better model is unlikely (probability 0.999) given the best one's support.
  int needed = iterations;
  for (int it = 0; it < std::min(iterations, needed); ++it) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
    Vec3 rhs = Vec3::Zero();
    bool ok = true;
    std::array<int, 3> rows{-1000, -1000, -1000};
    for (int k = 0; k < m && ok; ++k) {
      const EdgeCandidate& e = cands[pick(rng)];
      for (int j = 0; j < k; ++j) ok = ok && std::abs(e.v - rows[j]) >= 16;
      rows[k] = e.v;
      A.row(k) = model.basis(e.v).transpose();
      rhs[k] = e.u + (e.left ? 0.5 : -0.5) * widths[e.v];
    }
    if (!ok) continue;
    CentreModel h = model;
    h.p = Vec3::Zero();
    h.p.head(m) = A.topLeftCorner(m, m).partialPivLu().solve(rhs.head(m));
    if (!h.p.allFinite() || std::abs(h.p[2]) > max_curvature || !allowed(h)) continue;
    const int n = edgeSupport(terms, h.p, arc, tol);
    if (n > best_n) {
      best_n = n;
      best = h;
      const double w = std::min(0.99, static_cast<double>(n) / static_cast<double>(cands.size()));
      needed = static_cast<int>(std::ceil(std::log(0.001) / std::log(1.0 - std::pow(w, m))));
    }
  }
  return best;
}

/// Each row's left and right candidates nearest the model's two edges (centre ∓ half the row's
/// width), within `tol` pixels (NaN: none).
void edgesNearModel(const std::uint8_t* cimg, int width, int height, int v_top, const std::vector<double>& row_widths,
                    const CentreModel& model, double tol, std::vector<double>& left, std::vector<double>& right) {
  // Every row's candidates near the model's two edges.
  std::vector<EdgeCandidate> cands;
  for (int v = v_top; v < height; ++v)
    for (const double side : {-0.5, 0.5}) {
      const double want = model.u(v) + side * row_widths[v];
      if (want < -tol || want > width + tol) continue;
      rowCandidates(cimg + static_cast<std::size_t>(v) * width, width, v, static_cast<int>(std::floor(want - tol)),
                    static_cast<int>(std::ceil(want + tol)) + 1, cands);
    }
  left.assign(height, std::nan(""));
  right.assign(height, std::nan(""));
  for (const EdgeCandidate& e : cands) {
    const double want = model.u(e.v) + (e.left ? -0.5 : 0.5) * row_widths[e.v];
    double& slot = e.left ? left[e.v] : right[e.v];
    if (std::abs(e.u - want) <= tol && !(std::abs(slot - want) <= std::abs(e.u - want))) slot = e.u;
  }
}

/// The centre estimates (v, u) of the rows' edges: the pair's middle, or one edge plus half the row's
/// width, scaled by the median ratio of the widths measured where both show (at least 8 rows) to the
/// bootstrap's, within [0.8, 1.25].
std::vector<Vec2> centreSamples(const std::vector<double>& left, const std::vector<double>& right, int v_top,
                                int height, const std::vector<double>& row_widths) {
  std::vector<double> ratios;
  for (int v = v_top; v < height; ++v)
    if (!std::isnan(left[v]) && !std::isnan(right[v])) ratios.push_back((right[v] - left[v]) / row_widths[v]);
  double scale = 1.0;
  if (ratios.size() >= 8) {
    std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
    scale = std::clamp(ratios[ratios.size() / 2], 0.8, 1.25);
  }
  std::vector<Vec2> vu;
  for (int v = v_top; v < height; ++v) {
    const double hw = 0.5 * scale * row_widths[v];
    const bool l = !std::isnan(left[v]), r = !std::isnan(right[v]);
    if (l && r) vu.emplace_back(v, 0.5 * (left[v] + right[v]));
    else if (l) vu.emplace_back(v, left[v] + hw);
    else if (r) vu.emplace_back(v, right[v] - hw);
  }
  return vu;
}

}  // namespace

CentreModel edgeConsensusModel(const std::uint8_t* cimg, int width, int height, int v_top,
                               const std::vector<double>& row_widths, const CentreModel& model, int degree,
                               const ClusterPerceptronOptions& opt, const std::function<bool(const CentreModel&)>& admits) {
  // The Hough line counts road-coloured area, which shaded shoulders of road colour can pull; the
  // road's edges are straight and a known width apart, which those shadows' outlines are not.
  // Start from the model that most edge candidates support.
  std::vector<EdgeCandidate> cands;
  for (int v = v_top; v < height; v += 4) rowCandidates(cimg + static_cast<std::size_t>(v) * width, width, v, 0, width, cands);
  return edgeConsensus(cands, row_widths, model, degree, opt.seed, 200, 2.0, opt.max_curvature, admits);
}

void fitModelToEdges(const std::uint8_t* cimg, int width, int height, int v_top, const std::vector<double>& row_widths,
                     int degree, double max_curvature, CentreModel& model, RoadFinding& res) {
  // In each row the left and right candidates nearest the model's edges, each turned into a centre
  // estimate (the pair's middle, or one edge plus half the row's width scaled by the widths measured
  // where both show), by robust least squares; three times, each time with the edges nearer the last
  // fit.
  std::vector<double> left, right;
  for (const double tol : {2.0, 1.5, 1.0}) {
    edgesNearModel(cimg, width, height, v_top, row_widths, model, tol, left, right);
    const std::vector<Vec2> vu = centreSamples(left, right, v_top, height, row_widths);
    CentreModel fitted = model;
    // The arc's curvature within the searched range; else the line part with the curvature kept.
    if (!fitCentreModel(vu, degree, 0.6, fitted)) break;
    if (degree == 2 && std::abs(fitted.p[2]) > max_curvature) {
      fitted = model;
      if (!fitCentreModel(vu, 1, 0.6, fitted)) break;
    }
    model = fitted;
    res.refined = true;
    res.edge_rows = static_cast<int>(vu.size());
  }
}

}  // namespace mapnav
