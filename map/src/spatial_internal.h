#pragma once
// Internal to map/: Boost.Geometry box types for the R-trees, and connected components, shared by
// the Map (its index and components) and the validator (crossings, connectivity).
#include <cstddef>
#include <numeric>
#include <utility>
#include <vector>

#include <boost/geometry.hpp>
#include <boost/geometry/index/rtree.hpp>

#include "mapnav/geometry/types.h"

namespace mapnav::spatial {

namespace bg = boost::geometry;
namespace bgi = boost::geometry::index;
using BPoint = bg::model::point<double, 2, bg::cs::cartesian>;
using BBox = bg::model::box<BPoint>;

inline BBox toBBox(const Box2& b) {
  return BBox(BPoint(b.min().x(), b.min().y()), BPoint(b.max().x(), b.max().y()));
}

/// For each of `n` nodes joined by `edges`, the smallest node index in its connected component
/// (so node 0's component is labelled 0). Union–find with path halving.
inline std::vector<std::size_t> componentLabels(std::size_t n, const std::vector<std::pair<std::size_t, std::size_t>>& edges) {
  std::vector<std::size_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (const auto& [a, b] : edges) {
    const std::size_t ra = find(a), rb = find(b);
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);  // the smaller index stays the root
  }
  std::vector<std::size_t> label(n);
  for (std::size_t i = 0; i < n; ++i) label[i] = find(i);
  return label;
}

}  // namespace mapnav::spatial
