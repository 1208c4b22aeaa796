#pragma once
// The learned segmentation module (libmapnav_learned.so) opened when a program needs it: the CLI and
// the Python module link only this Torch-free part (mapnav_learned_options); Torch takes about half
// a second to load and initialise, which every command would pay.
#include <string>

namespace mapnav {

struct LearnedApi;  // learned_api.h

/// Whether this build has the module (MAPNAV_LEARNED and Debian's libtorch-dev).
bool learnedModuleBuilt();

/// Opens the module on the first call (it registers the "learned" pipeline) and returns its API. It
/// is looked for beside this library, then in the program's ../lib and ../<libdir> (build and
/// installed trees). Throws NotFound when the build has none, IoError naming the places looked in
/// when it is not installed or cannot be loaded.
const LearnedApi& learnedModule();

/// Opens the module when `pipeline` is "learned" and the build has it; nothing for any other name.
void loadPipelineModule(const std::string& pipeline);

}  // namespace mapnav
