#pragma once
// Internal to vision/: what the cluster-perceptron's files share (see cluster_perceptron.h): the
// certainty levels of the perceptron's output (lookup table, runtime), the per-pixel classification
// that find() calls (runtime), the image centre model and its fit (runtime, edge refinement,
// pipeline), the Hough that finds the first centre model (runtime), the row's edge candidates (image
// and ground refinement), and the arc model's ground road and its refinement (runtime).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <vector>
#ifdef __SSE2__
#include <immintrin.h>
#endif

#include "mapnav/geometry/types.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav {

// --- The certainty levels -------------------------------------------------------------------------------

/// A pixel's road certainty: the perceptron output y in [-1, 1] quantised to 16 levels, 16 apart
/// (0 = surely not road, 240 = surely road; > 127 ⇔ y > 0 but for y within 1/15 of 0). Coarser
/// than a byte on purpose: clusters of almost the same output (two shades of lit asphalt at 0.99
/// and 0.995) share a level, so the lookup table's cells between them are not boundary cells.
constexpr int kCertaintyMax = 240;
inline std::uint8_t certaintyOf(double y) {
  return static_cast<std::uint8_t>(16 * std::lround(std::clamp((y + 1.0) * 7.5, 0.0, 15.0)));
}
constexpr std::uint8_t kAmbiguous = 255;  // LUT cell spanning a cluster boundary: classify exactly

// --- The perceptron's net input (training, lookup table) ------------------------------------------------

/// Net input for a pixel won by cluster k: +w_k, -w_j for every other j, + bias.
inline double netFor(const std::vector<double>& w, int k) {
  const int n = static_cast<int>(w.size()) - 1;
  double net = w[static_cast<std::size_t>(n)];
  for (int j = 0; j < n; ++j) net += (j == k ? 1.0 : -1.0) * w[static_cast<std::size_t>(j)];
  return net;
}
/// The raw-RGB perceptron's input for one band of a feature: the level scaled to [-1, 1].
inline double rgbInput(double x) { return x / 127.5 - 1.0; }
inline double netRgb(const std::vector<double>& w, const Vec3& f) {
  return w[0] * rgbInput(f.x()) + w[1] * rgbInput(f.y()) + w[2] * rgbInput(f.z()) + w[3];
}

/// The widest vector code the fast path's classification may use, in order; the processor's best is
/// used, at most the cap (setParkSimdCap()), so that tests can compare every path with the reference.
enum class ParkSimd { Portable, Avx2, Avx512 };
/// Caps the vector code of every later find() (default: none, ParkSimd::Avx512). Not for use while
/// another thread runs find().
void setParkSimdCap(ParkSimd cap);

// --- The classification (cluster_perceptron_classify.cpp) ----------------------------------------------

/// The fast path's tables (LutTables, read by classifyFrame()): the 32³ cells' certainties, and the
/// ambiguous cells' offsets into their exact 8³ tables.
struct LutView {
  const std::uint8_t* lut;
  const std::uint32_t* sub_offset;
  const std::uint8_t* sub;
};

// --- The colour lookup table (cluster_perceptron_lut.cpp) ----------------------------------------------

// For features that are channel by channel (RGB and log colour, not normalised colour): each 8-bit
// value's squared float difference per channel to each mean, so that a colour's nearest cluster is
// table lookups that give what ClusterPerceptron::nearest() computes (the same float operations in
// the same order: the same cluster, ties the first).
class ChannelTables {
 public:
  template <class Feature>
  ChannelTables(const Feature& feature, const std::vector<Vec3>& means)
      : n_(static_cast<int>(means.size())), stride_(n_ <= kLanes ? kLanes : n_) {
    // Up to 8 clusters a row holds 8 floats, the missing clusters infinitely far (nearest()'s vector path).
    squares_.assign(3 * 256 * static_cast<std::size_t>(stride_), std::numeric_limits<float>::infinity());
    for (int x = 0; x < 256; ++x) {
      const Vec3 f = feature(x, x, x);
      for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < n_; ++k) {
          const float d = static_cast<float>(f[c]) - static_cast<float>(means[k][c]);
          squares_[(static_cast<std::size_t>(c) * 256 + x) * stride_ + k] = d * d;
        }
      }
    }
  }
  /// The nearest cluster: the least of the float sums sr + sg + sb, the first of equal ones.
  int nearest(int r, int g, int b) const {
    const std::size_t n = static_cast<std::size_t>(stride_);
    const float *sr = &squares_[static_cast<std::size_t>(r) * n], *sg = &squares_[(256 + static_cast<std::size_t>(g)) * n],
                *sb = &squares_[(512 + static_cast<std::size_t>(b)) * n];
#ifdef __SSE2__
    if (stride_ == kLanes) {
      // The 8 sums at once, the least by a min tree, its first lane by a mask: the same sums and the
      // same answer as the loop below, with no chain of comparisons from cluster to cluster.
      const __m128 d0 = _mm_add_ps(_mm_add_ps(_mm_loadu_ps(sr), _mm_loadu_ps(sg)), _mm_loadu_ps(sb));
      const __m128 d1 = _mm_add_ps(_mm_add_ps(_mm_loadu_ps(sr + 4), _mm_loadu_ps(sg + 4)), _mm_loadu_ps(sb + 4));
      __m128 m = _mm_min_ps(d0, d1);
      m = _mm_min_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(2, 3, 0, 1)));
      m = _mm_min_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(1, 0, 3, 2)));
      const unsigned mask = static_cast<unsigned>(_mm_movemask_ps(_mm_cmpeq_ps(d0, m))) |
                            (static_cast<unsigned>(_mm_movemask_ps(_mm_cmpeq_ps(d1, m))) << 4);
      return std::countr_zero(mask);
    }
#endif
    int best = 0;
    float bd = std::numeric_limits<float>::max();
    for (int k = 0; k < n_; ++k) {
      // Without a branch (a colour's nearest cluster changes from pixel to pixel unpredictably): the
      // same comparisons, the first of equal distances kept.
      const float d = sr[k] + sg[k] + sb[k];
      const bool nearer = d < bd;
      bd = nearer ? d : bd;
      best = nearer ? k : best;
    }
    return best;
  }

 private:
  static constexpr int kLanes = 8;
  int n_;
  int stride_;  ///< floats per (channel, value) row: 8 up to 8 clusters, else the clusters
  std::vector<float> squares_;  // [channel][value][cluster]
};

constexpr std::uint8_t kUnknownCell = 254;  // LUT cell not computed yet (no certainty level is 254)

/// One trained model's colour lookup table, computed cell by cell as frames need them: a cell of 8³
/// colours gets its certainty when its 8 corners prove it uniform, else its own table of the 512
/// colours' exact certainties (ClusterPerceptron::lutFor()). Copies of a ClusterPerceptron share it
/// (the same model); retraining makes a new one. `mutex` guards the filling.
struct LutTables {
  std::mutex mutex;
  std::vector<std::uint8_t> lut;          ///< 32³ cells + 3 bytes (the runtime reads 4 from a cell)
  std::vector<std::uint32_t> sub_offset;  ///< an ambiguous cell's first colour in `sub`
  std::vector<std::uint8_t> sub;          ///< the ambiguous cells' exact certainties, + 3 bytes (read 4 at a time)
  std::vector<std::uint8_t> cert;         ///< each cluster's certainty (the clusters' code)
  std::vector<std::uint8_t> near;         ///< the 64³ lattice corners' nearest cluster, kUnknownCell until asked
  std::optional<ChannelTables> tables;    ///< where the feature is channel by channel
  int frames = 0;                         ///< frames classified with it
  bool complete = false;                  ///< every cell computed
};

/// ClusterPerceptron::lutFor()'s answer: the tables, and their lock while they are not whole.
struct ClusterPerceptron::LutAccess {
  LutView view;
  std::unique_lock<std::mutex> lock;
};

/// A frame's per-pixel certainty (row by row, `width` a row) and its block sums (block row by block
/// row), as classifyFrame() leaves them; find() keeps one per thread.
struct FrameScratch {
  std::vector<std::uint8_t> cert;
  std::vector<std::uint32_t> bsum;
};

/// §6: every pixel's road certainty (into scr.cert) and each block's sum of them (scr.bsum), one band
/// of block rows per task: the bands write disjoint rows of both, so threads do not change the answer.
/// The fast path reads the lookup table; the reference path classifies every pixel by
/// finder.outputReference(). Returns the frame's road pixels.
long long classifyFrame(const ClusterPerceptron& finder, const LutView& tables, const std::uint8_t* rgb, int width,
                        int height, FrameScratch& scr);

// --- The image centre model -----------------------------------------------------------------------------

/// The arc model's offset per unit curvature (pixels per 1/m) of the rows: the column of the ground
/// parabola κ·(x − x0)(x − x1)/2, which vanishes at the rows v0 and v1 (ground distances x0, x1),
/// so that with it the centre line is an image line through (a, v0), (a + b, v1) plus κ times this.
/// The parabola differs from κx²/2 by a ground line, whose image is an image line: the same family.
struct ArcBasis {
  const std::vector<double>* x = nullptr;  // per image row: ground distance, m
  const std::vector<double>* b = nullptr;  // per image row: columns per metre of lateral offset
  double x0 = 0, x1 = 0;
  static double at(const std::vector<double>& f, double v) {
    const double c = std::clamp(v, 0.0, static_cast<double>(f.size() - 1));
    const std::size_t i = std::min(static_cast<std::size_t>(c), f.size() - 2);
    return f[i] + (c - static_cast<double>(i)) * (f[i + 1] - f[i]);
  }
  ArcBasis(const std::vector<double>& xs, const std::vector<double>& bs, double v0, double v1)
      : x(&xs), b(&bs), x0(at(xs, v0)), x1(at(xs, v1)) {}
  ArcBasis() = default;
  double operator()(double v) const {
    if (x == nullptr) return 0.0;
    const double xv = at(*x, v);
    return 0.5 * at(*b, v) * (xv - x0) * (xv - x1);
  }
};

/// The road model of the image centre line, t = (v − v0) / (v1 − v0): u = a + b t (the line), or
/// u = a + b t + κ·arc(v) (the ground arc; p[2] = κ, 1/m).
struct CentreModel {
  double v0 = 0, v1 = 1;
  Vec3 p = Vec3::Zero();  // a, b, κ
  ArcBasis arc;
  double t(double v) const { return (v - v0) / (v1 - v0); }
  Vec3 basis(double v) const { return Vec3(1.0, t(v), arc.x ? arc(v) : 0.0); }
  /// The centre's column at a row of basis b (basis()).
  double uAt(const Vec3& b) const { return p[0] + b[1] * p[1] + (arc.x ? p[2] * b[2] : 0.0); }
  double u(double v) const { return uAt(basis(v)); }
};

/// Least-squares fit of the model's `degree + 1` coefficients to (v, u) samples with Huber
/// weights (IRLS, `k` pixels), starting from the model's own coefficients for the weights.
bool fitCentreModel(const std::vector<Vec2>& vu, int degree, double k, CentreModel& model);

/// The arc model's per-row tables of a camera (cluster_perceptron_arc.cpp; ClusterPerceptron::
/// setCamera() keeps them): per image row, the ground distance (m) it sees along the principal column,
/// the column of lateral offset 0 there and the columns per metre of lateral offset; NaN where the row
/// sees no ground. Exact for a pin-hole without distortion, yaw or roll.
struct RowTables {
  std::vector<double> x, a, b;
};
RowTables rowTablesOf(const Camera& camera);

/// The camera's per-row geometry for the arc model (ClusterPerceptron::setCamera()).
struct RowGeometry {
  const std::vector<double>& x;  // ground distance, m
  const std::vector<double>& a;  // column of lateral offset 0
  const std::vector<double>& b;  // columns per metre of lateral offset
};

// --- The Hough (cluster_perceptron_hough.cpp) -------------------------------------------------------------

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

/// What the Hough found: the centre model (the line, or the arc of the best curvature; its rows v0
/// and v1 the top and bottom road block rows' centres), the prior's window the refinement keeps to,
/// the top road row (pixels), the coarse peak (RoadFinding::intercept_col and shift, blocks) and the
/// confidence; or why it found nothing (`failure`; then only what was set before it is).
struct HoughAnswer {
  const char* failure = nullptr;
  CentreModel model;
  PriorWindow window;
  int v_top = 0;
  double intercept_col = 0;
  int shift = 0;
  double confidence = 0;
  HoughAnswer& fails(const char* why) {
    failure = why;
    return *this;
  }
};

/// §5: the Hough over the road block rows of a frame's block sums (FrameScratch::bsum, blocks of
/// opt.block_size), each row's summation kernel the bootstrap's road width there (`row_widths`, per
/// image row): the coarse search over intercept, angle and (opt.road_model Arc, with `rows` the
/// camera's) curvature, then its sub-block refinement; with opt.prior_px and a `prior`, only near it.
HoughAnswer houghCentre(const std::vector<std::uint32_t>& bsum, const std::vector<double>& row_widths,
                        const RowGeometry& rows, int width, int height, const ClusterPerceptronOptions& opt,
                        const std::optional<Segment2>& prior);

// --- Edge candidates (cluster_perceptron_edges.cpp) ------------------------------------------------------

/// A place in a row where the class changes and stays changed for 3 pixels on each side (isolated
/// pixels of the other class are no edge): a left road edge (road starts, going right) or a right one.
struct EdgeCandidate {
  int v;
  double u;  // pixel boundary, x.5
  bool left;
};

/// The candidates of one row (certainties; road ⇔ > 127 ⇔ the byte's top bit) with u in [lo, hi].
void rowCandidates(const std::uint8_t* row, int width, int v, int lo, int hi, std::vector<EdgeCandidate>& out);

/// How many row sides of `edges` (in row order, `.v` the row) hold an edge that `near` accepts: each
/// row counts a left (`isLeft`) and a right edge at most once. The support of a consensus model.
template <typename Edge, typename IsLeft, typename Near>
int rowSideSupport(const std::vector<Edge>& edges, IsLeft isLeft, Near near) {
  int n = 0, last_v = -1;
  bool got_l = false, got_r = false;
  for (const Edge& e : edges) {
    if (e.v != last_v) {
      last_v = e.v;
      got_l = got_r = false;
    }
    bool& got = isLeft(e) ? got_l : got_r;
    if (got || !near(e)) continue;
    got = true;
    ++n;
  }
  return n;
}

/// How many row sides of `cands` (in row order) hold a candidate within `tol` pixels of the road edge
/// that `model` with coefficients `p` puts at centre ∓ widths[v]/2: rowSideSupport() of that test, as
/// the edge consensus counts it for each hypothesis (vectorised there; exposed for its test).
int edgeSupportCount(const std::vector<EdgeCandidate>& cands, const std::vector<double>& widths,
                     const CentreModel& model, const Vec3& p, double tol);

/// The image edge refinement of find() (beyond the paper): the Hough's `model` (its `degree + 1`
/// coefficients) moved to the model most edge candidates support (edge consensus; `admits` the prior's
/// window), for the arc model the place to start the ground fit from.
CentreModel edgeConsensusModel(const std::uint8_t* cimg, int width, int height, int v_top,
                               const std::vector<double>& row_widths, const CentreModel& model, int degree,
                               const ClusterPerceptronOptions& opt, const std::function<bool(const CentreModel&)>& admits);
/// Then the model fitted to the edges that support it (robust least squares, in narrowing windows);
/// sets `res`'s refined and edge_rows where a fit succeeds.
void fitModelToEdges(const std::uint8_t* cimg, int width, int height, int v_top, const std::vector<double>& row_widths,
                     int degree, double max_curvature, CentreModel& model, RoadFinding& res);

// --- The arc model on the ground (cluster_perceptron_arc.cpp) -------------------------------------------

/// The arc model's road on the ground (vehicle frame: x ahead, y left): the centre line is the
/// circle (a line when κ = 0) through (0, y0) with heading θ and curvature κ (1/m, left positive);
/// the road's edges are the concentric circles half the road's width to either side.
struct GroundArc {
  double y0 = 0, th = 0, k = 0;
  /// The signed perpendicular offset of the ground point (x, y) from the centre line (left
  /// positive), ℓ = N / (1 + D) with N = 2n − κa, D = √(1 − κN) (n the offset from the tangent
  /// line, a the squared distance to (0, y0)): exact for circles and lines alike. With its
  /// derivatives by y0, θ and κ when `jac` is given: (κ·dy − cos θ)/D, −along/D and (ℓ² − a)/(2D).
  double offset(double x, double y, double c, double s, Vec3* jac = nullptr) const {
    const double dy = y - y0, along = c * x + s * dy, n = -s * x + c * dy, a = x * x + dy * dy;
    const double N = 2.0 * n - k * a, D = std::sqrt(std::max(1e-12, 1.0 - k * N)), l = N / (1.0 + D);
    if (jac != nullptr) *jac = Vec3((k * dy - c) / D, -along / D, (l * l - a) / (2.0 * D));
    return l;
  }
  /// The centre line's lateral offset at ground distance x: y0 + x(κx + 2 sin θ) / (cos θ + √(1 − s²)),
  /// s = κx + sin θ; NaN where the circle turns back before x.
  double at(double x) const {
    const double s = k * x + std::sin(th);
    if (std::abs(s) >= 1.0) return std::nan("");
    return y0 + x * (k * x + 2.0 * std::sin(th)) / (std::cos(th) + std::sqrt(1.0 - s * s));
  }
};

/// The arc model's refinement of find() on the ground, from the image model `model`: the circle (or
/// line) fitted to the road's edges on the ground (this frame's and the `carried` ones), or nothing
/// when too few edges support a fit. Sets `res`'s refined, edge_rows, bottom_column_sd, ground_edges
/// and carried_edges when it succeeds. `rgb`: the frame (its colours place the edges with
/// opt.subpixel_edges).
std::optional<GroundArc> refineOnGround(const std::uint8_t* cimg, const std::uint8_t* rgb, int width, int height,
                                        int v_top, const CentreModel& model, const RowGeometry& rows,
                                        const std::vector<double>& row_widths, const ClusterPerceptronOptions& opt,
                                        const std::vector<std::vector<RoadEdgePoint>>& carried, RoadFinding& res);
/// The image model's centre line, taken to the ground, passes farther than half the road's width from
/// the vehicle, which stands on the road.
bool leavesTheVehicleOffRoad(const CentreModel& model, const RowGeometry& rows, const std::vector<double>& row_widths,
                             int v_top, int height, double max_curvature);

}  // namespace mapnav
