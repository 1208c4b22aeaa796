#pragma once
// The learned segmentation module (learned/, libmapnav_learned.so) opened when a command needs it
// (internal to apps/). The CLI does not link it: Torch takes about half a second to load and
// initialise, which every command would pay.
#include <string>

namespace mapnav {
struct LearnedApi;  // mapnav/learned/learned_api.h, where the build has learned/
}  // namespace mapnav

namespace mapnav::cli {

/// Whether this build has the module (MAPNAV_LEARNED).
bool learnedModuleBuilt();

/// Opens the module beside the program's libraries on the first call (it registers "learned") and
/// returns its API. Throws NotFound when the build has none, IoError when it cannot be loaded.
const LearnedApi& learnedModule();

/// Opens the module when `pipeline` is "learned" and the build has it; nothing for any other name.
void loadPipelineModule(const std::string& pipeline);

}  // namespace mapnav::cli
