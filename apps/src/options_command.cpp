#include "options_command.h"

#include <algorithm>
#include <ostream>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "command_line.h"
#include "command_support.h"
#include "mapnav/core/error.h"
#include "mapnav/eval/segmentation_evaluation.h"
#include "mapnav/learned/learned_pipeline.h"
#include "mapnav/learned/train_segmentation.h"
#include "mapnav/localization/filter_supervisor.h"
#include "mapnav/localization/line_fit.h"
#include "mapnav/localization/localize.h"
#include "mapnav/localization/pose_filter.h"
#include "mapnav/localization/relocalize.h"
#include "mapnav/logs/kitti_import.h"
#include "mapnav/logs/kitti_raw_import.h"
#include "mapnav/logs/gnss.h"
#include "mapnav/logs/odometry.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/map/generate.h"
#include "mapnav/map/geojson.h"
#include "mapnav/map/map_render.h"
#include "mapnav/map/predict.h"
#include "mapnav/map/predict_render.h"
#include "mapnav/map/random_campus.h"
#include "mapnav/map/validation.h"
#include "mapnav/mission/blackboard.h"
#include "mapnav/mission/mission_file.h"
#include "mapnav/mission/modules.h"
#include "mapnav/mission/path_agreement.h"
#include "mapnav/mission/track.h"
#include "mapnav/mission/report.h"
#include "mapnav/mission/runner.h"
#include "mapnav/mission_sim/simulate.h"
#include "mapnav/mission_sim/suite.h"
#include "mapnav/navigator/progress.h"
#include "mapnav/navigator/route.h"
#include "mapnav/navigator/steering.h"
#include "mapnav/navigator/vehicle.h"
#include "mapnav/osm/osm_import.h"
#include "mapnav/sim/map_error.h"
#include "mapnav/sim/world.h"
#include "mapnav/vision/bev_eval.h"
#include "mapnav/vision/cluster_perceptron.h"
#include "mapnav/vision/color_classifier.h"
#include "mapnav/vision/edge_tracker.h"
#include "mapnav/vision/ground_step.h"
#include "mapnav/vision/landmarks.h"
#include "mapnav/vision/line_labelling.h"
#include "mapnav/vision/pipelines.h"
#include "mapnav/vision/rectify.h"
#include "mapnav/vision/region.h"
#include "mapnav/vision/segmentation_eval.h"

namespace mapnav::cli {

namespace {

template <class T>
OptionTableEntry entry(const OptionTable<T>& (*table)(), std::string header, std::string set_by) {
  return {std::move(header), std::move(set_by), [table] { return table().describe(); }};
}

const std::string kPipeline = "a pipeline's options: a mission's `vision.options`, `--options` of detect, segment, eval and log track";
const std::string kCode = "C++ and Python";

}  // namespace

// How a table's struct is set comes from the command flags and file objects that read it; the
// module's order is that of the layout (README), the structs' within a module that of their headers.
const std::vector<OptionTableEntry>& optionTables() {
  static const std::vector<OptionTableEntry> tables = {
      entry(&gridMapOptionTable, "map/include/mapnav/map/generate.h", kCode),
      entry(&geoJsonImportOptionTable, "map/include/mapnav/map/geojson.h", "`mapnav map import-geojson`'s flags; C++ and Python"),
      entry(&mapRenderOptionTable, "map/include/mapnav/map/map_render.h", "`mapnav map render`'s flags; C++"),
      entry(&predictOptionTable, "map/include/mapnav/map/predict.h", "`mapnav predict`; the Map module (MapModuleOptions::predict); C++ and Python"),
      entry(&predictionPictureOptionTable, "map/include/mapnav/map/predict_render.h", "`mapnav predict --png`; C++"),
      entry(&randomCampusOptionTable, "map/include/mapnav/map/random_campus.h", "`mapnav map random-campus` and `mapnav suite`; C++"),
      entry(&validationOptionTable, "map/include/mapnav/map/validation.h", "`mapnav map validate`; C++ and Python"),
      entry(&osmImportOptionTable, "osm/include/mapnav/osm/osm_import.h", "`mapnav map import-osm`'s flags; C++"),
      entry(&progressOptionTable, "navigator/include/mapnav/navigator/progress.h", kCode),
      entry(&routeOptionTable, "navigator/include/mapnav/navigator/route.h", "`mapnav route`'s flags; C++ and Python"),
      entry(&centerServoOptionTable, "navigator/include/mapnav/navigator/steering.h", kCode),
      entry(&purePursuitOptionTable, "navigator/include/mapnav/navigator/steering.h", kCode),
      entry(&vehicleLimitsOptionTable, "navigator/include/mapnav/navigator/vehicle.h", kCode),
      entry(&lineMatchOptionTable, "localization/include/mapnav/localization/line_fit.h", kCode),
      entry(&localizeOptionTable, "localization/include/mapnav/localization/localize.h", kCode),
      entry(&filterOptionTable, "localization/include/mapnav/localization/pose_filter.h", kCode),
      entry(&motionNoiseOptionTable, "localization/include/mapnav/localization/pose_filter.h", kCode),
      entry(&relocalizeOptionTable, "localization/include/mapnav/localization/relocalize.h", kCode),
      entry(&filterSupervisorOptionTable, "localization/include/mapnav/localization/filter_supervisor.h",
            "the Map module (MapModuleOptions::supervisor, as park_reset_*); C++"),
      entry(&bevGridOptionTable, "vision/include/mapnav/vision/bev_eval.h",
            "`mapnav eval segmentation --bev-range` and `--bev-cell`; C++ and Python"),
      entry(&clusterPerceptronOptionTable, "vision/include/mapnav/vision/cluster_perceptron.h", kCode),
      entry(&clusterPerceptronPipelineOptionTable, "vision/include/mapnav/vision/cluster_perceptron.h", kPipeline + " (cluster-perceptron)"),
      entry(&colorClassifierOptionTable, "vision/include/mapnav/vision/color_classifier.h", kCode),
      entry(&edgeTrackerOptionTable, "vision/include/mapnav/vision/edge_tracker.h", kPipeline + " (edge-tracker)"),
      entry(&groundStepOptionTable, "vision/include/mapnav/vision/ground_step.h", kCode),
      entry(&landmarkFinderOptionTable, "vision/include/mapnav/vision/landmarks.h", kCode),
      entry(&lineOptionTable, "vision/include/mapnav/vision/line_labelling.h", kCode),
      entry(&blueBandOptionTable, "vision/include/mapnav/vision/pipelines.h", kPipeline + " (blue-band)"),
      entry(&colorPipelineOptionTable, "vision/include/mapnav/vision/pipelines.h", kPipeline + " (color-rgb, sidewalk)"),
      entry(&regionPipelineOptionTable, "vision/include/mapnav/vision/pipelines.h", kCode),
      entry(&scorePipelineOptionTable, "vision/include/mapnav/vision/pipelines.h", kCode),
      entry(&rectifyOptionTable, "vision/include/mapnav/vision/rectify.h", "`mapnav rectify`'s flags; C++"),
      entry(&regionOptionTable, "vision/include/mapnav/vision/region.h", kCode),
      entry(&trapezoidOptionTable, "vision/include/mapnav/vision/segmentation_eval.h",
            "`mapnav log track --trapezoid`, the eval's bootstrap region; C++"),
      entry(&learnedPipelineOptionTable, "learned/include/mapnav/learned/learned_pipeline.h", kPipeline + " (learned)"),
      entry(&segmentationTrainOptionTable, "learned/include/mapnav/learned/train_segmentation.h", "`mapnav train segmentation --options`; C++"),
      entry(&kittiImportOptionTable, "logs/include/mapnav/logs/kitti_import.h", "`mapnav log import-kitti`'s flags; C++"),
      entry(&kittiRawImportOptionTable, "logs/include/mapnav/logs/kitti_raw_import.h", "`mapnav log import-kitti-raw`'s flags; C++"),
      entry(&odometryNoiseOptionTable, "logs/include/mapnav/logs/odometry.h", "a mission's `odometry` object; C++"),
      entry(&gnssReceiverOptionTable, "logs/include/mapnav/logs/gnss.h",
            "`mapnav log import-kitti-raw --gnss-*` (KittiRawImportOptions::gnss, as gnss_*), a mission's `world.gnss` object; C++"),
      entry(&logHeaderOptionTable, "logs/include/mapnav/logs/replay_log.h", "a replay log's header (docs/replay-log-format.md)"),
      entry(&readOptionTable, "logs/include/mapnav/logs/replay_log.h", kCode),
      entry(&worldOptionTable, "sim/include/mapnav/sim/world.h", "a mission's `world` object; C++"),
      entry(&mapErrorOptionTable, "sim/include/mapnav/sim/map_error.h",
            "a mission's `world.map_error` object, `mapnav suite random-campus --map-error-m`; C++"),
      entry(&missionFileOptionTable, "mission/include/mapnav/mission/mission_file.h", "a mission file's numbers (docs/mission-format.md)"),
      entry(&blackboardOptionTable, "mission/include/mapnav/mission/blackboard.h", kCode),
      entry(&mapModuleOptionTable, "mission/include/mapnav/mission/modules.h", kCode),
      entry(&navigatorOptionTable, "mission/include/mapnav/mission/modules.h", kCode),
      entry(&pathAgreementOptionTable, "mission/include/mapnav/mission/path_agreement.h", kCode),
      entry(&trackOptionTable, "mission/include/mapnav/mission/track.h", "`mapnav log track --row` and `--max-frames`; C++"),
      entry(&reportOptionTable, "mission/include/mapnav/mission/report.h", "`mapnav replay --report`; C++"),
      entry(&runOptionTable, "mission/include/mapnav/mission/runner.h", "`mapnav replay` and `mapnav run` flags; C++ and Python"),
      entry(&suiteOptionTable, "mission_sim/include/mapnav/mission_sim/suite.h", "`mapnav suite random-campus`'s flags; C++"),
      entry(&simulateOptionTable, "mission_sim/include/mapnav/mission_sim/simulate.h", "`mapnav simulate`'s flags; C++ and Python"),
      entry(&segmentationEvalOptionTable, "eval/include/mapnav/eval/segmentation_evaluation.h",
            "`mapnav eval segmentation`'s flags; C++ and Python (evaluate_segmentation)"),
  };
  return tables;
}

const std::vector<std::pair<std::string, std::string>>& pipelineOptionStructs() {
  static const std::vector<std::pair<std::string, std::string>> pipelines = {
      {"blue-band", "BlueBandOptions"},           {"cluster-perceptron", "ClusterPerceptronPipelineOptions"},
      {"color-rgb", "ColorPipelineOptions"},      {"edge-tracker", "EdgeTrackerOptions"},
      {"learned", "LearnedPipelineOptions"},      {"sidewalk", "ColorPipelineOptions"}};
  return pipelines;
}

namespace {

using OrderedJson = nlohmann::ordered_json;

/// The `vision` object's rule: its `options` are those of the pipeline it names (a plug-in's are
/// not known here, so any object).
OrderedJson visionPipelineSchema() {
  OrderedJson all = OrderedJson::array();
  for (const auto& [pipeline, owner] : pipelineOptionStructs()) {
    all.push_back({{"if", {{"properties", {{"pipeline", {{"const", pipeline}}}}}, {"required", {"pipeline"}}}},
                   {"then", {{"properties", {{"options", {{"$ref", "#/$defs/" + owner}}}}}}}});
  }
  return {{"title", "a vision object's options by its pipeline"}, {"allOf", all}};
}

std::vector<const OptionTableEntry*> chosen(const std::vector<std::string>& names) {
  std::vector<const OptionTableEntry*> out;
  for (const std::string& name : names) {
    const auto& tables = optionTables();
    const auto it = std::find_if(tables.begin(), tables.end(), [&](const OptionTableEntry& e) { return e.describe().owner == name; });
    if (it == tables.end()) throw NotFound("no option struct \"" + name + "\" (`mapnav options` lists them)");
    out.push_back(&*it);
  }
  return out;
}

}  // namespace

std::string optionsSchemaDocument() {
  OrderedJson doc = {{"$schema", "https://json-schema.org/draft/2020-12/schema"},
                     {"title", "mapnav option objects"},
                     {"description",
                      "The JSON objects of options that mapnav's option structs read, one definition per struct, each "
                      "with its defaults and rules. Generated from the option tables by `mapnav options --schema` "
                      "(scripts/update_option_docs.py writes this file): do not edit. docs/options.md says the same in prose."},
                     {"$defs", OrderedJson::object()}};
  for (const OptionTableEntry& entry : optionTables()) {
    const OptionTableDescription table = entry.describe();
    doc["$defs"][table.owner] = OrderedJson::parse(optionSchemaJson(table));
  }
  doc["$defs"]["VisionPipelineOptions"] = visionPipelineSchema();
  // A mission's `world`: WorldOptions and the map error the world is drawn with.
  OrderedJson world = doc["$defs"]["WorldOptions"];
  world["title"] =
      "a mission's world: WorldOptions, the map it is drawn from, its map_error (MapErrorOptions) and the vehicle's GNSS "
      "receiver (GnssReceiverOptions)";
  world["properties"]["map_error"] = {{"$ref", "#/$defs/MapErrorOptions"}};
  world["properties"]["gnss"] = {{"$ref", "#/$defs/GnssReceiverOptions"}};
  world["properties"]["map"] = {
      {"type", "string"},
      {"description",
       "the map file the world is drawn from instead of the mission's map (relative to the mission file; its roads "
       "and intersections carry the mission map's ids): a map that is wrong somewhere"}};
  doc["$defs"]["MissionWorld"] = world;
  return doc.dump();
}

std::string optionsMarkdownDocument() {
  std::string out =
      "# Options\n\n"
      "<!-- Generated from the option tables by `mapnav options --markdown` (scripts/update_option_docs.py): do not edit. -->\n\n"
      "Every option struct of mapnav with its options, defaults and rules, as its table states them\n"
      "(`core/include/mapnav/core/option_table.h`); a value outside its rule is refused with the struct,\n"
      "the field and the value named. The same as JSON Schema: `maps/schema/mapnav-options-1.schema.json`.\n"
      "`mapnav options NAME` prints one struct's section.\n\n"
      "A pipeline's options by pipeline:\n\n";
  for (const auto& [pipeline, owner] : pipelineOptionStructs()) out += "- `" + pipeline + "`: " + owner + "\n";
  for (const OptionTableEntry& entry : optionTables()) {
    out += "\n" + optionMarkdown(entry.describe());
    out += "\nIn `" + entry.header + "`; set by " + entry.set_by + ".\n";
  }
  return out;
}

int runOptions(const OptionsConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    const std::vector<const OptionTableEntry*> entries = chosen(config.names);
    if (config.schema) {
      if (entries.empty()) {
        out << OrderedJson::parse(optionsSchemaDocument()).dump(2) << "\n";
      } else {
        for (const OptionTableEntry* entry : entries) out << OrderedJson::parse(optionSchemaJson(entry->describe())).dump(2) << "\n";
      }
    } else if (config.markdown && entries.empty()) {
      out << optionsMarkdownDocument();
    } else if (entries.empty()) {
      for (const OptionTableEntry& entry : optionTables()) {
        const OptionTableDescription table = entry.describe();
        out << table.owner << "    " << table.fields.size() << " options    " << entry.header << "\n";
      }
    } else {
      for (const OptionTableEntry* entry : entries) out << optionMarkdown(entry->describe());
    }
    return static_cast<int>(kOk);
  });
}

void registerOptionsCommand(CLI::App& app, Commands& commands) {
  auto* config = commands.hold<OptionsConfig>();
  CLI::App* c = app.add_subcommand(
      "options",
      "List the option structs and their options, defaults and rules (from their tables); print their JSON Schema or "
      "docs/options.md");
  c->add_option("names", config->names, "Option structs to show, by name (WorldOptions, EdgeTrackerOptions, ...); none: list them all");
  c->add_flag("--schema", config->schema,
              "Print the JSON Schema of the named structs' option objects, or with no name the whole "
              "maps/schema/mapnav-options-1.schema.json");
  c->add_flag("--markdown", config->markdown, "Print docs/options.md (with names: their sections, the default)");
  c->callback(commands.choose([config](std::ostream& out, std::ostream& err) { return runOptions(*config, out, err); }));
}

}  // namespace mapnav::cli
