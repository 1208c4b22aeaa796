// The renderer's tiles (see RenderTiles in world_scene.h): per frame, for each tile of the image
// and each grid cell its ground points can fall in, copies of the cell's lists without the entries
// that no point of the tile can meet, so that a pixel's lookups test a handful of candidates, not
// the cell's dozens. Every bound is conservative by far more than the pixels' rounding, so a pixel
// finds the very same polygon, centre line and canopy discs as with its cell's whole lists.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "world_scene.h"

namespace mapnav {

using namespace world_detail;

namespace {

// A tile's box is widened by this much (m), and a centre line dropped only when farther than the
// nearest one by this much: a pixel's point, distances and crossings are rounded by about 1e-12 m.
constexpr double kSlack = 1e-6;

double pointBoxDist2(const Vec2& q, const Box2& box) {
  const double dx = std::max({box.min().x() - q.x(), 0.0, q.x() - box.max().x()});
  const double dy = std::max({box.min().y() - q.y(), 0.0, q.y() - box.max().y()});
  return dx * dx + dy * dy;
}

/// Distance from q to segment s (locate's formula).
double pointSegDist(const Vec2& q, const Segment& s) {
  const Vec2 d = q - s.a;
  const double t = std::clamp(d.dot(s.dir), 0.0, s.len);
  return (d - s.dir * t).norm();
}

/// Whether segment ab may meet the box (true when unsure: the separating tests want a clear side).
bool segmentMayMeet(const Vec2& a, const Vec2& b, const Box2& box) {
  if (std::max(a.x(), b.x()) < box.min().x() || std::min(a.x(), b.x()) > box.max().x() ||
      std::max(a.y(), b.y()) < box.min().y() || std::min(a.y(), b.y()) > box.max().y())
    return false;
  const Vec2 n(a.y() - b.y(), b.x() - a.x());  // normal of the line
  const double eps = kSlack * n.norm();
  int below = 0, above = 0;
  for (const Vec2& c : corners(box)) {
    const double side = n.dot(c - a);
    below += side < -eps;
    above += side > eps;
  }
  return below < 4 && above < 4;
}

/// A lower bound of the distance from any point of the box to segment s.
double boxSegLowerBound(const Box2& box, const Segment& s) {
  const Vec2 b = s.a + s.dir * s.len;
  if (segmentMayMeet(s.a, b, box)) return 0;
  double d2 = std::min(pointBoxDist2(s.a, box), pointBoxDist2(b, box));
  for (const Vec2& c : corners(box)) {
    const double d = pointSegDist(c, s);
    d2 = std::min(d2, d * d);
  }
  return std::sqrt(d2);
}

/// An upper bound of the distance from any point of the box to segment s (the distance is convex:
/// its largest value over the box is at a corner).
double boxSegUpperBound(const Box2& box, const Segment& s) {
  double d = 0;
  for (const Vec2& c : corners(box)) d = std::max(d, pointSegDist(c, s));
  return d;
}

}  // namespace

bool Scene::polygonHoldsBox(const PavedPolygon& poly, const Box2& box) const {
  if (!poly.box.contains(box)) return false;
  const auto band = [&](double y) {
    return static_cast<std::size_t>(
        std::clamp((y - poly.band_y0) / kEdgeBand, 0.0, static_cast<double>(poly.band_start.size() - 2)));
  };
  for (std::size_t b = band(box.min().y()); b <= band(box.max().y()); ++b)
    for (std::uint32_t i = poly.band_start[b]; i < poly.band_start[b + 1]; ++i)
      if (segmentMayMeet(poly.band_edges[i].a, poly.band_edges[i].b, box)) return false;
  // No edge within reach: every point of the box is on the centre's side.
  return crossingContains(poly, Vec2(box.center()));
}

void Scene::addTileCell(int cell, const Box2& tile, RenderTiles& rt) const {
  const int cx = cell % nx, cy = cell / nx;
  const Vec2 c0 = origin + Vec2(cx * kCell, cy * kCell);
  Box2 box = tile.intersection(Box2(c0 - Vec2(kSlack, kSlack), c0 + Vec2(kCell + kSlack, kCell + kSlack)));
  if (box.isEmpty()) return;
  const CellLists all = cellLists(cell);
  RenderTiles::Cell tc{cell, static_cast<std::uint32_t>(rt.polys.size()), static_cast<std::uint32_t>(rt.segs.size()),
                       static_cast<std::uint32_t>(rt.discs.size()), static_cast<std::uint32_t>(rt.marks.size())};
  // Paved polygons: those whose box the tile misses dropped, those holding the whole tile marked so.
  for (std::uint32_t i = 0; i < all.n_polys; ++i) {
    PolyRef ref = all.polys[i];
    const PavedPolygon& poly = polys[ref.poly];
    if (!ref.whole) {
      if (!poly.box.intersects(box)) continue;
      ref.whole = polygonHoldsBox(poly, box);
    }
    rt.polys.push_back(ref);
  }
  // Centre lines: one farther from every point of the tile than another of its road is from any
  // point is never the nearest (nor the nearest of its road).
  for (std::uint32_t i = 0; i < all.n_segs; ++i) {
    const Segment& s = segments[all.segs[i]];
    double& ub = rt.road_bound[static_cast<std::size_t>(s.road)];
    ub = std::min(ub, boxSegUpperBound(box, s));
  }
  for (std::uint32_t i = 0; i < all.n_segs; ++i) {
    const Segment& s = segments[all.segs[i]];
    if (boxSegLowerBound(box, s) <= rt.road_bound[static_cast<std::size_t>(s.road)] + kSlack)
      rt.segs.push_back(all.segs[i]);
  }
  for (std::uint32_t i = 0; i < all.n_segs; ++i)
    rt.road_bound[static_cast<std::size_t>(segments[all.segs[i]].road)] = std::numeric_limits<double>::infinity();
  // Canopy discs within reach of the tile.
  for (std::uint32_t i = 0; i < all.n_discs; ++i) {
    const Disc& d = discs[all.discs[i]];
    if (pointBoxDist2(d.c, box) <= d.reach2) rt.discs.push_back(all.discs[i]);
  }
  // The landmarks' ground marks whose box the tile meets; a post's and a crown's shadow only within
  // their reach (the radius, or the longer half-axis, and half the widest soft edge) of the tile.
  for (std::uint32_t i = 0; i < all.n_marks; ++i) {
    const GroundMark& m = landmarks.marks[all.marks[i]];
    if (!m.box.intersects(box)) continue;
    if (m.kind == GroundMark::Kind::Capsule) {
      const double len = (m.b - m.a).norm();
      const Segment axis{m.a, len > 0 ? Vec2((m.b - m.a) / len) : Vec2::UnitX(), len};
      if (boxSegLowerBound(box, axis) > m.r + 0.5 * kMarkEdgeMax + kSlack) continue;
    } else if (m.kind == GroundMark::Kind::Ellipse) {
      const double reach = m.r_along + 0.5 * kMarkEdgeMax + kSlack;
      if (pointBoxDist2(m.a, box) > reach * reach) continue;
    }
    rt.marks.push_back(all.marks[i]);
  }
  tc.n_polys = static_cast<std::uint32_t>(rt.polys.size()) - tc.polys;
  tc.n_segs = static_cast<std::uint32_t>(rt.segs.size()) - tc.segs;
  tc.n_discs = static_cast<std::uint32_t>(rt.discs.size()) - tc.discs;
  tc.n_marks = static_cast<std::uint32_t>(rt.marks.size()) - tc.marks;
  rt.cells.push_back(tc);
}

void Scene::clearTiles(RenderTiles& rt) const {
  rt.cells.clear();
  rt.polys.clear();
  rt.segs.clear();
  rt.discs.clear();
  rt.marks.clear();
  rt.road_bound.assign(roads.size(), std::numeric_limits<double>::infinity());
  rt.first.assign(1, 0);
  rt.sure.clear();
}

void Scene::addTile(const Box2& points, RenderTiles& rt) const {
  const Box2 tile(points.min() - Vec2(kSlack, kSlack), points.max() + Vec2(kSlack, kSlack));
  // cellIndex's quotients are monotone in the point: the box's bound every point's.
  const double fx0 = (tile.min().x() - origin.x()) / kCell, fx1 = (tile.max().x() - origin.x()) / kCell;
  const double fy0 = (tile.min().y() - origin.y()) / kCell, fy1 = (tile.max().y() - origin.y()) / kCell;
  const auto cellOf = [](double f, int n) { return std::clamp(static_cast<int>(std::floor(f)), 0, n - 1); };
  const int x0 = cellOf(fx0, nx), x1 = cellOf(fx1, nx), y0 = cellOf(fy0, ny), y1 = cellOf(fy1, ny);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) addTileCell(y * nx + x, tile, rt);
  // Within one cell of the grid, every point's cellIndex is that cell.
  const bool one = fx0 >= 0 && fy0 >= 0 && fx1 < nx && fy1 < ny && x0 == x1 && y0 == y1;
  rt.sure.push_back(one && rt.cells.size() == rt.first.back() + 1 ? static_cast<int>(rt.first.back()) : -1);
  rt.first.push_back(static_cast<std::uint32_t>(rt.cells.size()));
}

void Scene::tileRow(const RayExtras& extras, int band, const std::array<double, 4>& pose, RenderTiles& rt) const {
  const auto [ch, sh, tx, ty] = pose;
  rt.band = band;
  clearTiles(rt);
  for (int t = 0; t < extras.tiles_x; ++t) {
    const RayExtras::TileBox& vb = extras.tiles[static_cast<std::size_t>(band) * extras.tiles_x + t];
    if (vb.ground) {
      // The vehicle-frame box turned and moved: its corners' box holds every pixel's world point.
      Box2 tile;
      for (const Vec2& c : corners(Box2(Vec2(vb.x0, vb.y0), Vec2(vb.x1, vb.y1))))
        tile.extend(Vec2(ch * c.x() - sh * c.y() + tx, sh * c.x() + ch * c.y() + ty));
      addTile(tile, rt);
    } else {
      rt.sure.push_back(-1);
      rt.first.push_back(static_cast<std::uint32_t>(rt.cells.size()));
    }
  }
}

CellLists Scene::tileLists(const RenderTiles& rt, int tile, const Vec2& p) const {
  const auto t = static_cast<std::size_t>(tile);
  const int sure = rt.sure[t];
  const int cell = sure >= 0 ? rt.cells[static_cast<std::size_t>(sure)].cell : cellIndex(p);
  for (std::uint32_t i = rt.first[t]; i < rt.first[t + 1]; ++i) {
    const RenderTiles::Cell& c = rt.cells[i];
    if (c.cell == cell)
      return {rt.polys.data() + c.polys, rt.segs.data() + c.segs, rt.discs.data() + c.discs, rt.marks.data() + c.marks,
              c.n_polys,                 c.n_segs,                c.n_discs,                 c.n_marks};
  }
  return cellLists(cell);  // off the grid, or a cell the tile's box missed by a rounding
}

}  // namespace mapnav
