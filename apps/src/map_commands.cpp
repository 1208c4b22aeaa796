#include "map_commands.h"

#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <ostream>
#include <sstream>

#include "cli.h"
#include "command_support.h"
#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/map/geojson.h"
#include "mapnav/map/info.h"
#include "mapnav/map/map_io.h"
#include "mapnav/map/map_render.h"
#include "mapnav/map/validation.h"
#include "mapnav/osm/osm_import.h"

namespace mapnav::cli {


GeoOrigin parseOrigin(const std::string& text) {
  const std::vector<double> values = parseNumbers("--origin", text, 2, 3, "LAT,LON or LAT,LON,ALT (degrees, metres)");
  if (std::abs(values[0]) > 90 || std::abs(values[1]) > 180) {
    throw InvalidInput("--origin \"" + text + "\": latitude must be in [-90, 90] and longitude in [-180, 180]");
  }
  return GeoOrigin{values[0], values[1], values.size() == 3 ? values[2] : 0.0};
}

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
      const bool valid = readAndValidate(file, issues).has_value();
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
    MapRenderOptions options;
    options.width_px = config.width_px;
    options.labels = config.labels;
    const MapPicture picture = renderMap(map, options);
    picture.canvas.save(config.output);
    out << "wrote " << config.output << " (" << picture.canvas.width() << "×" << picture.canvas.height() << " px, "
        << picture.view.pixelsPerMetre() << " px/m)\n";
    return static_cast<int>(kOk);
  });
}

int runImportGeoJson(const ImportGeoJsonConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    GeoJsonImportOptions options;
    options.origin = config.origin;
    options.snap_tolerance_m = config.snap_tolerance_m;
    Issues issues;
    const std::string text = readFile(config.input);
    auto imported = importGeoJson(text, issues, options);
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
        << imported->map.roads.size() << " roads)\n";
    return static_cast<int>(kOk);
  });
}

int runImportOsm(const ImportOsmConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    OsmImportOptions options;
    options.bbox = config.bbox;
    if (config.highways) {
      options.highways.clear();
      std::stringstream list(*config.highways);
      for (std::string h; std::getline(list, h, ',');) {
        if (!h.empty()) options.highways.push_back(h);
      }
    }
    options.origin = config.origin;
    options.repair = config.repair;
    if (config.name) options.name = *config.name;
    const OsmImport imported = importOsm(config.input, options);
    const OsmImportReport& report = imported.report;
    out << config.input << ": " << report.nodes_read << " nodes, " << report.ways_read << " ways; kept "
        << report.ways_kept << " ways\n";
    printIssues(report.issues, config.input, err);
    for (const std::string& repair : report.repairs) out << "repair: " << repair << "\n";
    const Issues issues = validateMap(imported.map);
    printIssues(issues, config.output, err);
    if (hasErrors(issues)) {
      err << "mapnav: error: " << config.input << ": the imported map is invalid (" << countSeverity(issues, Severity::Error)
          << " errors" << (config.repair ? "" : "; --repair may fix them") << "); nothing written\n";
      return static_cast<int>(kInvalid);
    }
    saveMap(imported.map, config.output);
    out << "wrote " << config.output << " (" << imported.map.intersections.size() << " intersections, "
        << imported.map.roads.size() << " roads; " << report.repairs.size() << " repairs, "
        << countSeverity(report.issues, Severity::Warning) << " data warnings, "
        << countSeverity(issues, Severity::Warning) << " map warnings)\n";
    return static_cast<int>(kOk);
  });
}

int runExportGeoJson(const ExportGeoJsonConfig& config, std::ostream& out, std::ostream& err) {
  return withMap(config.input, err, [&](const Map& map) {
    writeFileAtomic(config.output, exportGeoJson(map.data(), config.origin));
    out << "wrote " << config.output << " (" << map.intersections().size() + map.roads().size() << " features)\n";
    return static_cast<int>(kOk);
  });
}

}  // namespace mapnav::cli
