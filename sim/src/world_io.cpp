#include "mapnav/sim/world_io.h"

#include <optional>

#include "mapnav/core/json.h"

namespace mapnav {

namespace {

// The objects of the block that other tables read (not WorldOptions').
constexpr const char* kMapError = "map_error";
constexpr const char* kGnss = "gnss";

// The block's JSON without its nested objects, and one of them (nullopt: the text is not a JSON
// object; its errors are the world table's to report).
struct Split {
  std::string world;
  std::optional<std::string> nested;
};

std::optional<Split> split(const std::string& json, const char* nested) {
  Issues ignored;
  std::optional<Json> block = parseJson(json, ignored);
  if (!block || !block->is_object()) return std::nullopt;
  Split out;
  if (const auto it = block->find(nested); it != block->end()) out.nested = it->dump();
  block->erase(kMapError);
  block->erase(kGnss);
  out.world = block->dump();
  return out;
}

}  // namespace

WorldOptions parseWorldOptions(const std::string& json, const std::string& pointer, Issues& issues) {
  const std::optional<Split> parts = split(json, kMapError);
  return worldOptionTable().read(parts ? parts->world : json, {}, pointer, issues);
}

MapErrorOptions parseMapErrorOptions(const std::string& json, const std::string& pointer, Issues& issues) {
  const std::optional<Split> parts = split(json, kMapError);
  if (!parts || !parts->nested) return {};
  return mapErrorOptionTable().read(*parts->nested, {}, pointer + "/" + kMapError, issues);
}

std::optional<GnssReceiverOptions> parseGnssOptions(const std::string& json, const std::string& pointer, Issues& issues) {
  const std::optional<Split> parts = split(json, kGnss);
  if (!parts || !parts->nested) return std::nullopt;
  return gnssReceiverOptionTable().read(*parts->nested, {}, pointer + "/" + kGnss, issues);
}

}  // namespace mapnav
