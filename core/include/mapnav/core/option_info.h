#pragma once
// What a listing (`mapnav pipelines`) shows of an option struct: its documented options with their
// defaults, and its named presets. Plain data; option_table.h makes them from a struct's table.
#include <string>

namespace mapnav {

/// One documented option, for listings and validation messages.
struct OptionInfo {
  std::string name;
  std::string default_json;  ///< the default, as JSON text
  std::string description;
};

/// A named set of option values, chosen with `"preset": "NAME"` in an options object and applied
/// before the object's other members (which override it).
struct OptionPreset {
  std::string name;
  std::string description;
  std::string json;  ///< a JSON object of options
};

}  // namespace mapnav
