#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>

#include "mapnav/core/error.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {

double pixelScale(int width, int height) {
  if (width <= 0 || height <= 0) return 1.0;
  return std::min(1.0, std::sqrt(static_cast<double>(width) * height / kReferenceFramePixels));
}

namespace {

struct Registry {
  std::mutex mutex;
  std::map<std::string, PipelineInfo> pipelines;
  std::vector<std::string> order;  // registration order: built-ins first, then plug-ins
  LandmarkFinder landmark_finder;
  StepMeasurer step_measurer;
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

void registerPipeline(PipelineInfo info) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  if (!r.pipelines.contains(info.name)) r.order.push_back(info.name);
  r.pipelines[info.name] = std::move(info);
}

namespace {

// The steps the Vision module runs after every pipeline (the landmark finder, the step measurer).
template <class Hook>
void setHook(Hook Registry::*member, Hook hook) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  r.*member = std::move(hook);
}

template <class Hook>
Hook getHook(Hook Registry::*member) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  return r.*member;
}

}  // namespace

void registerLandmarkFinder(LandmarkFinder finder) { setHook(&Registry::landmark_finder, std::move(finder)); }
LandmarkFinder landmarkFinder() { return getHook(&Registry::landmark_finder); }
void registerStepMeasurer(StepMeasurer measurer) { setHook(&Registry::step_measurer, std::move(measurer)); }
StepMeasurer stepMeasurer() { return getHook(&Registry::step_measurer); }

std::vector<PipelineInfo> listPipelines() {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  std::vector<PipelineInfo> out;
  for (const std::string& name : r.order) out.push_back(r.pipelines.at(name));
  return out;
}

std::unique_ptr<VisionPipeline> createPipeline(const std::string& name, const std::string& options_json) {
  std::function<std::unique_ptr<VisionPipeline>()> create;
  {
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    const auto it = r.pipelines.find(name);
    if (it == r.pipelines.end()) {
      std::string names;
      for (const std::string& n : r.order) names += (names.empty() ? "" : ", ") + n;
      throw NotFound("no vision pipeline \"" + name + "\" (available: " + (names.empty() ? "none" : names) + ")");
    }
    create = it->second.create;
  }
  std::unique_ptr<VisionPipeline> pipeline = create();
  pipeline->configure(options_json);
  return pipeline;
}

int loadPlugin(const std::string& path) {
  // RTLD_NOW: an unresolved symbol is an error here, not a crash later.
  void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* why = ::dlerror();
    throw IoError(path + ": cannot load plug-in: " + (why ? why : "unknown error"));
  }
  using Entry = int (*)();
  auto entry = reinterpret_cast<Entry>(::dlsym(handle, "mapnav_register_pipelines"));
  if (entry == nullptr) {
    ::dlclose(handle);
    throw InvalidInput(path + ": not a mapnav plug-in (no extern \"C\" mapnav_register_pipelines)");
  }
  // The library stays loaded: its pipelines' code lives there.
  return entry();
}

}  // namespace mapnav
