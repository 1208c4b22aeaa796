// readMapFile: a map file in either format, as every command that takes a map reads it.
#include "mapnav/core/io.h"
#include "mapnav/map/geojson.h"
#include "mapnav/map/map_io.h"

namespace mapnav {

std::optional<Map> readMapFile(const std::filesystem::path& path, Issues& issues,
                               const std::optional<GeoJsonImportOptions>& geojson) {
  const std::string text = readFile(path);
  const std::string ext = path.extension().string();
  if (!geojson && ext != ".geojson" && ext != ".GEOJSON") {
    auto data = parseMap(text, issues);
    return data ? buildMap(std::move(*data), path.string(), issues) : std::nullopt;
  }
  auto imported = importGeoJson(text, issues, geojson.value_or(GeoJsonImportOptions{}));
  if (!imported) return std::nullopt;
  Issues found;
  auto map = buildMap(imported->map, path.string(), found);
  for (Issue& issue : found) issue.where = imported->toFeaturePointer(issue.where);
  issues.insert(issues.end(), found.begin(), found.end());
  return map;
}

}  // namespace mapnav
