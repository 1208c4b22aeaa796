#include "mapnav/learned/learned_module.h"

#include <dlfcn.h>
#include <unistd.h>

#include <filesystem>
#include <mutex>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/vision_iface/pipeline.h"
#ifdef MAPNAV_LEARNED_MODULE
#include "mapnav/learned/learned_api.h"
#endif

namespace mapnav {

namespace fs = std::filesystem;

bool learnedModuleBuilt() {
#ifdef MAPNAV_LEARNED_MODULE
  return true;
#else
  return false;
#endif
}

#ifdef MAPNAV_LEARNED_MODULE
namespace {

// Beside this library (a shared build: the build tree's lib/, an installed tree's libdir), then
// beside the program (a static build, whose program holds this code).
std::vector<fs::path> placesToLook() {
  std::vector<fs::path> places;
  Dl_info info{};
  if (::dladdr(reinterpret_cast<void*>(&learnedModuleBuilt), &info) != 0 && info.dli_fname != nullptr)
    places.push_back(fs::path(info.dli_fname).parent_path() / MAPNAV_LEARNED_MODULE);
  char exe[4096];
  const ssize_t len = ::readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (len > 0) {
    const fs::path bin = fs::path(std::string(exe, static_cast<std::size_t>(len))).parent_path();
    places.push_back(bin / ".." / "lib" / MAPNAV_LEARNED_MODULE);
    places.push_back(bin / ".." / MAPNAV_INSTALL_LIBDIR / MAPNAV_LEARNED_MODULE);
  }
  return places;
}

}  // namespace
#endif

const LearnedApi& learnedModule() {
#ifndef MAPNAV_LEARNED_MODULE
  throw NotFound("this mapnav was built without the learned segmentation (libtorch-dev missing or MAPNAV_LEARNED=OFF)");
#else
  static std::mutex mutex;
  static const LearnedApi* api = nullptr;
  const std::lock_guard lock(mutex);
  if (api != nullptr) return *api;
  std::string tried;
  for (const fs::path& p : placesToLook()) {
    std::error_code ec;
    tried += (tried.empty() ? "" : ", ") + p.lexically_normal().string();
    if (!fs::exists(p, ec)) continue;
    loadPlugin(p.string());  // registers "learned"
    void* handle = ::dlopen(p.c_str(), RTLD_NOW | RTLD_NOLOAD);
    using Entry = const LearnedApi* (*)();
    const auto entry = handle != nullptr ? reinterpret_cast<Entry>(::dlsym(handle, kLearnedApiSymbol)) : nullptr;
    if (entry == nullptr) throw IoError(p.string() + ": not the learned module (no " + kLearnedApiSymbol + ")");
    api = entry();
    return *api;
  }
  throw IoError("the learned segmentation module is not installed (looked for " + tried + ")");
#endif
}

void loadPipelineModule(const std::string& pipeline) {
  if (pipeline == "learned" && learnedModuleBuilt()) learnedModule();
}

}  // namespace mapnav
