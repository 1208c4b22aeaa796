#pragma once
// OpenStreetMap → mapnav map: the walkable ways of an OSM file become roads, split at
// every node that two or more kept ways share; those nodes and the way ends become intersections,
// whose kind is inferred from the number of roads and their angles. libosmium reads the file and
// GeographicLib projects it (LocalCartesian); both stay inside this module's .cpp.
//
// Real OSM data is messy. Without `repair` the import only reports what it finds (duplicate nodes,
// ways that cross without a shared node, tiny pieces, steps, missing nodes) and map validation says
// what that means for the map; with `repair` it merges near-coincident nodes, adds an intersection
// where two kept ways cross, and drops degenerate pieces, and lists each repair.
//
// Trees, street lamps, benches, bollards and manholes tagged on nodes become the map's landmarks,
// those beside the imported roads.
#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mapnav/core/issue.h"
#include "mapnav/core/option_table.h"
#include "mapnav/map/map.h"

namespace mapnav {

struct OsmImportOptions {
  /// The `highway` values kept (walkable ways). Default: footway, path, pedestrian, steps, cycleway.
  std::vector<std::string> highways = {"footway", "path", "pedestrian", "steps", "cycleway"};
  /// Keep only what lies inside {west, south, east, north} (degrees); a way leaving the box is cut
  /// where it leaves. Nothing: everything in the file.
  std::optional<std::array<double, 4>> bbox;
  /// The local frame's origin. Nothing: the centre of the kept nodes' lat/lon bounding box.
  std::optional<GeoOrigin> origin;
  /// Paved width (m, > 0) by `highway` value when the way has no usable `width` tag; highways not
  /// listed get `default_width_m`.
  std::map<std::string, double> widths = {{"footway", 2.0}, {"path", 1.5},     {"pedestrian", 4.0},
                                          {"steps", 2.0},   {"cycleway", 2.0}, {"service", 4.0}};
  double default_width_m = 2.0;
  /// The shoulder surface on both sides (OSM does not say): one of standardSurfaces().
  std::string shoulder = "grass";
  /// Route cost factor of steps (>= 1): a small vehicle avoids them unless there is no other way.
  double steps_cost_factor = 20.0;
  /// Repair the data (below) instead of only reporting it.
  bool repair = false;
  /// Repair: nodes of kept ways closer than this (m, >= 0) become one node.
  double merge_distance_m = 0.5;
  /// A piece shorter than this (m, >= 0) is reported as tiny; with repair, a tiny piece that ends
  /// in nothing (a stub) or joins a node to itself is dropped.
  double min_piece_m = 1.0;
  /// Landmarks come from nodes tagged natural=tree, highway=street_lamp, amenity=bench,
  /// barrier=bollard, man_made=manhole or manhole=*. One farther than this (m, >= 0) from the paved
  /// area of every imported road is dropped: a vehicle on the roads could hardly see it (as
  /// ValidationOptions::max_landmark_distance_m, whose warning it would get).
  double max_landmark_distance_m = 10.0;
  /// Keep the landmarks farther than max_landmark_distance_m from every road too.
  bool keep_far_landmarks = false;
  /// The map's name ("" : "imported from <file name>").
  std::string name;
  /// The map's position_sigma_m, m (>= 0): how well OSM places its ways (kOsmPositionSigmaM).
  double position_sigma_m = kOsmPositionSigmaM;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// OsmImportOptions' fields that are values, with their rules (highways, bbox and widths are
/// checked by validate() itself; any origin goes).
const OptionTable<OsmImportOptions>& osmImportOptionTable();

/// What an import did, beside the map.
struct OsmImportReport {
  std::size_t nodes_read = 0, ways_read = 0;
  std::size_t ways_kept = 0;       ///< with a kept highway value, at least partly inside the bbox
  std::size_t landmarks_found = 0;  ///< nodes tagged as a landmark inside the bbox
  /// Of those, farther than max_landmark_distance_m from every road: dropped unless keep_far_landmarks.
  std::size_t landmarks_far = 0;
  std::vector<std::string> repairs;  ///< one line each: "merged node 123 into node 456 (0.21 m apart)"
  /// Data problems found, with the check name (osm.duplicate_node, osm.crossing_without_node,
  /// osm.tiny_piece, osm.steps, osm.missing_node, osm.area, osm.bad_width, osm.unknown_surface,
  /// osm.bad_size) and where = "way/123" or "node/456" (OSM's own element address). Warnings only:
  /// the map's own validation decides whether the result is usable.
  Issues issues;
};

struct OsmImport {
  MapData map;
  OsmImportReport report;
};

/// Reads `file` (.osm XML, .osm.pbf, .osm.bz2 ...: libosmium decides by the extension). Throws
/// IoError naming the file (and the line for malformed XML) when it cannot be read, InvalidInput
/// when nothing walkable is left. Validate the map with validateMap() / Map.
OsmImport importOsm(const std::filesystem::path& file, const OsmImportOptions& options = {});

/// Whether importing with `repair` can take away map validation errors of this check (the hint after
/// a failed import names only these): a crossing of two roads on the same layer, repeated points
/// and degenerate centre lines.
bool osmRepairCanFix(std::string_view check);

/// The intersection kind of a node from the headings (radians) of the roads leaving it: 1 road →
/// End; 2 → L when they turn by more than 30 degrees, else Other; 3 → T when two of them are within
/// 30 degrees of straight through, else Y; 4 → Cross when both pairs are, else Plaza; 5+ → Plaza.
IntersectionKind inferIntersectionKind(const std::vector<double>& headings);

}  // namespace mapnav
