// The cluster-perceptron's colour lookup table (Jochem & Baluja 1993 §6, the fast runtime path):
// the clusters and the perceptron collapsed into one road certainty per colour, in 32³ cells of 8³
// colours. A cell whose certainty its 8 corners prove to be the same everywhere in it gets that
// certainty; every other cell is marked ambiguous and gets its own 8×8×8 table of each colour's
// certainty (the reference path's, certaintyOf(outputReference()), computed the cheaper way), so the
// fast path needs no distance computation at all and still equals the reference path colour by
// colour. Cells are computed when a frame first needs them (lutFor()): a model trained for one photo
// computes the photo's cells only. See cluster_perceptron.h.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "cluster_perceptron_internal.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav {

namespace {

constexpr int kCells = 32 * 32 * 32;
int corner(int i) { return i % 2 == 0 ? (i / 2) * 8 : (i / 2) * 8 + 7; }  // 8q and 8q + 7

}  // namespace

void ClusterPerceptron::resetLut() {
  auto t = std::make_shared<LutTables>();
  if (!opt_.raw_rgb) {
    const int n = static_cast<int>(means_.size());
    t->cert.resize(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) t->cert[static_cast<std::size_t>(k)] = certaintyOf(std::tanh(netFor(weights_, k)));
    t->tables = channelTables();  // a colour's nearest cluster, as nearest() finds it
    t->near.assign(64 * 64 * 64, kUnknownCell);
  }
  t->lut.assign(kCells, kUnknownCell);
  t->lut.resize(kCells + 3, 0);  // 3 bytes beyond the last cell: the runtime reads 4 from a cell
  t->sub_offset.assign(kCells, 0);
  t->sub.assign(3, 0);  // 3 bytes beyond the last colour: the AVX-512 runtime reads 4 from one
  lut_ = std::move(t);
}

std::optional<std::uint8_t> ClusterPerceptron::uniformCell(LutTables& t, int r, int g, int b) const {
  if (opt_.raw_rgb) {
    // The net input is linear in the colour: over a cell it lies between its values at the corners,
    // and the certainty, monotonic in it, is uniform when it is the same at both ends (a hair wider,
    // against rounding). In normalised colour the net input is a ratio of two linear functions of
    // the colour, which also takes its extremes over a box at the corners where the denominator
    // R + G + B stays positive.
    double lo = std::numeric_limits<double>::max(), hi = -lo;
    for (int m = 0; m < 8; ++m) {
      const Vec3 f = feature(corner(2 * r + (m & 1)), corner(2 * g + ((m >> 1) & 1)), corner(2 * b + ((m >> 2) & 1)));
      const double net = netRgb(weights_, f);
      lo = std::min(lo, net);
      hi = std::max(hi, net);
    }
    const std::uint8_t c = certaintyOf(std::tanh(lo - 1e-9));
    if (c == certaintyOf(std::tanh(hi + 1e-9))) return c;
    return std::nullopt;
  }
  // A cell whose 8 corners share their nearest cluster lies wholly in that cluster's (convex) Voronoi
  // cell. In normalised colour f = 255 C / (R + G + B), "nearer mean k than mean j" is linear in f
  // and so, times R + G + B, a half-space through black in RGB: the same holds. Log colour maps each
  // channel by one increasing function, so a cell is a box there too whose corners are the corners'
  // images: the same holds.
  const auto nearCorner = [&](int a, int bb, int c) {
    std::uint8_t& k = t.near[(static_cast<std::size_t>(a) * 64 + bb) * 64 + c];
    if (k == kUnknownCell)
      k = static_cast<std::uint8_t>(t.tables ? t.tables->nearest(corner(a), corner(bb), corner(c))
                                             : nearest(corner(a), corner(bb), corner(c)));
    return k;
  };
  const int k0 = nearCorner(2 * r, 2 * g, 2 * b);
  const std::uint8_t c = t.cert[static_cast<std::size_t>(k0)];
  bool same = true;
  for (int m = 1; m < 8 && same; ++m) same = nearCorner(2 * r + (m & 1), 2 * g + ((m >> 1) & 1), 2 * b + ((m >> 2) & 1)) == k0;
  if (same) return c;
  // Exact test for a cell spanning clusters of equal certainty c: no point of the cube has a cluster
  // j of another certainty as its nearest if, for every such j, some cluster k of certainty c is
  // nearer than j at all 8 corners (the region nearer k than j is a half-space, so the whole cube is).
  const int n = static_cast<int>(means_.size());
  const auto d2 = [&](int k, double x, double y, double z) {
    return (means_[static_cast<std::size_t>(k)] - feature(x, y, z)).squaredNorm();
  };
  for (int j = 0; j < n; ++j) {
    if (t.cert[static_cast<std::size_t>(j)] == c) continue;
    bool out = false;
    for (int k = 0; k < n && !out; ++k) {
      if (t.cert[static_cast<std::size_t>(k)] != c) continue;
      out = true;
      for (int m = 0; m < 8 && out; ++m) {
        const double x = corner(2 * r + (m & 1)), y = corner(2 * g + ((m >> 1) & 1)), z = corner(2 * b + ((m >> 2) & 1));
        out = d2(k, x, y, z) < d2(j, x, y, z);
      }
    }
    if (!out) return std::nullopt;
  }
  return c;
}

void ClusterPerceptron::exactCell(LutTables& t, int r, int g, int b) const {
  t.sub.resize(t.sub.size() - 3);  // the padding goes back after the cell's 512 colours
  for (int i = 0; i < 512; ++i) {
    const int x = 8 * r + (i >> 6), y = 8 * g + ((i >> 3) & 7), z = 8 * b + (i & 7);
    if (opt_.raw_rgb) t.sub.push_back(certaintyOf(std::tanh(netRgb(weights_, feature(x, y, z)))));
    else t.sub.push_back(t.cert[static_cast<std::size_t>(t.tables ? t.tables->nearest(x, y, z) : nearest(x, y, z))]);
  }
  t.sub.resize(t.sub.size() + 3, 0);
}

void ClusterPerceptron::fillCell(LutTables& t, int cell) const {
  const int r = cell >> 10, g = (cell >> 5) & 31, b = cell & 31;
  // Black's cell proves nothing from its corners in normalised colour: black counts as grey there.
  const auto c = opt_.normalized_color && cell == 0 ? std::nullopt : uniformCell(t, r, g, b);
  if (c) {
    t.lut[static_cast<std::size_t>(cell)] = *c;
    return;
  }
  t.lut[static_cast<std::size_t>(cell)] = kAmbiguous;
  t.sub_offset[static_cast<std::size_t>(cell)] = static_cast<std::uint32_t>(t.sub.size() - 3);
  exactCell(t, r, g, b);
}

ClusterPerceptron::LutAccess ClusterPerceptron::lutFor(const std::uint8_t* rgb, int width, int height) const {
  LutTables& t = *lut_;
  std::unique_lock lock(t.mutex);
  if (!t.complete) {
    std::uint8_t* lut = t.lut.data();
    if (t.frames == 0) {
      const std::size_t pixels = static_cast<std::size_t>(width) * height;
      for (std::size_t i = 0; i < pixels; ++i) {
        const std::uint8_t* p = rgb + 3 * i;
        const int cell = ((p[0] >> 3) << 10) | ((p[1] >> 3) << 5) | (p[2] >> 3);
        if (lut[cell] == kUnknownCell) fillCell(t, cell);
      }
    } else {
      for (int cell = 0; cell < kCells; ++cell)
        if (lut[cell] == kUnknownCell) fillCell(t, cell);
      t.complete = true;
    }
    ++t.frames;
  }
  if (t.complete) lock.unlock();
  return LutAccess{LutView{t.lut.data(), t.sub_offset.data(), t.sub.data()}, std::move(lock)};
}

}  // namespace mapnav
