#include "pipelines_command.h"

#include <ostream>

#include "cli.h"
#include "command_support.h"
#include "mapnav/vision/pipelines.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav::cli {

void loadPlugins(const std::vector<std::string>& plugins) {
  registerBuiltinPipelines();
  for (const std::string& plugin : plugins) loadPlugin(plugin);
}

int runPipelines(const PipelinesConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    loadPlugins(config.plugins);
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

}  // namespace mapnav::cli
