// What is generated from the option tables — maps/schema/mapnav-options-1.schema.json, docs/options.md
// and the option definitions of the mission schema — is what is committed, and `mapnav options`
// prints them. A failure here means a default, rule or doc changed: run
// `scripts/update_option_docs.py build/bin/mapnav` and commit the files it rewrites.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "mapnav/core/option_table.h"
#include "mapnav/testing/support.h"
#include "mapnav/vision/pipelines.h"
#include "mapnav/vision_iface/pipeline.h"
#include "options_command.h"

namespace mapnav {
namespace {

using OrderedJson = nlohmann::ordered_json;
const char* const kRegenerateOptionDocs = "; run scripts/update_option_docs.py build/bin/mapnav and commit what it writes";

std::string optionDocText(const std::string& relative) {
  std::ifstream in(testing::sourceDir() / relative);
  EXPECT_TRUE(in) << relative << ": cannot be read";
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

OrderedJson optionDocJson(const std::string& relative) { return OrderedJson::parse(optionDocText(relative)); }

TEST(OptionDocs, TheCommittedOptionsSchemaIsWhatTheTablesSay) {
  const auto r = testing::runCli({"options", "--schema"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(OrderedJson::parse(r.out), optionDocJson("maps/schema/mapnav-options-1.schema.json"))
      << "maps/schema/mapnav-options-1.schema.json differs from the tables" << kRegenerateOptionDocs;
}

TEST(OptionDocs, TheCommittedOptionsDocIsWhatTheTablesSay) {
  const auto r = testing::runCli({"options", "--markdown"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, optionDocText("docs/options.md")) << "docs/options.md differs from the tables" << kRegenerateOptionDocs;
}

// The mission schema's `world`, `odometry` and `vision` objects are checked by the tables' own
// definitions, each copied whole.
TEST(OptionDocs, TheMissionSchemaCarriesTheGeneratedDefinitions) {
  const OrderedJson mission = optionDocJson("maps/schema/mapnav-mission-1.schema.json");
  const OrderedJson options = OrderedJson::parse(cli::optionsSchemaDocument());
  EXPECT_EQ(mission["properties"]["world"]["$ref"], "#/$defs/MissionWorld");
  EXPECT_EQ(mission["properties"]["odometry"]["$ref"], "#/$defs/OdometryNoiseOptions");
  EXPECT_EQ(mission["properties"]["vision"]["$ref"], "#/$defs/VisionPipelineOptions");
  EXPECT_EQ(mission["properties"]["speed_mps"]["$ref"], "#/$defs/MissionFile/properties/speed_mps");
  int copied = 0;
  for (const auto& [name, definition] : mission["$defs"].items()) {
    if (!options["$defs"].contains(name)) continue;
    EXPECT_EQ(definition, options["$defs"][name]) << "the mission schema's $defs/" << name << kRegenerateOptionDocs;
    ++copied;
  }
  // MissionFile, MissionWorld, MapErrorOptions, GnssReceiverOptions, OdometryNoiseOptions,
  // VisionPipelineOptions and the five option structs of the six pipelines.
  EXPECT_EQ(copied, 11);
}

// Each table's defaults, as a default-constructed struct holds them, are the committed schema's
// "default"s, and they keep the table's own rules.
TEST(OptionDocs, EveryTablesDefaultsAreTheCommittedSchemasAndValid) {
  const OrderedJson defs = optionDocJson("maps/schema/mapnav-options-1.schema.json")["$defs"];
  ASSERT_EQ(cli::optionTables().size(), 55u);
  for (const cli::OptionTableEntry& entry : cli::optionTables()) {
    const OptionTableDescription table = entry.describe();
    ASSERT_TRUE(defs.contains(table.owner)) << table.owner << kRegenerateOptionDocs;
    const OrderedJson& properties = defs[table.owner]["properties"];
    for (std::size_t i = 0; i < table.fields.size(); ++i) {
      const OrderedJson value = OrderedJson::parse(table.defaults[i]);
      const OrderedJson& committed = properties[table.fields[i].name];
      EXPECT_EQ(committed.value("default", OrderedJson()), value) << table.owner << "::" << table.fields[i].name << kRegenerateOptionDocs;
    }
  }
}

// Every built-in pipeline's options are the table the mission schema checks them by.
TEST(OptionDocs, EachBuiltInPipelinesOptionsAreItsStructsTable) {
  registerBuiltinPipelines();
  const auto& structs = cli::pipelineOptionStructs();
  int checked = 0;
  for (const PipelineInfo& info : listPipelines()) {
    const auto it = std::find_if(structs.begin(), structs.end(), [&](const auto& p) { return p.first == info.name; });
    ASSERT_NE(it, structs.end()) << "pipeline " << info.name << " has no option struct in pipelineOptionStructs()";
    const auto& tables = cli::optionTables();
    const auto table = std::find_if(tables.begin(), tables.end(), [&](const auto& e) { return e.describe().owner == it->second; });
    ASSERT_NE(table, tables.end()) << it->second;
    const OptionTableDescription d = table->describe();
    ASSERT_EQ(info.options.size(), d.fields.size()) << info.name;
    for (std::size_t i = 0; i < d.fields.size(); ++i) {
      EXPECT_EQ(info.options[i].name, d.fields[i].name) << info.name;
      EXPECT_EQ(info.options[i].default_json, d.defaults[i]) << info.name << " " << d.fields[i].name;
    }
    ++checked;
  }
  EXPECT_EQ(checked, 5);  // blue-band, cluster-perceptron, color-rgb, edge-tracker, sidewalk ("learned" is a module)
}

TEST(OptionsCli, ListsPrintsAndRefusesAnUnknownStruct) {
  const auto list = testing::runCli({"options"});
  ASSERT_EQ(list.exit_code, 0) << list.err;
  EXPECT_NE(list.out.find("WorldOptions    28 options    sim/include/mapnav/sim/world.h\n"), std::string::npos) << list.out;
  const auto one = testing::runCli({"options", "OdometryNoiseOptions"});
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_EQ(one.out.rfind("### OdometryNoiseOptions\n", 0), 0u) << one.out;
  EXPECT_NE(one.out.find("| `scale_error` | `0` | in [-0.49, 0.49] |"), std::string::npos) << one.out;
  const auto schema = testing::runCli({"options", "--schema", "OdometryNoiseOptions"});
  ASSERT_EQ(schema.exit_code, 0) << schema.err;
  EXPECT_EQ(OrderedJson::parse(schema.out)["properties"]["gyro_bias_deg_s"]["maximum"], 10);
  const auto unknown = testing::runCli({"options", "WordOptions"});
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_EQ(unknown.err, "mapnav: error: no option struct \"WordOptions\" (`mapnav options` lists them)\n");
  EXPECT_TRUE(unknown.out.empty());
}

}  // namespace
}  // namespace mapnav
