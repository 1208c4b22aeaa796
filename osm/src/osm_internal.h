#pragma once
// Shared by the OpenStreetMap importer's sources; not part of the public API.
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mapnav/core/issue.h"
#include "mapnav/map/map.h"

namespace mapnav::osm_internal {

using NodeId = std::int64_t;
using Cell = std::pair<std::int64_t, std::int64_t>;

inline std::string nodeRef(NodeId id) { return "node/" + std::to_string(id); }

/// Integer grid cell of a point, for neighbour searches.
inline Cell cellOf(const Vec2& p, double size) {
  return {static_cast<std::int64_t>(std::floor(p.x() / size)), static_cast<std::int64_t>(std::floor(p.y() / size))};
}

struct CellHash {
  std::size_t operator()(const Cell& c) const { return std::hash<std::int64_t>()(c.first * 73856093LL ^ c.second * 19349663LL); }
};

/// Calls `f(cell)` for every cell of the grid of `size` m that the box meets.
template <typename F>
void forEachCell(const Box2& box, double size, F&& f) {
  const auto [x0, y0] = cellOf(box.min(), size);
  const auto [x1, y1] = cellOf(box.max(), size);
  for (std::int64_t x = x0; x <= x1; ++x) {
    for (std::int64_t y = y0; y <= y1; ++y) f(Cell{x, y});
  }
}

/// A length tag in metres ("2", "2.5 m", "2.5m"); nothing when it is not a finite number.
std::optional<double> parseMetres(std::string text);

/// The tags of a node that mapnav reads for a landmark, (key, value) in the node's order.
using LandmarkTags = std::vector<std::pair<std::string, std::string>>;

/// Whether mapnav reads this key for landmarks: natural, highway, amenity, barrier, man_made,
/// manhole (the kind), circumference, height (the size).
bool isLandmarkKey(std::string_view key);

/// The kind the tags give: natural=tree a tree, highway=street_lamp a pole, amenity=bench a bench,
/// barrier=bollard a bollard, man_made=manhole or manhole=* a manhole (the first of these that
/// fits); nothing for another node.
std::optional<LandmarkKind> landmarkKindOf(const LandmarkTags& tags);

/// The landmark a node stands for: id "<kind><node>" ("tree123"); the kind's size unless a sane
/// `circumference` (a tree's trunk, m: radius = c / 2π) or `height` (m, upright kinds) gives one,
/// an unusable tag reported as osm.bad_size at node/ID; properties osm_node and the tags read.
Landmark landmarkFromNode(NodeId node, LandmarkKind kind, const Vec2& position, const LandmarkTags& tags, Issues& issues);

/// For each point, its distance (m) to the nearest road's paved area (the centre line's distance
/// less half the width; negative inside it), or +infinity when no paved area is within `reach` m.
std::vector<double> distancesToPavedArea(const std::vector<Road>& roads, const std::vector<Vec2>& points, double reach);

}  // namespace mapnav::osm_internal
