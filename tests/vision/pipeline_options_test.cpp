// The built-in pipelines' options, one table each (core/option_table.h): the defaults validate, the
// listing (`mapnav pipelines`) is the default-constructed struct, configure()'s errors name the
// option and its value, presets apply and can be overridden, and every field round-trips.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "mapnav/core/error.h"
#include "mapnav/vision/cluster_perceptron.h"
#include "mapnav/vision/edge_tracker.h"
#include "mapnav/vision/pipelines.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {
namespace {

PipelineInfo registered(const std::string& name) {
  registerBuiltinPipelines();
  for (const PipelineInfo& info : listPipelines())
    if (info.name == name) return info;
  ADD_FAILURE() << "no pipeline " << name;
  return {};
}

/// A valid value of the field other than `value`.
OptionValue otherValue(const OptionFieldSpec& field, const OptionValue& value) {
  switch (field.kind) {
    case OptionKind::Bool:
      return !std::get<bool>(value);
    case OptionKind::String:
      return std::get<std::string>(value) + "x";
    case OptionKind::Choice:
      for (const std::string& choice : field.choices)
        if (choice != std::get<std::string>(value)) return choice;
      break;
    case OptionKind::Integer:
    case OptionKind::Number: {
      const double x = std::get<double>(value);
      const OptionRule& r = field.rule;
      for (const double c : {x + 1, x + 2, x - 1, r.min, r.max, x / 2, x * 2, (r.min + r.max) / 2}) {
        if (c == x || !r.allows(c)) continue;
        if (field.kind == OptionKind::Integer && c != std::floor(c)) continue;
        if (r.odd && std::fmod(std::abs(c), 2.0) != 1.0) continue;
        return c;
      }
      break;
    }
  }
  ADD_FAILURE() << "no other value for " << field.name;
  return value;
}

/// The default struct with every field of the table changed to another valid value.
template <class T>
T everyFieldChanged(const OptionTable<T>& table) {
  T changed{};
  for (std::size_t i = 0; i < table.fields().size(); ++i)
    table.set(changed, i, otherValue(table.fields()[i], table.get(changed, i)));
  return changed;
}

/// The registry's listing of `pipeline` is `table`'s: the same options in the same order, each
/// listed default read back gives the default-constructed struct's member (onto a struct where every
/// field differs from it), and the presets are the table's.
template <class T>
void expectListingIsTheDefaults(const std::string& pipeline, const OptionTable<T>& table) {
  const PipelineInfo info = registered(pipeline);
  ASSERT_EQ(info.options.size(), table.fields().size()) << pipeline;
  std::string listed = "{";
  for (std::size_t i = 0; i < info.options.size(); ++i) {
    EXPECT_EQ(info.options[i].name, table.fields()[i].name) << pipeline;
    EXPECT_FALSE(info.options[i].description.empty()) << pipeline << " " << info.options[i].name;
    listed += (i > 0 ? ", \"" : "\"") + info.options[i].name + "\": " + info.options[i].default_json;
  }
  listed += "}";
  const T defaults{};
  const T changed = everyFieldChanged(table);
  const T read = table.parse(listed, changed, pipeline);
  for (std::size_t i = 0; i < table.fields().size(); ++i) {
    EXPECT_NE(table.get(changed, i), table.get(defaults, i)) << pipeline << " " << table.fields()[i].name;
    EXPECT_EQ(table.get(read, i), table.get(defaults, i)) << pipeline << " " << table.fields()[i].name;
  }
  ASSERT_EQ(info.presets.size(), table.presets().size()) << pipeline;
  for (std::size_t i = 0; i < info.presets.size(); ++i) EXPECT_EQ(info.presets[i].name, table.presets()[i].name);
}

/// Every field set to a value other than its default survives json() -> parse(), in the table and
/// through the pipeline's configure(); every preset parses and validates.
template <class T>
void expectEveryFieldRoundTrips(const std::string& pipeline, const OptionTable<T>& table) {
  const T changed = everyFieldChanged(table);
  const std::string json = table.json(changed);
  const T read = table.parse(json, T{}, pipeline);
  for (std::size_t i = 0; i < table.fields().size(); ++i)
    EXPECT_EQ(table.get(read, i), table.get(changed, i)) << pipeline << " " << table.fields()[i].name;
  EXPECT_EQ(table.json(read), json) << pipeline;
  EXPECT_NO_THROW(createPipeline(pipeline, json)) << pipeline << ": " << json;
  for (const OptionPreset& preset : table.presets()) {
    EXPECT_NO_THROW(table.parse("{\"preset\": \"" + preset.name + "\"}", T{}, pipeline)) << preset.name;
    EXPECT_NO_THROW(createPipeline(pipeline, "{\"preset\": \"" + preset.name + "\"}")) << preset.name;
  }
}

/// configure()'s InvalidInput message for `options`, or "" when the pipeline takes them.
std::string configureError(const std::string& pipeline, const std::string& options) {
  registerBuiltinPipelines();
  try {
    createPipeline(pipeline, options);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

TEST(PipelineOptions, EveryDefaultValidates) {
  EXPECT_NO_THROW(RegionPipelineOptions{}.validate());
  EXPECT_NO_THROW(ColorPipelineOptions{}.validate());
  EXPECT_NO_THROW(BlueBandOptions{}.validate());
  EXPECT_NO_THROW(ClusterPerceptronPipelineOptions{}.validate());
  EXPECT_NO_THROW(EdgeTrackerOptions{}.validate());
  registerBuiltinPipelines();
  for (const PipelineInfo& info : listPipelines()) EXPECT_NO_THROW(createPipeline(info.name, "{}")) << info.name;
}

TEST(PipelineOptions, TheListingIsTheStructsDefaults) {
  expectListingIsTheDefaults("sidewalk", colorPipelineOptionTable());
  expectListingIsTheDefaults("color-rgb", colorPipelineOptionTable());
  expectListingIsTheDefaults("blue-band", blueBandOptionTable());
  expectListingIsTheDefaults("cluster-perceptron", clusterPerceptronPipelineOptionTable());
  expectListingIsTheDefaults("edge-tracker", edgeTrackerOptionTable());
}

TEST(PipelineOptions, EveryFieldRoundTrips) {
  registerBuiltinPipelines();
  expectEveryFieldRoundTrips("sidewalk", colorPipelineOptionTable());
  expectEveryFieldRoundTrips("color-rgb", colorPipelineOptionTable());
  expectEveryFieldRoundTrips("blue-band", blueBandOptionTable());
  expectEveryFieldRoundTrips("cluster-perceptron", clusterPerceptronPipelineOptionTable());
  expectEveryFieldRoundTrips("edge-tracker", edgeTrackerOptionTable());
}

TEST(PipelineOptions, ErrorsNameTheOptionAndItsValue) {
  EXPECT_EQ(configureError("sidewalk", R"({"no_such": 1})"), "pipeline \"sidewalk\": unknown option \"no_such\"");
  EXPECT_EQ(configureError("sidewalk", R"({"adaptive": 1})"),
            "pipeline \"sidewalk\": option adaptive = 1: must be true or false");
  EXPECT_EQ(configureError("color-rgb", R"({"blend": 2})"), "pipeline \"color-rgb\": option blend = 2: must be in (0, 1]");
  EXPECT_EQ(configureError("blue-band", R"({"block_size": 2.5})"),
            "pipeline \"blue-band\": option block_size = 2.5: must be an integer");
  EXPECT_EQ(configureError("blue-band", R"({"threshold": "otsu"})"),
            "pipeline \"blue-band\": option threshold = \"otsu\": must be a number");
  EXPECT_EQ(configureError("blue-band", "[1]"), "pipeline \"blue-band\": options must be a JSON object");
  EXPECT_EQ(configureError("cluster-perceptron", R"({"clusters": 31})"),
            "pipeline \"cluster-perceptron\": option clusters = 31: must be in [1, 30]");
  EXPECT_EQ(configureError("cluster-perceptron", R"({"texture_window": 8})"),
            "pipeline \"cluster-perceptron\": option texture_window = 8: must be odd");
  EXPECT_EQ(configureError("edge-tracker", R"({"window_rows": 2})"),
            "pipeline \"edge-tracker\": option window_rows = 2: must be >= 4");
  EXPECT_EQ(configureError("edge-tracker", R"({"band": "red"})"),
            "pipeline \"edge-tracker\": option band = \"red\": must be \"blue\", \"luminance\", \"normalized_green\" "
            "or \"normalized_red\"");
  // A rule between two fields is the struct's validate(), named by it.
  EXPECT_EQ(configureError("edge-tracker", R"({"max_points": 2})"),
            "pipeline \"edge-tracker\": EdgeTrackerOptions::max_points = 2: must be >= min_points");
}

TEST(PipelineOptions, ParkShadowsSetsTheArcModelInNormalisedColourWithEightClusters) {
  const auto& table = clusterPerceptronPipelineOptionTable();
  const ClusterPerceptronPipelineOptions o = table.parse(R"({"preset": "park-shadows"})", {}, "test");
  EXPECT_EQ(o.road_model, RoadModel::Arc);
  EXPECT_TRUE(o.normalized_color);
  EXPECT_EQ(o.clusters, 8);
  EXPECT_EQ(o.max_curvature, ClusterPerceptronPipelineOptions{}.max_curvature);  // the rest as they were
  // An explicit member overrides the preset, wherever it is written.
  const ClusterPerceptronPipelineOptions more = table.parse(R"({"clusters": 10, "preset": "park-shadows"})", {}, "test");
  EXPECT_EQ(more.clusters, 10);
  EXPECT_EQ(more.road_model, RoadModel::Arc);
  const PipelineInfo info = registered("cluster-perceptron");
  ASSERT_EQ(info.presets.size(), 1u);
  EXPECT_EQ(info.presets[0].name, "park-shadows");
  EXPECT_FALSE(info.presets[0].description.empty());
}

TEST(PipelineOptions, AnUnknownPresetIsAnErrorListingThePresets) {
  EXPECT_EQ(configureError("cluster-perceptron", R"({"preset": "sunny"})"),
            "pipeline \"cluster-perceptron\": unknown preset \"sunny\" (presets: park-shadows)");
  EXPECT_EQ(configureError("sidewalk", R"({"preset": "park-shadows"})"),
            "pipeline \"sidewalk\": unknown preset \"park-shadows\" (there are none)");
}

}  // namespace
}  // namespace mapnav
