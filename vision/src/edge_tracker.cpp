// The edge tracker's options (validation, JSON, the documented list) and the "edge-tracker" pipeline.
// The tracker itself (Wallace et al. 1985, 3.1-3.2) is in edge_tracker_*.cpp; see edge_tracker.h.
#include "mapnav/vision/edge_tracker.h"

#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "mapnav/core/error.h"

namespace mapnav {

// --- Options -------------------------------------------------------------------------------------------

const OptionTable<EdgeTrackerOptions>& edgeTrackerOptionTable() {
  using O = EdgeTrackerOptions;
  static const OptionTable<O> table =
      OptionTable<O>("EdgeTrackerOptions")
          .choice("band", &O::band,
                  {{GreyBand::Blue, "blue"},
                   {GreyBand::Luminance, "luminance"},
                   {GreyBand::NormalizedGreen, "normalized_green"},
                   {GreyBand::NormalizedRed, "normalized_red"}},
                  "grey image: \"luminance\" (0.299 R + 0.587 G + 0.114 B), \"blue\" (the blue band of the Warp runs, "
                  "3.6.3) or \"normalized_green\" (255 G / (R + G + B), the normalised colour of 3.4.3: blind to "
                  "shadows) or \"normalized_red\"")
          .field("band_from_prediction", &O::band_from_prediction,
                 "with a normalised band: trace each edge in whichever of the normalised green and red separates its "
                 "predicted side colours more (dirt and gravel have the asphalt's normalised green)")
          .field("min_normalised_step", &O::min_normalised_step, atLeast(0),
                 "with band_from_prediction: when neither normalised band separates an edge's predicted side colours "
                 "by this many levels, trace it in luminance (gravel against asphalt: 2.8 in green, 6.6 in red, 60 in "
                 "luminance); 0: never")
          .field("window_rows", &O::window_rows, atLeast(4),
                 "search window length along the edge at 480 rows (scaled with the image height)")
          .field("window_cols", &O::window_cols, atLeast(8),
                 "search window width across the edge at 512 columns (scaled with the image width)")
          .field("step_fraction", &O::step_fraction, aboveUpTo(0, 4),
                 "the next point is predicted this x window_rows ahead along theta")
          .field("step_half_width_px", &O::step_half_width_px, atLeast(1),
                 "the ideal step edge: this many profile samples each side (at 512 columns)")
          .field("angle_search_deg", &O::angle_search_deg, inRange(0, 45), "operator orientations tried: theta +- this ...")
          .field("angle_step_deg", &O::angle_step_deg, aboveUpTo(0, 45), "... in steps of this")
          .field("min_contrast", &O::min_contrast, atLeast(0), "a weaker step (grey levels) ends the trace")
          .field("max_turn_deg", &O::max_turn_deg, aboveUpTo(0, 180),
                 "a larger change of theta between two steps ends the trace")
          .field("min_points", &O::min_points, atLeast(1), "fewer edge points: the edge is lost (status failed)")
          .field("max_points", &O::max_points, "at most this many points per edge")
          .field("start_left_u", &O::start_left_u, "without a prediction: left edge start column (-1: 0.25 x width)")
          .field("start_right_u", &O::start_right_u, "without a prediction: right edge start column (-1: 0.75 x width)")
          .field("start_v", &O::start_v, "without a prediction: start row (-1: half a window above the bottom)")
          .field("start_left_angle_deg", &O::start_left_angle_deg,
                 "without a prediction: left edge direction, degrees from up, + leaning right")
          .field("start_right_angle_deg", &O::start_right_angle_deg, "without a prediction: right edge direction")
          .field("expected_width_m", &O::expected_width_m, atLeast(0),
                 "expected road width; 0: the prediction's parallel relation separation_m")
          .field("width_tolerance", &O::width_tolerance, above(0),
                 "ground width must be within this fraction of the expected width")
          .field("parallel_tolerance_deg", &O::parallel_tolerance_deg, above(0),
                 "the two edges' ground lines must be within this angle")
          .field("max_width_sd_m", &O::max_width_sd_m, above(0),
                 "the spread of the width along the edges must be within this")
          .field("max_range_m", &O::max_range_m, above(0),
                 "an edge ends at its first point farther than this on the ground (or above the horizon), m")
          .field("gate_search", &O::gate_search,
                 "after the first point search only offsets reachable within max_turn_deg (step x tan); off: the "
                 "whole window")
          .field("gate_luminance", &O::gate_luminance,
                 "gate_search for the edges min_normalised_step sends to luminance alone (there tree shadows on a "
                 "bright shoulder step more than the material)")
          .field("use_carried_edges", &O::use_carried_edges,
                 "start from advance()'d previous edges when the prediction has no segments")
          .field("single_edge", &O::single_edge,
                 "when one edge is lost and the other (labelled) is tracked, report that edge alone instead of failing")
          .field("start_search_m", &O::start_search_m, above(0),
                 "starts from a predicted region's sides: the first window searches this far either side (m on the "
                 "ground at the start's range)")
          .field("start_angle_search_deg", &O::start_angle_search_deg, inRange(0, 80),
                 "starts from a predicted region's sides: the first window tries orientations within this of the "
                 "side's")
          .field("max_heading_deg", &O::max_heading_deg, aboveUpTo(0, 90),
                 "starts from a predicted region's sides: an edge whose ground line is farther than this off the "
                 "vehicle's heading counts as lost")
          .field("region_far_m", &O::region_far_m, above(0),
                 "starts from a predicted region's sides: the road region reported reaches up to the row this far "
                 "ahead (m), a lost edge's side to the image side")
          .check("max_points", [](const O& o) { return o.max_points >= o.min_points; }, ">= min_points");
  return table;
}

void EdgeTrackerOptions::validate() const { edgeTrackerOptionTable().validate(*this); }

// --- The pipeline ----------------------------------------------------------------------------------------

namespace {

class EdgeTrackerPipeline : public VisionPipeline {
 public:
  std::string name() const override { return "edge-tracker"; }
  void configure(const std::string& options_json) override {
    tracker_.setOptions(edgeTrackerOptionTable().parse(options_json, tracker_.options(), "pipeline \"edge-tracker\""));
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
