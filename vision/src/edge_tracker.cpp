// The edge tracker's options (validation, JSON, the documented list) and the "edge-tracker" pipeline.
// The tracker itself (Wallace et al. 1985, 3.1-3.2) is in edge_tracker_*.cpp; see edge_tracker.h.
#include "mapnav/vision/edge_tracker.h"

#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mapnav/core/error.h"

namespace mapnav {

// --- Options -------------------------------------------------------------------------------------------

void EdgeTrackerOptions::validate() const {
  auto bad = [](const std::string& field, double v, const std::string& rule) {
    std::ostringstream s;
    s << "EdgeTrackerOptions::" << field << " = " << v << ": must be " << rule;
    throw InvalidInput(s.str());
  };
  if (!(min_normalised_step >= 0)) bad("min_normalised_step", min_normalised_step, ">= 0");
  if (window_rows < 4) bad("window_rows", window_rows, ">= 4");
  if (window_cols < 8) bad("window_cols", window_cols, ">= 8");
  if (!(step_fraction > 0 && step_fraction <= 4)) bad("step_fraction", step_fraction, "in (0, 4]");
  if (step_half_width_px < 1) bad("step_half_width_px", step_half_width_px, ">= 1");
  if (!(angle_search_deg >= 0 && angle_search_deg <= 45)) bad("angle_search_deg", angle_search_deg, "in [0, 45]");
  if (!(angle_step_deg > 0 && angle_step_deg <= 45)) bad("angle_step_deg", angle_step_deg, "in (0, 45]");
  if (!(min_contrast >= 0)) bad("min_contrast", min_contrast, ">= 0");
  if (!(max_turn_deg > 0 && max_turn_deg <= 180)) bad("max_turn_deg", max_turn_deg, "in (0, 180]");
  if (min_points < 1) bad("min_points", min_points, ">= 1");
  if (max_points < min_points) bad("max_points", max_points, ">= min_points");
  if (!(expected_width_m >= 0)) bad("expected_width_m", expected_width_m, ">= 0");
  if (!(width_tolerance > 0)) bad("width_tolerance", width_tolerance, "> 0");
  if (!(parallel_tolerance_deg > 0)) bad("parallel_tolerance_deg", parallel_tolerance_deg, "> 0");
  if (!(max_width_sd_m > 0)) bad("max_width_sd_m", max_width_sd_m, "> 0");
  if (!(max_range_m > 0)) bad("max_range_m", max_range_m, "> 0");
}

namespace {

struct Spec {
  const char* name;
  const char* def;
  const char* description;
};

const std::vector<Spec>& specs() {
  static const std::vector<Spec> s = {
      {"band", "\"normalized_green\"",
       "grey image: \"luminance\" (0.299 R + 0.587 G + 0.114 B), \"blue\" (the blue band of the Warp runs, 3.6.3) or "
       "\"normalized_green\" (255 G / (R + G + B), the normalised colour of 3.4.3: blind to shadows) or \"normalized_red\""},
      {"band_from_prediction", "true",
       "with a normalised band: trace each edge in whichever of the normalised green and red separates its predicted "
       "side colours more (dirt and gravel have the asphalt's normalised green)"},
      {"min_normalised_step", "12",
       "with band_from_prediction: when neither normalised band separates an edge's predicted side colours by this many "
       "levels, trace it in luminance (gravel against asphalt: 2.8 in green, 6.6 in red, 60 in luminance); 0: never"},
      {"window_rows", "64", "search window length along the edge at 480 rows (scaled with the image height)"},
      {"window_cols", "128", "search window width across the edge at 512 columns (scaled with the image width)"},
      {"step_fraction", "0.5", "the next point is predicted this x window_rows ahead along theta"},
      {"step_half_width_px", "6", "the ideal step edge: this many profile samples each side (at 512 columns)"},
      {"angle_search_deg", "10", "operator orientations tried: theta +- this ..."},
      {"angle_step_deg", "1", "... in steps of this"},
      {"min_contrast", "6", "a weaker step (grey levels) ends the trace"},
      {"max_turn_deg", "30", "a larger change of theta between two steps ends the trace"},
      {"min_points", "3", "fewer edge points: the edge is lost (status failed)"},
      {"max_points", "200", "at most this many points per edge"},
      {"start_left_u", "-1", "without a prediction: left edge start column (-1: 0.25 x width)"},
      {"start_right_u", "-1", "without a prediction: right edge start column (-1: 0.75 x width)"},
      {"start_v", "-1", "without a prediction: start row (-1: half a window above the bottom)"},
      {"start_left_angle_deg", "20", "without a prediction: left edge direction, degrees from up, + leaning right"},
      {"start_right_angle_deg", "-20", "without a prediction: right edge direction"},
      {"expected_width_m", "0", "expected road width; 0: the prediction's parallel relation separation_m"},
      {"width_tolerance", "0.15", "ground width must be within this fraction of the expected width"},
      {"parallel_tolerance_deg", "10", "the two edges' ground lines must be within this angle"},
      {"max_width_sd_m", "0.4", "the spread of the width along the edges must be within this"},
      {"max_range_m", "15", "an edge ends at its first point farther than this on the ground (or above the horizon), m"},
      {"gate_search", "false",
       "after the first point search only offsets reachable within max_turn_deg (step x tan); off: the whole window"},
      {"gate_luminance", "true",
       "gate_search for the edges min_normalised_step sends to luminance alone (there tree shadows on a bright shoulder "
       "step more than the material)"},
      {"use_carried_edges", "true", "start from advance()'d previous edges when the prediction has no segments"},
      {"single_edge", "true",
       "when one edge is lost and the other (labelled) is tracked, report that edge alone instead of failing"},
  };
  return s;
}

}  // namespace

EdgeTrackerOptions edgeTrackerOptionsFromJson(const std::string& text, const EdgeTrackerOptions& base) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text.empty() ? std::string("{}") : text);
  } catch (const nlohmann::json::exception& e) {
    throw InvalidInput(std::string("pipeline \"edge-tracker\": options are not JSON: ") + e.what());
  }
  if (!j.is_object()) throw InvalidInput("pipeline \"edge-tracker\": options must be a JSON object");
  EdgeTrackerOptions o = base;
  for (const auto& [key, value] : j.items()) {
    const std::string bad = "pipeline \"edge-tracker\": option " + key + " = " + value.dump();
    auto num = [&]() {
      if (!value.is_number() || !std::isfinite(value.get<double>())) throw InvalidInput(bad + ": must be a number");
      return value.get<double>();
    };
    auto integer = [&]() {
      const double v = num();
      if (v != std::floor(v) || std::abs(v) > 1e9) throw InvalidInput(bad + ": must be an integer");
      return static_cast<int>(v);
    };
    if (key == "band") {
      if (value == "blue") o.band = GreyBand::Blue;
      else if (value == "luminance") o.band = GreyBand::Luminance;
      else if (value == "normalized_green") o.band = GreyBand::NormalizedGreen;
      else if (value == "normalized_red") o.band = GreyBand::NormalizedRed;
      else throw InvalidInput(bad + ": must be \"blue\", \"luminance\", \"normalized_green\" or \"normalized_red\"");
    } else if (key == "min_normalised_step") o.min_normalised_step = num();
    else if (key == "window_rows") o.window_rows = integer();
    else if (key == "window_cols") o.window_cols = integer();
    else if (key == "step_fraction") o.step_fraction = num();
    else if (key == "step_half_width_px") o.step_half_width_px = integer();
    else if (key == "angle_search_deg") o.angle_search_deg = num();
    else if (key == "angle_step_deg") o.angle_step_deg = num();
    else if (key == "min_contrast") o.min_contrast = num();
    else if (key == "max_turn_deg") o.max_turn_deg = num();
    else if (key == "min_points") o.min_points = integer();
    else if (key == "max_points") o.max_points = integer();
    else if (key == "start_left_u") o.start_left_u = num();
    else if (key == "start_right_u") o.start_right_u = num();
    else if (key == "start_v") o.start_v = num();
    else if (key == "start_left_angle_deg") o.start_left_angle_deg = num();
    else if (key == "start_right_angle_deg") o.start_right_angle_deg = num();
    else if (key == "expected_width_m") o.expected_width_m = num();
    else if (key == "width_tolerance") o.width_tolerance = num();
    else if (key == "parallel_tolerance_deg") o.parallel_tolerance_deg = num();
    else if (key == "max_width_sd_m") o.max_width_sd_m = num();
    else if (key == "max_range_m") o.max_range_m = num();
    else if (key == "gate_search") {
      if (!value.is_boolean()) throw InvalidInput(bad + ": must be true or false");
      o.gate_search = value.get<bool>();
    } else if (key == "gate_luminance") {
      if (!value.is_boolean()) throw InvalidInput(bad + ": must be true or false");
      o.gate_luminance = value.get<bool>();
    } else if (key == "band_from_prediction") {
      if (!value.is_boolean()) throw InvalidInput(bad + ": must be true or false");
      o.band_from_prediction = value.get<bool>();
    } else if (key == "single_edge") {
      if (!value.is_boolean()) throw InvalidInput(bad + ": must be true or false");
      o.single_edge = value.get<bool>();
    } else if (key == "use_carried_edges") {
      if (!value.is_boolean()) throw InvalidInput(bad + ": must be true or false");
      o.use_carried_edges = value.get<bool>();
    } else
      throw InvalidInput("pipeline \"edge-tracker\": unknown option \"" + key + "\"");
  }
  try {
    o.validate();
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string("pipeline \"edge-tracker\": ") + e.what());
  }
  return o;
}

std::vector<OptionInfo> edgeTrackerOptionInfos() {
  std::vector<OptionInfo> out;
  for (const Spec& s : specs()) out.push_back({s.name, s.def, s.description});
  return out;
}

// --- The pipeline ----------------------------------------------------------------------------------------

namespace {

class EdgeTrackerPipeline : public VisionPipeline {
 public:
  std::string name() const override { return "edge-tracker"; }
  void configure(const std::string& options_json) override {
    tracker_.setOptions(edgeTrackerOptionsFromJson(options_json, tracker_.options()));
  }
  DetectedObject detect(const VisionFrame& frame, const PredictedObject& prediction) override {
    return tracker_.detect(frame, prediction);
  }
  void reset() override { tracker_.reset(); }

 private:
  EdgeTracker tracker_;
};

}  // namespace

std::unique_ptr<VisionPipeline> createEdgeTrackerPipeline() { return std::make_unique<EdgeTrackerPipeline>(); }

}  // namespace mapnav
