#pragma once
#include <iosfwd>
#include <string>
#include <vector>

namespace mapnav::cli {

struct PipelinesConfig {
  bool names_only = false;             ///< one name a line
  std::vector<std::string> plugins;    ///< shared libraries to load first
};

/// Registers the built-in pipelines; "learned" too when `pipeline` names it and this build has it
/// (its module is opened only then: learned_module.h); then the plug-ins given with --plugin (every
/// command that takes a pipeline accepts them).
void loadPlugins(const std::vector<std::string>& plugins, const std::string& pipeline = "");

/// `mapnav pipelines`: the vision pipelines available, with their options and defaults.
int runPipelines(const PipelinesConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
