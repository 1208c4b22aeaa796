#include "pipelines_command.h"

#include <ostream>

#include "cli.h"
#include "command_line.h"
#include "command_support.h"
#include "mapnav/learned/learned_module.h"
#include "mapnav/vision/pipelines.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav::cli {

void loadPlugins(const std::vector<std::string>& plugins, const std::string& pipeline) {
  registerBuiltinPipelines();
  loadPipelineModule(pipeline);
  for (const std::string& plugin : plugins) loadPlugin(plugin);
}

int runPipelines(const PipelinesConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    loadPlugins(config.plugins, "learned");  // every pipeline this build has, listed
    for (const PipelineInfo& info : listPipelines()) {
      if (config.names_only) {
        out << info.name << "\n";
        continue;
      }
      out << info.name << ": " << info.description << "\n";
      for (const OptionInfo& option : info.options) {
        out << "    " << option.name << " = " << option.default_json << "    " << option.description << "\n";
      }
      for (const OptionPreset& preset : info.presets) {
        out << "    preset " << preset.name << " = " << preset.json << "    " << preset.description << "\n";
      }
    }
    return static_cast<int>(kOk);
  });
}

void registerPipelinesCommand(CLI::App& app, Commands& commands) {
  auto* pipelines = commands.hold<PipelinesConfig>();
  CLI::App* pl = app.add_subcommand("pipelines", "List the vision pipelines available, with their options and defaults");
  pl->add_flag("--names", pipelines->names_only, "One name a line");
  pl->add_option("--plugin", pipelines->plugins, "Load a vision plug-in (a shared library; see examples/vision_plugin)");
  pl->callback(commands.choose([pipelines](std::ostream& out, std::ostream& err) { return runPipelines(*pipelines, out, err); }));
}

}  // namespace mapnav::cli
