#pragma once
// Reading and writing `mapnav-map/1` JSON files (docs/map-format.md). As Lanelet2's loaders, each
// reader either throws or, given an issue list, collects every problem and goes on.
//
// Reading runs in two passes, as a compiler would: the structure (JSON syntax, types, required and
// unknown members) and then, only when the structure is sound, the map's meaning (validateMap).
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "mapnav/core/issue.h"
#include "mapnav/map/map.h"
#include "mapnav/map/validation.h"

namespace mapnav {

inline constexpr std::string_view kMapFormat = "mapnav-map/1";

/// The structure pass on a document's text: the data when the text is a readable map, nothing (and
/// issues) otherwise. Does not validate meaning.
std::optional<MapData> parseMap(std::string_view text, Issues& issues);

/// The meaning pass: the Map built from `data` (validated with `options`), appending every issue,
/// warnings too, to `issues`; nothing when there is an error. `source` names the data in messages.
std::optional<Map> buildMap(MapData data, const std::string& source, Issues& issues,
                            const ValidationOptions& options = {});

/// Both passes on a file. Appends every problem to `issues` (warnings too) and returns the map when
/// there is no error. Throws IoError when the file cannot be read.
std::optional<Map> loadMap(const std::filesystem::path& path, Issues& issues,
                           const ValidationOptions& options = {});
/// Both passes on a file; throws ValidationError (with every issue) or IoError.
Map loadMap(const std::filesystem::path& path, const ValidationOptions& options = {});

/// The document's text: 2-space indented, points on one line, doubles written so that they read
/// back to the same bits (load → save → load is exact).
std::string mapToJson(const MapData& map);
/// mapToJson written atomically.
void saveMap(const MapData& map, const std::filesystem::path& path);

}  // namespace mapnav
