#pragma once
// Internal to vision/: the options of a built-in pipeline, declared once as specs (name, default,
// type, range, description) and read from the JSON the pipeline is configured with. Shared by every
// built-in pipeline so that each checks and names its options the same way.
#include <map>
#include <string>
#include <vector>

#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {

struct OptionSpec {
  std::string name;
  double value;  ///< default (bool: 0 / 1)
  bool is_bool;
  bool is_int;
  double min, max;
  std::string description;
};

/// How `mapnav pipelines` shows a value: true/false, an integer, or a number.
std::string optionText(double value, bool is_bool, bool is_int);
std::vector<OptionInfo> optionInfos(const std::vector<OptionSpec>& specs);

class PipelineOptions {
 public:
  explicit PipelineOptions(std::vector<OptionSpec> specs);
  /// Reads a JSON object of options; throws InvalidInput naming `pipeline`, the option and its bad
  /// value (unknown, wrong type, out of range, not an integer). On error nothing changes.
  void configure(const std::string& pipeline, const std::string& text);
  double operator[](const std::string& k) const { return values_.at(k); }
  int i(const std::string& k) const { return static_cast<int>(values_.at(k)); }
  bool b(const std::string& k) const { return values_.at(k) != 0; }

 private:
  std::vector<OptionSpec> specs_;
  std::map<std::string, double> values_;
};

}  // namespace mapnav
