#include "route_command.h"

#include <filesystem>
#include <ostream>

#include "cli.h"
#include "command_support.h"
#include "mapnav/core/io.h"
#include "mapnav/navigator/route.h"
#include "mapnav/navigator/route_output.h"

namespace mapnav::cli {

int runRoute(const RouteConfig& config, std::ostream& out, std::ostream& err) {
  return withMap(config.map, err, [&](const Map& map) {
    RoadGraph graph(map);
    RouteOptions options;
    options.blocked = config.blocked;
    const RouteResult result = graph.route(config.from, config.to, options);
    if (!result.route) {
      err << "mapnav: error: no route: " << result.reason << "\n";
      return static_cast<int>(kInvalid);
    }
    const Route& route = *result.route;
    if (!config.output.empty()) {
      if (std::filesystem::path(config.output).extension() == ".geojson") {
        writeFileAtomic(config.output, routeToGeoJson(map, route));
      } else {
        renderRoute(map, route).save(config.output);
      }
    }
    if (config.json) {
      out << toJson(route);
    } else {
      out << toDialogue(route);
      char line[120];
      std::snprintf(line, sizeof line, "(%.1f m, %zu intersections)\n", route.length_m, route.intersections.size());
      out << line;
      if (!config.output.empty()) out << "wrote " << config.output << "\n";
    }
    return static_cast<int>(kOk);
  });
}

}  // namespace mapnav::cli
