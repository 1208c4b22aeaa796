#include "mapnav/sim/world_io.h"

namespace mapnav {

WorldOptions parseWorldOptions(const std::string& json, const std::string& pointer, Issues& issues) {
  return worldOptionTable().read(json, {}, pointer, issues);
}

}  // namespace mapnav
