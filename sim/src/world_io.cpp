#include "mapnav/sim/world_io.h"

#include <optional>

#include "mapnav/core/json.h"

namespace mapnav {

namespace {

constexpr const char* kMapError = "map_error";

// The block's JSON and its `map_error` member apart (nullopt: the text is not a JSON object; its
// errors are the world table's to report).
struct Split {
  std::string world;
  std::optional<std::string> map_error;
};

std::optional<Split> split(const std::string& json) {
  Issues ignored;
  std::optional<Json> block = parseJson(json, ignored);
  if (!block || !block->is_object()) return std::nullopt;
  Split out;
  if (const auto it = block->find(kMapError); it != block->end()) {
    out.map_error = it->dump();
    block->erase(it);
  }
  out.world = block->dump();
  return out;
}

}  // namespace

WorldOptions parseWorldOptions(const std::string& json, const std::string& pointer, Issues& issues) {
  const std::optional<Split> parts = split(json);
  return worldOptionTable().read(parts ? parts->world : json, {}, pointer, issues);
}

MapErrorOptions parseMapErrorOptions(const std::string& json, const std::string& pointer, Issues& issues) {
  const std::optional<Split> parts = split(json);
  if (!parts || !parts->map_error) return {};
  return mapErrorOptionTable().read(*parts->map_error, {}, pointer + "/" + kMapError, issues);
}

}  // namespace mapnav
