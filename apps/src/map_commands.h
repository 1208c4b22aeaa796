#pragma once
// `mapnav map ...`: each command is a config struct and a function, so tests can call them.
#include <array>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/map/geojson.h"
#include "mapnav/map/map.h"
#include "mapnav/map/map_render.h"
#include "mapnav/osm/osm_import.h"

namespace mapnav::cli {

struct ValidateConfig {
  std::vector<std::string> files;  ///< mapnav-map/1 JSON, or GeoJSON (.geojson)
  bool quiet = false;              ///< print only errors and warnings, no per-file summary
};
int runValidate(const ValidateConfig& config, std::ostream& out, std::ostream& err);

struct InfoConfig {
  std::string file;
  bool json = false;
};
int runInfo(const InfoConfig& config, std::ostream& out, std::ostream& err);

struct RenderConfig {
  std::string file;
  std::string output;         ///< .png or .svg
  MapRenderOptions options;   ///< --width, --no-labels
};
int runRender(const RenderConfig& config, std::ostream& out, std::ostream& err);

struct ImportGeoJsonConfig {
  std::string input;
  std::string output;
  GeoJsonImportOptions options;  ///< --origin, --snap, --default-width, --default-surface
  std::optional<std::string> name;
};
int runImportGeoJson(const ImportGeoJsonConfig& config, std::ostream& out, std::ostream& err);

struct ExportGeoJsonConfig {
  std::string input;
  std::string output;
  std::optional<GeoOrigin> origin;
};
int runExportGeoJson(const ExportGeoJsonConfig& config, std::ostream& out, std::ostream& err);

struct ImportOsmConfig {
  std::string input;                       ///< .osm (XML), .osm.pbf, .osm.bz2, ...
  std::string output;                      ///< mapnav-map/1 JSON (written only when the map is valid)
  /// --bbox, --origin, --repair, --keep-far-landmarks, --name; the rest at the library's defaults.
  OsmImportOptions options;
  std::optional<std::string> highways;     ///< "footway,path,..." (default: options.highways)
};
int runImportOsm(const ImportOsmConfig& config, std::ostream& out, std::ostream& err);

/// "W,S,E,N" (degrees, west < east, south < north). Throws InvalidInput saying what is wrong.
std::array<double, 4> parseBbox(const std::string& text);

}  // namespace mapnav::cli
