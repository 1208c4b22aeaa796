#include "route_command.h"

#include <filesystem>
#include <ostream>
#include <string>

#include "cli.h"
#include "command_line.h"
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

void registerRouteCommand(CLI::App& app, Commands& commands) {
  auto* route = commands.hold<RouteConfig>();
  struct Texts {
    std::string from, to, block;
  };
  auto* text = commands.hold<Texts>();
  CLI::App* rt = app.add_subcommand("route", "Plan a route between two road positions and say it as motion commands");
  rt->add_option("--map", route->map, "Map file")->required()->check(CLI::ExistingFile);
  rt->add_option("--from", text->from, "Start: ROAD@NODE+METERS, e.g. R1@I1+3")->required();
  rt->add_option("--to", text->to, "Goal: ROAD@NODE+METERS, e.g. R3@I3+2")->required();
  rt->add_option("--block", text->block, "Roads and intersections not to use, comma-separated: R2,I5");
  rt->add_flag("--json", route->json, "Print the route as JSON instead of the dialogue");
  rt->add_option("-o,--output", route->output, "Also draw the route on the map (OUT.png, OUT.svg) or write it as OUT.geojson")
      ->check(outputFile(true));
  rt->footer("Cost = length x the road's cost_factor + a turn penalty by angle. Exit codes: 0 a route, 1 no route\n"
             "(the reason is printed) or an invalid map or position, 2 usage or I/O error.");
  rt->callback(commands.choose([route, text](std::ostream& out, std::ostream& err) {
    route->from = parseRoadPosition(text->from);
    route->to = parseRoadPosition(text->to);
    for (const std::string& id : splitNames(text->block)) route->blocked.push_back(id);
    return runRoute(*route, out, err);
  }));
}

}  // namespace mapnav::cli
