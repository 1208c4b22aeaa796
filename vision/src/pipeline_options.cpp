#include "pipeline_options.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "mapnav/core/error.h"

namespace mapnav {

std::string optionText(double v, bool is_bool, bool is_int) {
  if (is_bool) return v != 0 ? "true" : "false";
  if (is_int) return std::to_string(static_cast<long long>(v));
  std::ostringstream s;
  s << v;
  return s.str();
}

std::vector<OptionInfo> optionInfos(const std::vector<OptionSpec>& specs) {
  std::vector<OptionInfo> out;
  for (const OptionSpec& s : specs) out.push_back({s.name, optionText(s.value, s.is_bool, s.is_int), s.description});
  return out;
}

PipelineOptions::PipelineOptions(std::vector<OptionSpec> specs) : specs_(std::move(specs)) {
  for (const OptionSpec& s : specs_) values_[s.name] = s.value;
}

void PipelineOptions::configure(const std::string& pipeline, const std::string& text) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text.empty() ? std::string("{}") : text);
  } catch (const nlohmann::json::exception& e) {
    throw InvalidInput("pipeline \"" + pipeline + "\": options are not JSON: " + e.what());
  }
  if (!j.is_object()) throw InvalidInput("pipeline \"" + pipeline + "\": options must be a JSON object");
  std::map<std::string, double> next = values_;
  for (const auto& [key, value] : j.items()) {
    const auto it = std::find_if(specs_.begin(), specs_.end(), [&](const OptionSpec& s) { return s.name == key; });
    if (it == specs_.end()) throw InvalidInput("pipeline \"" + pipeline + "\": unknown option \"" + key + "\"");
    const std::string bad = "pipeline \"" + pipeline + "\": option " + key + " = " + value.dump();
    if (it->is_bool) {
      if (!value.is_boolean()) throw InvalidInput(bad + ": must be true or false");
      next[key] = value.get<bool>() ? 1 : 0;
      continue;
    }
    if (!value.is_number()) throw InvalidInput(bad + ": must be a number");
    const double v = value.get<double>();
    if (!std::isfinite(v) || v < it->min || v > it->max) {
      throw InvalidInput(bad + ": must be in [" + optionText(it->min, false, false) + ", " + optionText(it->max, false, false) + "]");
    }
    if (it->is_int && v != std::floor(v)) throw InvalidInput(bad + ": must be an integer");
    next[key] = v;
  }
  values_ = std::move(next);
}

}  // namespace mapnav
