// The option tables of the region pipelines ("sidewalk", "color-rgb", "blue-band"): each option's
// name, range and the description `mapnav pipelines` lists. The defaults are the structs' (pipelines.h);
// the components' options (region reproduction, lines, colour classes) are the components' tables,
// nested under the flat names the JSON has always had.
#include "mapnav/vision/pipelines.h"

namespace mapnav {

const OptionTable<RegionPipelineOptions>& regionPipelineOptionTable() {
  using O = RegionPipelineOptions;
  static const OptionTable<O> table =
      OptionTable<O>("RegionPipelineOptions")
          .field("dark_level", &O::dark_level, inRange(0, 255),
                 "mean grey level (0-255) of the ground pixels below which the frame fails: \"frame too dark\"")
          .field("saturated_level", &O::saturated_level, inRange(0, 255),
                 "a pixel is saturated when all its channels are at least this")
          .field("overexposed_fraction", &O::overexposed_fraction, inRange(0, 1),
                 "fraction of saturated ground pixels above which the frame fails: \"frame over-exposed\"")
          .field("min_predicted_px", &O::min_predicted_px, inRange(0, 1e9),
                 "fewer predicted road pixels in the image than this: \"nothing predicted in view\"")
          .field("min_region_fraction", &O::min_region_fraction, inRange(0, 10),
                 "a reproduced region smaller than this fraction of the predicted road area: \"no road-coloured region\"")
          .field("smooth_px", &O::smooth_px, inRange(0, 50),
                 "box-filter radius applied to the per-pixel road score before the threshold")
          .nest(&O::region, regionOptionTable(), {}, {"reference"})
          .field("region_tolerance_px", &O::region_tolerance_px, inRange(1e-6, 100),
                 "polygon tolerance of region_image, pixels")
          .nest(&O::lines, lineOptionTable(), {{"min_length_px", "min_line_length_px"}}, {"reference"})
          .field("grid_px", &O::grid_px, inRange(1, 8),
                 "classify and reproduce the region on a grid of cells this many pixels a side (the frame averaged "
                 "over each cell; the options in pixels above are divided by it), the boundary mapped back to "
                 "pixels; 1 = every pixel. The default 2 runs the loop about 2.6 times faster than 1 "
                 "(campus_dialogue replay: 1.6 against 4.0 ms median) and meets the same localisation targets "
                 "(campus_tour replay: along-road error after intersections 0.12 against 0.10 m) with a coarser "
                 "edge (lateral RMS 1.6 against 1.0 cm). Every option in pixels, this one too, is for a 480 x 360 "
                 "frame: on a smaller one lengths are multiplied by sqrt(pixels / (480 x 360)) and min_predicted_px "
                 "by that squared (pixelScale()), so that at 240 x 180 the grid is 1 and a block 4 px; larger "
                 "frames keep them")
          .field("reference", &O::reference,
                 "run every pixel (grid_px 1) with the reference implementations (double-precision per-pixel "
                 "log-odds, OpenCV's box filter (double-precision sums), morphology and distance transform, CGAL "
                 "simplification): the answers of grid_px 1, several times slower; for tests and benchmarks");
  return table;
}

const OptionTable<ColorPipelineOptions>& colorPipelineOptionTable() {
  using O = ColorPipelineOptions;
  static const OptionTable<O> table =
      OptionTable<O>("ColorPipelineOptions")
          .field("adaptive", &O::adaptive, "keep the colour models from frame to frame, blending in each frame's estimate")
          .nest(&O::classifier, colorClassifierOptionTable(), {{"min_pixels", "min_training_pixels"}}, {"space", "stride"})
          .field("label_erosion_px", &O::label_erosion_px, inRange(0, 200),
                 "training labels: the predicted road eroded by this, non-road = the rest of the view eroded by this")
          .field("nonroad_gate_sigma_mapped", &O::nonroad_gate_sigma_mapped, inRange(0, 1e6),
                 "nonroad_gate_sigma where the prediction comes from a pose estimate (its pose covariance given: a "
                 "mission's Map), whose predicted road is the map's paving seen from a known pose, so that the rest "
                 "of the view is mostly not road: a shoulder close to the road's colour (dirt beside brick, shaded grass "
                 "beside a carriageway) then trains non-road, where within the photos' 8 sigma it was taken for road; "
                 "0 = every cell outside")
          .field("outlier_llr", &O::outlier_llr, inRange(0, 1e6),
                 "adaptive: drop training pixels whose label the current model contradicts by more than this log-odds")
          .field("llr_threshold", &O::llr_threshold, inRange(-1e6, 1e6), "road where the smoothed log-odds exceed this")
          .field("min_separation", &O::min_separation, inRange(0, 1e6),
                 "Bhattacharyya distance between the class models below which: \"no road-coloured region\"")
          .include(regionPipelineOptionTable());
  return table;
}

const OptionTable<ScorePipelineOptions>& scorePipelineOptionTable() {
  using O = ScorePipelineOptions;
  static const OptionTable<O> table =
      OptionTable<O>("ScorePipelineOptions")
          .field("threshold", &O::threshold, inRange(1e-6, 1 - 1e-6),
                 "road where the road probability, averaged over the (2 smooth_px + 1)^2 box, exceeds this")
          .field("centre_line", &O::centre_line,
                 "give the centre line of the road ahead, from the region's rows that show both its sides")
          .include(regionPipelineOptionTable());
  return table;
}

const OptionTable<BlueBandOptions>& blueBandOptionTable() {
  using O = BlueBandOptions;
  static const OptionTable<O> table =
      OptionTable<O>("BlueBandOptions")
          .field("threshold", &O::threshold, inRange(-1, 255),
                 "the blue level between road and non-road, road on the side where most of the predicted road is; "
                 "-1 = Otsu's threshold on the ground pixels")
          .field("band_sigma", &O::band_sigma, inRange(0, 100),
                 "> 0: road is the band of blue levels within this many sigma of the predicted road's median "
                 "(sigma from its 16th-84th percentiles, at least 2 levels), threshold unused; 0 = one cut")
          .include(regionPipelineOptionTable());
  return table;
}

void RegionPipelineOptions::validate() const { regionPipelineOptionTable().validate(*this); }
void ColorPipelineOptions::validate() const { colorPipelineOptionTable().validate(*this); }
void BlueBandOptions::validate() const { blueBandOptionTable().validate(*this); }
void ScorePipelineOptions::validate() const { scorePipelineOptionTable().validate(*this); }

}  // namespace mapnav
