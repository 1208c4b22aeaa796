#pragma once
// A mission file's block of options (`world`, `odometry`) read through the options' table.
#include <iterator>
#include <optional>
#include <string>

#include "mapnav/core/json.h"
#include "mapnav/core/option_table.h"

namespace mapnav::sim_detail {

/// The block `json` read by `table` onto a default-constructed T, with Issues under `pointer`: a
/// syntax error is one `json.syntax` Issue with its line and column (parseJson), every bad member
/// an Issue at its pointer and a broken rule one at its field's (OptionTable::read). Members named
/// "x-..." (extensions) and "$schema" are skipped, as in every object of mapnav's files.
template <class T>
T readOptionBlock(const OptionTable<T>& table, const std::string& json, const std::string& pointer, Issues& issues) {
  const std::optional<Json> parsed = parseJson(json, issues);
  if (!parsed) return T{};
  Json block = *parsed;
  if (block.is_object()) {
    for (auto it = block.begin(); it != block.end();)
      it = it.key().rfind("x-", 0) == 0 || it.key() == "$schema" ? block.erase(it) : std::next(it);
  }
  return table.read(block.dump(), T{}, pointer, issues);
}

}  // namespace mapnav::sim_detail
