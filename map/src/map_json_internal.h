#pragma once
// Shared by the map's JSON and GeoJSON readers and writers; not part of the public API (it pulls
// in nlohmann-json).
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mapnav/core/json.h"
#include "mapnav/map/map.h"

namespace mapnav {

/// A reader lists the problems of at most this many elements of one array, then says how many more
/// there are: a million bad points need one line, not a million.
inline constexpr std::size_t kMaxIssuesPerArray = 20;
void reportSuppressed(Issues& issues, const std::string& pointer, std::size_t bad);

std::optional<Vec2> readPoint(const Json& value, const std::string& pointer, Issues& issues);
std::optional<std::vector<Vec2>> readPoints(const Json* value, const std::string& pointer, Issues& issues);
std::optional<GeoOrigin> readOrigin(const Json& value, const std::string& pointer, Issues& issues);
std::optional<std::vector<std::pair<std::string, Appearance>>> readSurfaces(const Json* value, const std::string& pointer,
                                                                         Issues& issues);
Json pointToJson(const Vec2& p);
Json pointsToJson(const std::vector<Vec2>& points);
Json surfacesToJson(const std::vector<std::pair<std::string, Appearance>>& surfaces);
Json originToJson(const GeoOrigin& origin);
/// The landmark kind a name spells; nothing, with a schema.enum error at `pointer` listing the
/// kinds, when it spells none.
std::optional<LandmarkKind> readLandmarkKind(const std::string& text, const std::string& pointer, Issues& issues);
/// A property's JSON value as kept (a string as itself, anything else as its compact text), and back.
PropertyValue propertyFromJson(const Json& value);
Json propertyToJson(const PropertyValue& value);

}  // namespace mapnav
