// The tables of vision/'s option structs (core/option_table.h): the defaults validate, the rules
// between fields name the field they are about in the table's words, and the cluster-perceptron's
// pipeline judges the finder's options by the finder's own rows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/vision/bev_eval.h"
#include "mapnav/vision/cluster_perceptron.h"
#include "mapnav/vision/color_classifier.h"
#include "mapnav/vision/ground_step.h"
#include "mapnav/vision/landmarks.h"
#include "mapnav/vision/line_labelling.h"
#include "mapnav/vision/pipelines.h"
#include "mapnav/vision/rectify.h"
#include "mapnav/vision/region.h"
#include "mapnav/vision/segmentation_eval.h"

namespace mapnav {
namespace {

/// validate()'s InvalidInput message for `options`, or "" when they hold.
template <class T>
std::string validateError(const T& options) {
  try {
    options.validate();
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

/// validateError() of the default options changed by `change`.
template <class T, class F>
std::string rejected(F change) {
  T options;
  change(options);
  return validateError(options);
}

/// The names of a table's fields, in its order.
template <class T>
std::vector<std::string> fieldNames(const OptionTable<T>& table) {
  std::vector<std::string> names;
  for (const OptionFieldSpec& f : table.fields()) names.push_back(f.name);
  return names;
}

TEST(VisionOptionTables, EveryDefaultValidates) {
  EXPECT_EQ(validateError(LineOptions{}), "");
  EXPECT_EQ(validateError(RegionOptions{}), "");
  EXPECT_EQ(validateError(ColorClassifierOptions{}), "");
  EXPECT_EQ(validateError(RectifyOptions{}), "");
  EXPECT_EQ(validateError(LandmarkFinderOptions{}), "");
  EXPECT_EQ(validateError(GroundStepOptions{}), "");
  EXPECT_EQ(validateError(ClusterPerceptronOptions{}), "");
  EXPECT_EQ(validateError(ClusterPerceptronPipelineOptions{}), "");
  EXPECT_EQ(validateError(TrapezoidOptions{}), "");
  EXPECT_EQ(validateError(BevGrid{}), "");
}

// The pipelines will hold these structs whole: their tables name the fields as the members are named.
TEST(VisionOptionTables, TheFieldsAreTheMembersNames) {
  EXPECT_EQ(fieldNames(lineOptionTable()),
            (std::vector<std::string>{"simplify_tolerance_px", "min_length_px", "frame_edge_px", "max_angle_deg",
                                      "max_distance_m", "gate_sigma", "gate_sigma_uncertain_map", "min_overlap", "relation_tolerance_m",
                                      "reference"}));
  EXPECT_EQ(fieldNames(regionOptionTable()),
            (std::vector<std::string>{"block_size", "block_fraction", "morph_iterations", "refine_margin_blocks",
                                      "pixel_morph_px", "max_hole_fraction", "min_part_fraction", "reference"}));
  EXPECT_EQ(fieldNames(colorClassifierOptionTable()),
            (std::vector<std::string>{"space", "blend", "max_mean_shift_sigma", "min_pixels", "stride",
                                      "nonroad_gate_sigma", "brightness_sigma", "brightness_separation",
                                      "noise_sigma"}));
  const ColorClassifierOptions rgb = colorClassifierOptionTable().parse(R"({"space": "log_rgb"})", {}, "test");
  EXPECT_EQ(rgb.space, ColorSpace::LogRGB);
}

TEST(VisionOptionTables, TheFieldsOwnRulesAreWordedByTheTable) {
  EXPECT_EQ(rejected<LineOptions>([](auto& o) { o.gate_sigma = -1; }),
            "LineOptions::gate_sigma = -1: must be in [0, 100]");
  EXPECT_EQ(rejected<RegionOptions>([](auto& o) { o.block_fraction = 0; }),
            "RegionOptions::block_fraction = 0: must be in (0, 1]");
  EXPECT_EQ(rejected<RegionOptions>([](auto& o) { o.block_size = 0; }), "RegionOptions::block_size = 0: must be in [1, 256]");
  EXPECT_EQ(rejected<ColorClassifierOptions>(
                [](auto& o) { o.brightness_separation = std::numeric_limits<double>::infinity(); }),
            "ColorClassifierOptions::brightness_separation = inf: must be finite and >= 0");
  EXPECT_EQ(rejected<ClusterPerceptronOptions>([](auto& o) { o.trapezoid_top = 1; }),
            "ClusterPerceptronOptions::trapezoid_top = 1: must be in [0, 1)");
  EXPECT_EQ(rejected<ClusterPerceptronOptions>([](auto& o) { o.adaptive_error_ratio = 1; }),
            "ClusterPerceptronOptions::adaptive_error_ratio = 1: must be in (1, 1e+06]");
  EXPECT_EQ(rejected<ClusterPerceptronOptions>([](auto& o) { o.carry_frames = 65; }),
            "ClusterPerceptronOptions::carry_frames = 65: must be in [0, 64]");
  EXPECT_EQ(rejected<LandmarkFinderOptions>([](auto& o) { o.max_search_px = 600; }),
            "LandmarkFinderOptions::max_search_px = 600: must be finite and <= 500");
  EXPECT_EQ(rejected<GroundStepOptions>([](auto& o) { o.far_m = 101; }),
            "GroundStepOptions::far_m = 101: must be finite and <= 100");
  EXPECT_EQ(rejected<RectifyOptions>([](auto& o) { o.y_max_m = std::numeric_limits<double>::infinity(); }),
            "RectifyOptions::y_max_m = inf: must be finite");
}

TEST(VisionOptionTables, ARuleBetweenFieldsNamesTheFieldItIsAbout) {
  EXPECT_EQ(rejected<RectifyOptions>([](auto& o) { o.x_max_m = 0.5; }), "RectifyOptions::x_max_m = 0.5: must be > x_min_m");
  EXPECT_EQ(rejected<RectifyOptions>([](auto& o) { o.metres_per_pixel = 0.0001; }),
            "RectifyOptions::metres_per_pixel = 0.0001: must be such that (y_max_m - y_min_m) / metres_per_pixel "
            "<= 16384");
  EXPECT_EQ(rejected<RectifyOptions>([](auto& o) {
              o.metres_per_pixel = 0.0001;
              o.y_min_m = -0.5;
              o.y_max_m = 0.5;
            }),
            "RectifyOptions::metres_per_pixel = 0.0001: must be such that (x_max_m - x_min_m) / metres_per_pixel "
            "<= 16384");
  EXPECT_EQ(rejected<LandmarkFinderOptions>([](auto& o) { o.max_search_px = 2; }),
            "LandmarkFinderOptions::max_search_px = 2: must be >= min_search_px");
  EXPECT_EQ(rejected<GroundStepOptions>([](auto& o) { o.far_m = o.near_m; }),
            "GroundStepOptions::far_m = 3: must be > near_m");
  EXPECT_EQ(rejected<GroundStepOptions>([](auto& o) { o.cell_m = 0.001; }),
            "GroundStepOptions::cell_m = 0.001: must be giving 16-1024 cells along (far_m - near_m) and across (2 "
            "half_width_m)");
  EXPECT_EQ(rejected<GroundStepOptions>([](auto& o) { o.clear_m = 0.01; }),
            "GroundStepOptions::clear_m = 0.01: must be >= cell_m");
  EXPECT_EQ(rejected<TrapezoidOptions>([](auto& o) { o.top_width = 0.75; }),
            "TrapezoidOptions::top_width = 0.75: must be <= bottom_width");
  EXPECT_EQ(rejected<TrapezoidOptions>([](auto& o) { o.top = 1; }), "TrapezoidOptions::top = 1: must be < bottom");
  EXPECT_EQ(rejected<TrapezoidOptions>([](auto& o) { o.bottom = 0; }), "TrapezoidOptions::bottom = 0: must be in (0, 1]");
  // KITTI's 20 m x 40 m in 1 mm cells: 800 million; 50 m cells: round(20 / 50) = 0 columns.
  EXPECT_EQ(rejected<BevGrid>([](auto& o) { o.cell_m = 0.001; }),
            "BevGrid::cell_m = 0.001: must be such that the grid has at most 20 million cells");
  EXPECT_EQ(rejected<BevGrid>([](auto& o) { o.cell_m = 50; }),
            "BevGrid::cell_m = 50: must be such that round((x_max_m - x_min_m) / cell_m) and round((z_max_m - z_min_m) "
            "/ cell_m) are >= 1");
  EXPECT_EQ(rejected<BevGrid>([](auto& o) { o.z_max_m = 6; }), "BevGrid::z_max_m = 6: must be > z_min_m");
}

// One rule set: every field of the pipeline that is the finder's is the finder's row as it is
// (name, kind, rule, description); the finder's rows the pipeline lacks are the road model, which
// it takes as "arc", and carry_frames.
TEST(VisionOptionTables, TheClusterPerceptronPipelineSharesTheFindersRows) {
  const auto& finder = clusterPerceptronOptionTable();
  const auto& pipeline = clusterPerceptronPipelineOptionTable();
  std::vector<std::string> not_in_pipeline;
  for (const OptionFieldSpec& f : finder.fields()) {
    const OptionFieldSpec* p = nullptr;
    for (const OptionFieldSpec& candidate : pipeline.fields())
      if (candidate.name == f.name) p = &candidate;
    if (p == nullptr) {
      not_in_pipeline.push_back(f.name);
      continue;
    }
    EXPECT_EQ(p->kind, f.kind) << f.name;
    EXPECT_EQ(p->rule.rangeText(true), f.rule.rangeText(true)) << f.name;
    EXPECT_EQ(p->rule.odd, f.rule.odd) << f.name;
    EXPECT_EQ(p->doc, f.doc) << f.name;
  }
  EXPECT_EQ(not_in_pipeline, (std::vector<std::string>{"road_model", "carry_frames"}));
  // A pipeline struct the finder's rules refuse is refused, carry_frames too.
  EXPECT_EQ(rejected<ClusterPerceptronPipelineOptions>([](auto& o) { o.carry_frames = 65; }),
            "ClusterPerceptronOptions::carry_frames = 65: must be in [0, 64]");
  EXPECT_EQ(rejected<ClusterPerceptronPipelineOptions>([](auto& o) { o.perceptron_rate = 0; }),
            "ClusterPerceptronPipelineOptions::perceptron_rate = 0: must be in (0, 100]");
}

/// Every field of `component` but `omitted` is a field of `holder` under its name (or `renamed`'s),
/// with the component's kind, rule and description.
template <class H, class C>
void expectTheComponentsRows(const OptionTable<H>& holder, const OptionTable<C>& component,
                             const std::vector<std::pair<std::string, std::string>>& renamed,
                             const std::vector<std::string>& omitted) {
  for (const OptionFieldSpec& f : component.fields()) {
    if (std::find(omitted.begin(), omitted.end(), f.name) != omitted.end()) continue;
    std::string name = f.name;
    for (const auto& [from, to] : renamed)
      if (from == f.name) name = to;
    const auto& fields = holder.fields();
    const auto it = std::find_if(fields.begin(), fields.end(), [&](const OptionFieldSpec& h) { return h.name == name; });
    ASSERT_NE(it, fields.end()) << holder.owner() << " lacks " << name;
    EXPECT_EQ(it->kind, f.kind) << name;
    EXPECT_EQ(it->rule.rangeText(true), f.rule.rangeText(true)) << name;
    EXPECT_EQ(it->doc, f.doc) << name;
  }
}

// The region pipelines hold their components' options (region reproduction, lines, colour classes)
// and read them under the JSON names they always had: the component's rows, set in the component.
TEST(VisionOptionTables, TheRegionPipelinesHoldTheirComponentsOptions) {
  expectTheComponentsRows(regionPipelineOptionTable(), regionOptionTable(), {}, {"reference"});
  expectTheComponentsRows(regionPipelineOptionTable(), lineOptionTable(), {{"min_length_px", "min_line_length_px"}},
                          {"reference"});
  expectTheComponentsRows(colorPipelineOptionTable(), colorClassifierOptionTable(),
                          {{"min_pixels", "min_training_pixels"}}, {"space", "stride"});
  const ColorPipelineOptions o = colorPipelineOptionTable().parse(
      R"({"block_size": 16, "min_line_length_px": 20, "min_training_pixels": 90, "noise_sigma": 2})", ColorPipelineOptions{},
      "pipeline \"sidewalk\"");
  EXPECT_EQ(o.region.block_size, 16);
  EXPECT_EQ(o.lines.min_length_px, 20);
  EXPECT_EQ(o.classifier.min_pixels, 90);
  EXPECT_EQ(o.classifier.noise_sigma, 2);
  // The pipeline's own defaults for its classes, where they are not the classifier's.
  const ColorPipelineOptions defaults;
  EXPECT_EQ(defaults.classifier.nonroad_gate_sigma, 8);
  EXPECT_EQ(defaults.classifier.noise_sigma, 3);
  EXPECT_EQ(ColorClassifierOptions{}.noise_sigma, 1);
  // A component's rule, named as the pipeline's field.
  EXPECT_EQ(rejected<ColorPipelineOptions>([](auto& c) { c.lines.min_length_px = -1; }),
            "ColorPipelineOptions::min_line_length_px = -1: must be in [0, 1e+06]");
  try {
    colorPipelineOptionTable().parse(R"({"stride": 2})", ColorPipelineOptions{}, "pipeline \"sidewalk\"");
    ADD_FAILURE() << "stride is set by the pipeline, not an option";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "pipeline \"sidewalk\": unknown option \"stride\"");
  }
}

TEST(VisionOptionTables, AFunctionsArgumentIsNamedAsTheFunctions) {
  ColorClassifier c;
  const std::vector<std::uint8_t> rgb(3 * 4 * 4, 128), road(16, 1), nonroad(16, 0);
  try {
    c.update(rgb.data(), 4, 4, road.data(), nonroad.data(), -1.0);
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "ColorClassifier::update: nonroad_gate_sigma = -1: must be finite and >= 0");
  }
}

}  // namespace
}  // namespace mapnav
