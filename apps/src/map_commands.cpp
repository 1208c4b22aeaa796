#include "map_commands.h"

#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <ostream>

#include "cli.h"
#include "command_line.h"
#include "command_support.h"
#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/map/geojson.h"
#include "mapnav/map/info.h"
#include "mapnav/map/map_io.h"
#include "mapnav/map/map_render.h"
#include "mapnav/map/validation.h"
#include "mapnav/osm/osm_import.h"

namespace mapnav::cli {


std::array<double, 4> parseBbox(const std::string& text) {
  const std::vector<double> b = parseNumbers("--bbox", text, 4, 4, "W,S,E,N (degrees)");
  if (!(b[0] < b[2] && b[1] < b[3] && b[0] >= -180 && b[2] <= 180 && b[1] >= -90 && b[3] <= 90)) {
    throw InvalidInput("--bbox \"" + text + "\": expected west < east in [-180, 180] and south < north in [-90, 90]");
  }
  return {b[0], b[1], b[2], b[3]};
}

int runValidate(const ValidateConfig& config, std::ostream& out, std::ostream& err) {
  int worst = kOk;
  for (const std::string& file : config.files) {
    const int code = guarded(err, [&] {
      Issues issues;
      const bool valid = readMapFile(file, issues).has_value();
      printIssues(issues, file, out);
      if (!config.quiet) {
        const auto errors = countSeverity(issues, Severity::Error), warnings = countSeverity(issues, Severity::Warning);
        out << file << ": " << (valid ? "valid" : "invalid") << " (" << errors << " errors, " << warnings
            << " warnings)\n";
      }
      return static_cast<int>(valid ? kOk : kInvalid);
    });
    worst = std::max(worst, code);
  }
  return worst;
}

int runInfo(const InfoConfig& config, std::ostream& out, std::ostream& err) {
  return withMap(config.file, err, [&](const Map& map) {
    const MapInfo info = describeMap(map);
    out << (config.json ? toJson(info) : toText(info));
    return static_cast<int>(kOk);
  });
}

int runRender(const RenderConfig& config, std::ostream& out, std::ostream& err) {
  return withMap(config.file, err, [&](const Map& map) {
    const MapPicture picture = renderMap(map, config.options);
    picture.canvas.save(config.output);
    out << "wrote " << config.output << " (" << picture.canvas.width() << "×" << picture.canvas.height() << " px, "
        << picture.view.pixelsPerMetre() << " px/m)\n";
    return static_cast<int>(kOk);
  });
}

int runImportGeoJson(const ImportGeoJsonConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    Issues issues;
    const std::string text = readFile(config.input);
    auto imported = importGeoJson(text, issues, config.options);
    if (imported) {
      if (config.name) imported->map.name = *config.name;
      for (Issue issue : validateMap(imported->map)) {
        issue.where = imported->toFeaturePointer(issue.where);
        issues.push_back(std::move(issue));
      }
    }
    printIssues(issues, config.input, err);
    if (!imported || hasErrors(issues)) {
      err << "mapnav: error: " << config.input << ": cannot import (" << countSeverity(issues, Severity::Error)
          << " errors); nothing written\n";
      return static_cast<int>(kInvalid);
    }
    saveMap(imported->map, config.output);
    out << "wrote " << config.output << " (" << imported->map.intersections.size() << " intersections, "
        << imported->map.roads.size() << " roads, " << imported->map.landmarks.size() << " landmarks)\n";
    for (const std::string& a : imported->assumptions) out << "  assumed: " << a << "\n";
    return static_cast<int>(kOk);
  });
}

// "; --repair may fix the 3 roads.crossing_without_intersection" — only the errors it can repair
// ("" when there are none).
static std::string repairHint(const Issues& issues) {
  std::map<std::string, int> fixable;
  for (const Issue& issue : issues) {
    if (issue.severity == Severity::Error && osmRepairCanFix(issue.check)) ++fixable[issue.check];
  }
  std::string hint;
  for (const auto& [check, count] : fixable) hint += (hint.empty() ? "" : ", ") + std::to_string(count) + " " + check;
  return hint.empty() ? hint : "; --repair may fix the " + hint;
}

// "landmarks: 48 found, 39 kept (9 farther than 10 m from every road dropped; --keep-far-landmarks keeps them)"
static std::string landmarksLine(const OsmImportReport& report, const OsmImportOptions& options) {
  const std::size_t far = report.landmarks_far;
  const std::size_t kept = options.keep_far_landmarks ? report.landmarks_found : report.landmarks_found - far;
  std::string line = "landmarks: " + std::to_string(report.landmarks_found) + " found, " + std::to_string(kept) + " kept";
  if (far > 0) {
    line += " (" + std::to_string(far) + " farther than " + strprintf("%g", options.max_landmark_distance_m) +
            " m from every road " +
            (options.keep_far_landmarks ? "kept too)" : "dropped; --keep-far-landmarks keeps them)");
  }
  return line + "\n";
}

int runImportOsm(const ImportOsmConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    OsmImportOptions options = config.options;
    if (config.highways) options.highways = splitNames(*config.highways);
    const OsmImport imported = importOsm(config.input, options);
    const OsmImportReport& report = imported.report;
    out << config.input << ": " << report.nodes_read << " nodes, " << report.ways_read << " ways; kept "
        << report.ways_kept << " ways\n";
    if (report.landmarks_found > 0) out << landmarksLine(report, options);
    printIssues(report.issues, config.input, err);
    for (const std::string& repair : report.repairs) out << "repair: " << repair << "\n";
    const Issues issues = validateMap(imported.map);
    printIssues(issues, config.output, err);
    if (hasErrors(issues)) {
      err << "mapnav: error: " << config.input << ": the imported map is invalid (" << countSeverity(issues, Severity::Error)
          << " errors" << (options.repair ? "" : repairHint(issues)) << "); nothing written\n";
      return static_cast<int>(kInvalid);
    }
    saveMap(imported.map, config.output);
    out << "wrote " << config.output << " (" << imported.map.intersections.size() << " intersections, "
        << imported.map.roads.size() << " roads, " << imported.map.landmarks.size() << " landmarks; "
        << report.repairs.size() << " repairs, "
        << countSeverity(report.issues, Severity::Warning) << " data warnings, "
        << countSeverity(issues, Severity::Warning) << " map warnings)\n";
    return static_cast<int>(kOk);
  });
}

int runExportGeoJson(const ExportGeoJsonConfig& config, std::ostream& out, std::ostream& err) {
  return withMap(config.input, err, [&](const Map& map) {
    if (!config.origin && !map.data().origin)
      throw InvalidInput("map \"" + map.data().name + "\" has no geodetic origin: give one with --origin LAT,LON to export GeoJSON");
    writeFileAtomic(config.output, exportGeoJson(map.data(), config.origin));
    out << "wrote " << config.output << " ("
        << map.intersections().size() + map.roads().size() + map.landmarks().size() << " features)\n";
    return static_cast<int>(kOk);
  });
}

// ---- the command line: `mapnav map ...` -------------------------------------------------------

namespace {

constexpr const char* kMapFooter = R"(Map files are mapnav-map/1 JSON (docs/map-format.md) or, where a command says so,
GeoJSON from QGIS or geojson.io. Exit codes: 0 success, 1 the input is wrong (an invalid map),
2 usage or I/O error.)";

void addOrigin(CLI::App* command, std::string& text) {
  command->add_option("--origin", text,
                      "Geodetic origin of the local frame as LAT,LON or LAT,LON,ALT (degrees, metres)");
}

void addValidate(CLI::App& map, Commands& commands) {
  auto* validate = commands.hold<ValidateConfig>();
  CLI::App* v = map.add_subcommand("validate", "Check map files and report every problem as FILE:/pointer: severity: check: message");
  v->add_option("files", validate->files, "Map files (.json, or .geojson)")->required()->check(CLI::ExistingFile);
  v->add_flag("-q,--quiet", validate->quiet, "Print only the problems, not a summary line per file");
  v->footer("Exit code 0 when every file is valid (warnings allowed), 1 when any has an error, 2 when a file cannot be read.");
  v->callback(commands.choose([validate](std::ostream& out, std::ostream& err) { return runValidate(*validate, out, err); }));
}

void addInfo(CLI::App& map, Commands& commands) {
  auto* info = commands.hold<InfoConfig>();
  CLI::App* i = map.add_subcommand("info", "Summarise a map: counts by kind, total length, bounds, components");
  i->add_option("file", info->file, "Map file")->required()->check(CLI::ExistingFile);
  i->add_flag("--json", info->json, "Print one JSON object instead of text");
  i->callback(commands.choose([info](std::ostream& out, std::ostream& err) { return runInfo(*info, out, err); }));
}

void addRender(CLI::App& map, Commands& commands) {
  auto* render = commands.hold<RenderConfig>();
  auto* no_labels = commands.hold<bool>();
  CLI::App* r = map.add_subcommand("render", "Draw a map as PNG or SVG: roads in their surface colours, ids, scale bar, north arrow");
  r->add_option("file", render->file, "Map file")->required()->check(CLI::ExistingFile);
  r->add_option("-o,--output", render->output, "Picture to write: OUT.png or OUT.svg")
      ->required()
      ->check(outputFile(false));
  r->add_option("--width", render->options.width_px, "Picture width in pixels; the height follows the map")
      ->capture_default_str()
      ->check(commands.ruleCheck(mapRenderOptionTable(), "width_px"));
  r->add_flag("--no-labels", *no_labels, "Leave out road and intersection ids");
  r->callback(commands.choose([render, no_labels](std::ostream& out, std::ostream& err) {
    render->options.labels = !*no_labels;
    return runRender(*render, out, err);
  }));
}

void addImportGeoJson(CLI::App& map, Commands& commands) {
  auto* import = commands.hold<ImportGeoJsonConfig>();
  auto* origin = commands.hold<std::string>();
  CLI::App* im = map.add_subcommand(
      "import-geojson", "Convert GeoJSON (LineString roads, Point/Polygon intersections, Point landmarks) to a mapnav map");
  im->add_option("input", import->input, "GeoJSON FeatureCollection in lon/lat")->required()->check(CLI::ExistingFile);
  im->add_option("-o,--output", import->output, "mapnav-map/1 JSON to write (only when the import is valid)")->required();
  addOrigin(im, *origin);
  im->add_option("--snap", import->options.snap_tolerance_m, "Road ends this close (m) to an intersection or to each other share it")
      ->capture_default_str()
      ->check(commands.ruleCheck(geoJsonImportOptionTable(), "snap_tolerance_m"));
  im->add_option("--default-width", import->options.default_width_m,
                 "Width (m) of the roads whose features give none, e.g. a street's carriageway from centre lines")
      ->capture_default_str()
      ->check(commands.ruleCheck(geoJsonImportOptionTable(), "default_width_m"));
  im->add_option("--default-surface", import->options.default_surface,
                 "Surface of the roads whose features give none (the map's surfaces: concrete, asphalt, brick, gravel, "
                 "grass, dirt)")
      ->capture_default_str();
  im->add_option("--position-sigma", import->options.position_sigma_m,
                 "How well the roads are placed in the world, 1-sigma per axis (m), when the file's mapnav member does "
                 "not say: the pose filter takes the map's error into account (0: exact, a survey)")
      ->capture_default_str()
      ->check(commands.ruleCheck(geoJsonImportOptionTable(), "position_sigma_m"));
  im->add_option("--name", import->name, "The map's name (default: the file's, or \"imported from GeoJSON\")");
  im->footer("Without --origin, the origin is the file's mapnav.origin, else the centroid of its coordinates. Plain "
             "street centre lines (LineString or MultiLineString features with only a name, as OpenStreetMap extracts "
             "give them) import too: each part is a road named after its feature, cut where its vertices meet another "
             "line's (--snap), with the default width and surface; what was assumed is printed after the counts.");
  im->callback(commands.choose([import, origin](std::ostream& out, std::ostream& err) {
    if (!origin->empty()) import->options.origin = parseOrigin(*origin);
    return runImportGeoJson(*import, out, err);
  }));
}

void addImportOsm(CLI::App& map, Commands& commands) {
  auto* osm = commands.hold<ImportOsmConfig>();
  struct Texts {
    std::string origin, bbox;
  };
  auto* text = commands.hold<Texts>();
  CLI::App* io = map.add_subcommand("import-osm", "Convert OpenStreetMap data (walkable ways) to a mapnav map");
  io->add_option("input", osm->input, "OpenStreetMap file: .osm (XML), .osm.pbf, .osm.bz2")->required()->check(CLI::ExistingFile);
  io->add_option("-o,--output", osm->output, "mapnav-map/1 JSON to write (only when the imported map is valid)")->required();
  io->add_option("--bbox", text->bbox, "Keep only W,S,E,N (degrees); ways leaving it are cut at its border");
  const OsmImportOptions defaults;
  std::string highways, widths;
  for (const std::string& h : defaults.highways) {
    highways += (highways.empty() ? "" : ",") + h;
    widths += (widths.empty() ? "" : ", ") + h + " " + strprintf("%g", defaults.widths.at(h)) + " m";
  }
  io->add_option("--highways", osm->highways, "highway values kept, comma-separated (default " + highways + ")");
  addOrigin(io, text->origin);
  io->add_flag("--repair", osm->options.repair,
               "Merge nodes closer than " + strprintf("%g", defaults.merge_distance_m) +
                   " m, add an intersection where kept ways cross without a shared node, drop stubs and loops "
                   "shorter than " + strprintf("%g", defaults.min_piece_m) + " m; every repair is listed");
  io->add_flag("--keep-far-landmarks", osm->options.keep_far_landmarks,
               "Keep the landmarks (trees, street lamps, benches, bollards, manholes) farther than " +
                   strprintf("%g", defaults.max_landmark_distance_m) +
                   " m from every imported road; by default they are dropped and counted");
  io->add_option("--name", osm->options.name, "The map's name (default: \"imported from FILE\")");
  io->add_option("--position-sigma", osm->options.position_sigma_m,
                 "How well OSM places the ways in the world, 1-sigma per axis (m): the pose filter takes the map's "
                 "error into account")
      ->capture_default_str()
      ->check(commands.ruleCheck(osmImportOptionTable(), "position_sigma_m"));
  io->footer(
      "Ways are split at every node two kept ways share; those nodes and way ends become intersections (id n<node>, "
      "x<k> for one --repair added), roads are w<way> or w<way>-<k>, with the OSM ids in their properties. Widths "
      "from `width` or per highway (" + widths + "), surfaces from `surface`, " + defaults.shoulder +
      " shoulders, steps with route cost factor " + strprintf("%g", defaults.steps_cost_factor) +
      ". Nodes tagged natural=tree, highway=street_lamp, "
      "amenity=bench, barrier=bollard, man_made=manhole or manhole=* become landmarks (size from circumference and "
      "height when given). Without --origin the origin is the centre of the kept data. Data problems are reported "
      "as warnings (where = way/ID or node/ID); nothing is written when the map is invalid.");
  io->callback(commands.choose([osm, text](std::ostream& out, std::ostream& err) {
    if (!text->origin.empty()) osm->options.origin = parseOrigin(text->origin);
    if (!text->bbox.empty()) osm->options.bbox = parseBbox(text->bbox);
    return runImportOsm(*osm, out, err);
  }));
}

void addExportGeoJson(CLI::App& map, Commands& commands) {
  auto* exp = commands.hold<ExportGeoJsonConfig>();
  auto* origin = commands.hold<std::string>();
  CLI::App* ex = map.add_subcommand("export-geojson", "Write a map as GeoJSON in lon/lat, for QGIS");
  ex->add_option("input", exp->input, "Map file")->required()->check(CLI::ExistingFile);
  ex->add_option("-o,--output", exp->output, "GeoJSON file to write")->required();
  addOrigin(ex, *origin);
  ex->footer("The map's own origin is used unless --origin is given; a map without one needs --origin.");
  ex->callback(commands.choose([exp, origin](std::ostream& out, std::ostream& err) {
    if (!origin->empty()) exp->origin = parseOrigin(*origin);
    return runExportGeoJson(*exp, out, err);
  }));
}

}  // namespace

void registerMapCommands(CLI::App& app, Commands& commands) {
  CLI::App* map = app.add_subcommand("map", "Validate, inspect, draw and convert sidewalk maps");
  map->require_subcommand(1);
  map->footer(kMapFooter);
  addValidate(*map, commands);
  addInfo(*map, commands);
  addRender(*map, commands);
  addImportGeoJson(*map, commands);
  addImportOsm(*map, commands);
  addExportGeoJson(*map, commands);
}

}  // namespace mapnav::cli
