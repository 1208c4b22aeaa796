// The top of the `mapnav` command line: the application, its registrars (one per command group,
// command_line.h) and the exit codes of CLI11's parse errors (a command's own errors: guarded()).
#include "cli.h"

#include <ostream>
#include <string>

#include "command_line.h"

namespace mapnav::cli {

int run(int argc, char** argv, std::ostream& out, std::ostream& err) {
  CLI::App app{"mapnav: map-based navigation of small vehicles on sidewalks and park paths with one camera.\n"
               "Author and check sidewalk maps, predict views, plan routes and run missions."};
  app.name("mapnav");
  const std::string version = std::string("mapnav ") + MAPNAV_VERSION;
  app.set_version_flag("--version", version);
  app.require_subcommand(1);
  app.footer("Run `mapnav COMMAND --help` for a command's options.");

  Commands commands;
  registerMapCommands(app, commands);
  registerPredictCommand(app, commands);
  registerRouteCommand(app, commands);
  registerSimulateCommand(app, commands);
  registerLogCommands(app, commands);
  registerMissionCommands(app, commands);
  registerPipelinesCommand(app, commands);
  registerOptionsCommand(app, commands);
  registerDetectCommands(app, commands);
  registerVisionCommands(app, commands);
  registerEvalCommands(app, commands);
#ifdef MAPNAV_HAVE_LEARNED
  registerTrainCommand(app, commands);
#endif
  registerBenchCommand(app, commands);
  registerSuiteCommand(app, commands);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    out << app.help();
    return kOk;
  } catch (const CLI::CallForAllHelp&) {
    out << app.help("", CLI::AppFormatMode::All);
    return kOk;
  } catch (const CLI::CallForVersion&) {
    out << version << "\n";
    return kOk;
  } catch (const CLI::ParseError& e) {
    err << "mapnav: error: " << e.what() << "\n";
    if (dynamic_cast<const CLI::ValidationError*>(&e) != nullptr && commands.valueRejected()) {
      return kInvalid;  // a value out of its range, a name not among the known: wrong input
    }
    err << "Run with --help for more information.\n";
    return kUsage;
  }
  return commands.run(out, err);
}

}  // namespace mapnav::cli
