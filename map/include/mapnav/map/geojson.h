#pragma once
// GeoJSON (RFC 7946) import and export, for maps drawn in QGIS or geojson.io (docs/map-format.md).
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mapnav/core/issue.h"
#include "mapnav/core/option_table.h"
#include "mapnav/map/map.h"

namespace mapnav {

struct GeoJsonImportOptions {
  /// The local frame's origin. Default: the file's `mapnav.origin`, else the data's centroid.
  std::optional<GeoOrigin> origin;
  /// Road ends closer than this (m) to an intersection point, or to each other, share a node; a
  /// plain centre line's interior vertex this close to another line's vertex cuts it there.
  double snap_tolerance_m = 1.0;
  /// Defaults for LineString properties that are absent.
  double default_width_m = 2.0;
  std::string default_surface = "concrete";
  std::string default_shoulder = "grass";
  /// The map's position_sigma_m when the file's `mapnav` member gives none, m (>= 0): centre lines
  /// drawn over aerial imagery (kGeoJsonPositionSigmaM). A feature's `position_sigma_m` is its road's.
  double position_sigma_m = kGeoJsonPositionSigmaM;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// GeoJsonImportOptions' fields but the origin, with their rules.
const OptionTable<GeoJsonImportOptions>& geoJsonImportOptionTable();

/// What an import gives: the map, and for each road, intersection and landmark the JSON Pointer of
/// the feature it came from, so that validation issues point into the GeoJSON file.
struct GeoJsonImport {
  MapData map;
  std::vector<std::string> road_features;          ///< "/features/7" for roads[i]
  std::vector<std::string> intersection_features;  ///< "" for an intersection made at shared ends
  std::vector<std::string> landmark_features;      ///< for landmarks[i]: a Point with a `landmark` property
  /// What the import assumed, for people ("12 roads without a width: 7 m (the default width)"):
  /// defaults taken, ids from names, lines cut where they meet, intersections made.
  std::vector<std::string> assumptions;

  /// A pointer into the map ("/roads/3/width") as a pointer into the GeoJSON file
  /// ("/features/7/properties/width"; a landmark's "kind" is its feature's "properties/landmark");
  /// the input when it cannot be translated.
  std::string toFeaturePointer(const std::string& map_pointer) const;
};

/// The structure pass on GeoJSON text: nothing (and issues) when it is not a FeatureCollection
/// mapnav can read. Validate the result with validateMap().
std::optional<GeoJsonImport> importGeoJson(std::string_view text, Issues& issues,
                                           const GeoJsonImportOptions& options = {});

/// The map as a FeatureCollection in lon/lat (9 decimals): intersections, roads, then landmarks
/// (Point features with a `landmark` property), with a `mapnav` foreign member holding name, origin
/// and surfaces. Throws InvalidInput when neither `origin` nor the map has an origin.
std::string exportGeoJson(const MapData& map, const std::optional<GeoOrigin>& origin = std::nullopt);

/// Both passes on a map file in either format: GeoJSON when `geojson` options are given or the
/// extension is `.geojson` (importGeoJson, its issues' pointers translated into the GeoJSON file),
/// else mapnav-map/1 JSON. Appends every issue, warnings too, to `issues`; nothing when there is an
/// error. Throws IoError when the file cannot be read. What `mapnav map validate`, every command
/// that takes --map and the Python module's Map.load read with.
std::optional<Map> readMapFile(const std::filesystem::path& path, Issues& issues,
                               const std::optional<GeoJsonImportOptions>& geojson = std::nullopt);

/// The surfaces used when a GeoJSON file carries none (concrete, asphalt, brick, gravel, grass, dirt).
std::vector<std::pair<std::string, Appearance>> standardSurfaces();

}  // namespace mapnav
