#include "mapnav/mission/pipeline_choice.h"

#include <algorithm>
#include <utility>

#include "mapnav/core/error.h"

namespace mapnav {

std::string pipelineForSurface(const std::string& surface) {
  if (surface == "concrete" || surface == "brick") return "sidewalk";
  if (surface == "asphalt" || surface == "gravel") return "color-rgb";
  if (surface == "dirt") return "edge-tracker";
  return "";
}

std::string pipelineForRoads(const Map& map, const std::vector<std::string>& roads, const std::string& what) {
  // The route's surfaces in the order it first drives on them, each with its roads.
  std::vector<std::pair<std::string, std::vector<std::string>>> surfaces;
  for (const std::string& id : roads) {
    const std::string& surface = map.road(id).surface;
    auto it = std::find_if(surfaces.begin(), surfaces.end(), [&](const auto& s) { return s.first == surface; });
    if (it == surfaces.end()) it = surfaces.insert(surfaces.end(), {surface, {}});
    if (std::find(it->second.begin(), it->second.end(), id) == it->second.end()) it->second.push_back(id);
  }
  if (surfaces.empty()) throw NoPipelineChosen(what + ": names no vision pipeline and drives on no road to choose one by");
  const std::string first = pipelineForSurface(surfaces.front().first);
  const bool decided = !first.empty() && std::all_of(surfaces.begin(), surfaces.end(), [&](const auto& s) {
    return pipelineForSurface(s.first) == first;
  });
  if (decided) return first;
  // Paved surfaces of both families: the sidewalk pipeline keeps a road class per surface in view
  // and follows each at its defaults (pipelineForRoads' measurements).
  const bool paved = std::all_of(surfaces.begin(), surfaces.end(), [](const auto& s) {
    const std::string p = pipelineForSurface(s.first);
    return p == "sidewalk" || p == "color-rgb";
  });
  if (paved) return "sidewalk";
  std::string said;
  for (const auto& [surface, ids] : surfaces) {
    std::string list;
    for (const std::string& id : ids) list += (list.empty() ? "" : ", ") + id;
    const std::string pipeline = pipelineForSurface(surface);
    said += (said.empty() ? "" : "; ") + surface + " (" + list + ") " +
            (pipeline.empty() ? "calls for no pipeline known to follow it" : "calls for " + pipeline);
  }
  throw NoPipelineChosen(what + ": names no vision pipeline, and the surfaces of the roads its route drives do not decide one: " +
                         said + ". Name the pipeline in the mission, \"vision\": {\"pipeline\": \"NAME\"}, or for the run " +
                         "(`mapnav pipelines` lists them)");
}

}  // namespace mapnav
