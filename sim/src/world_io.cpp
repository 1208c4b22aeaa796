#include "mapnav/sim/world_io.h"

#include "option_block.h"

namespace mapnav {

WorldOptions parseWorldOptions(const std::string& json, const std::string& pointer, Issues& issues) {
  return sim_detail::readOptionBlock(worldOptionTable(), json, pointer, issues);
}

}  // namespace mapnav
