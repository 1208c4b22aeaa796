// The option tables of the region pipelines ("sidewalk", "color-rgb", "blue-band"): each option's
// name, range and the description `mapnav pipelines` lists. The defaults are the structs' (pipelines.h).
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
          .field("block_size", &O::block_size, inRange(1, 256), "region reproduction: block side, pixels")
          .field("block_fraction", &O::block_fraction, inRange(1e-9, 1),
                 "a block is road when at least this fraction of its pixels is")
          .field("morph_iterations", &O::morph_iterations, inRange(0, 10), "block-level closings then openings (3 x 3)")
          .field("refine_margin_blocks", &O::refine_margin_blocks, inRange(0, 10),
                 "pixel region may reach this many blocks beyond the block region")
          .field("pixel_morph_px", &O::pixel_morph_px, inRange(0, 50), "pixel-level closing then opening radius")
          .field("max_hole_fraction", &O::max_hole_fraction, inRange(0, 1),
                 "fill the region's holes up to this fraction of its area (leaves, cracks, slab gaps); larger "
                 "holes (a car on the road) stay out of the region; 0 = fill none, 1 = fill every hole")
          .field("min_part_fraction", &O::min_part_fraction, inRange(0, 1e6),
                 "where a line (a lane marking, a kerb) splits the road-coloured pixels inside the block "
                 "region, every part within two blocks of the main part holding at least this fraction of "
                 "what the main part holds of the block region joins the region's mask (the outline and its "
                 "lines stay the main part's); above 1 = the main part only")
          .field("region_tolerance_px", &O::region_tolerance_px, inRange(1e-6, 100),
                 "polygon tolerance of region_image, pixels")
          .field("simplify_tolerance_px", &O::simplify_tolerance_px, inRange(1e-6, 100),
                 "polygon fit tolerance for lines, pixels")
          .field("min_line_length_px", &O::min_line_length_px, inRange(0, 1e6),
                 "shorter polygon edges are dropped, pixels")
          .field("frame_edge_px", &O::frame_edge_px, inRange(0, 100),
                 "lines within this of the image border or ground edge are frame edges")
          .field("max_angle_deg", &O::max_angle_deg, inRange(1e-6, 90), "label match: angle on the ground within this")
          .field("max_distance_m", &O::max_distance_m, inRange(1e-6, 100),
                 "label match: both end points within this of the predicted line (the gate's floor)")
          .field("gate_sigma", &O::gate_sigma, inRange(0, 100),
                 "label match: ... or within this many sigma of it, the predicted line's sigma across itself from the "
                 "prediction's pose covariance (the Map's estimate), where that is wider; 0 = max_distance_m alone")
          .field("min_overlap", &O::min_overlap, inRange(0, 1),
                 "label match: this fraction of the line overlaps the predicted segment")
          .field("relation_tolerance_m", &O::relation_tolerance_m, inRange(1e-6, 100),
                 "a labelled parallel pair must be within this of the predicted separation")
          .field("grid_px", &O::grid_px, inRange(1, 8),
                 "classify and reproduce the region on a grid of cells this many pixels a side (the frame averaged "
                 "over each cell; the options in pixels above are divided by it), the boundary mapped back to "
                 "pixels; 1 = every pixel. The default 2 runs the loop about 2.6 times faster than 1 "
                 "(campus_dialogue replay: 1.6 against 4.0 ms median) and meets the same localisation targets "
                 "(campus_tour replay: along-road error after intersections 0.12 against 0.10 m) with a coarser "
                 "edge (lateral RMS 1.6 against 1.0 cm)")
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
          .field("blend", &O::blend, inRange(1e-9, 1), "weight of a frame's estimate in the blended model")
          .field("max_mean_shift_sigma", &O::max_mean_shift_sigma, inRange(1e-9, 1e6),
                 "refuse a class estimate whose mean moved more than this many sigma (drift guard)")
          .field("min_training_pixels", &O::min_training_pixels, inRange(1, 1e9),
                 "refuse a class estimate from fewer labelled training cells (training reads every 2nd cell of "
                 "every 2nd row)")
          .field("label_erosion_px", &O::label_erosion_px, inRange(0, 200),
                 "training labels: the predicted road eroded by this, non-road = the rest of the view eroded by this")
          .field("nonroad_gate_sigma", &O::nonroad_gate_sigma, inRange(0, 1e6),
                 "non-road trains only on the cells outside the predicted road whose colour is more than this many "
                 "sigma (Mahalanobis) from the frame's road colour: on real roads the rest of the view is mostly road; "
                 "until a frame shows such cells, non-road is flat (road is what the road colour explains); "
                 "0 = every cell outside")
          .field("nonroad_gate_sigma_mapped", &O::nonroad_gate_sigma_mapped, inRange(0, 1e6),
                 "the same gate where the prediction comes from a pose estimate (its pose covariance given: a "
                 "mission's Map), whose predicted road is the map's paving seen from a known pose, so that the rest "
                 "of the view is mostly not road: a shoulder close to the road's colour (dirt beside brick, shaded grass "
                 "beside a carriageway) then trains non-road, where within the photos' 8 sigma it was taken for road; "
                 "0 = every cell outside")
          .field("brightness_sigma", &O::brightness_sigma, inRange(0, 10),
                 "the spread in log brightness added to every class (0.1 = 10 %), so that a road learnt in even light "
                 "keeps its shades; sidewalk: the log brightness is a third feature (rg alone takes grey cars, walls and "
                 "kerbs for a grey road), 0 = rg only (Wallace 3.4.3); color-rgb: added along log RGB's grey axis")
          .field("brightness_separation", &O::brightness_separation, inRange(0, 1e6),
                 "sidewalk: the brightness only while rg alone separates road and non-road by less than this "
                 "Bhattacharyya distance (a grey road among grey cars and walls: 2-4); where colour separates them "
                 "(grass: 5 and more) rg alone stays robust to shadows")
          .field("noise_sigma", &O::noise_sigma, inRange(1e-3, 100),
                 "the camera's noise, 8-bit levels per channel, added to every class's spread (in rg scaled to one "
                 "level's effect at mid-grey, 1/500): a real camera's noise and compression; 1 = a rendered frame's")
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
