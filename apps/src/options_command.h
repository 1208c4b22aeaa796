#pragma once
// `mapnav options`: every option struct's table (core/option_table.h) — its options, defaults and
// rules — and what is generated from the tables: the JSON Schema of the option objects
// (maps/schema/mapnav-options-1.schema.json, whose definitions the mission schema copies) and
// docs/options.md. A test compares the committed files with what this command prints.
#include <functional>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "mapnav/core/option_table.h"

namespace mapnav::cli {

/// One option struct with a table: where it is documented and how a user sets it.
struct OptionTableEntry {
  std::string header;  ///< the header that documents the struct, from the source root
  std::string set_by;  ///< how a user sets it ("a mission's `world` object", "C++ and Python")
  std::function<OptionTableDescription()> describe;
};

/// Every option struct with a table, module by module (map, osm, navigator, localization, vision, learned, sim, mission).
const std::vector<OptionTableEntry>& optionTables();

/// The option struct of each built-in pipeline's options, by pipeline name (the mission schema's
/// `vision` object checks its `options` against it).
const std::vector<std::pair<std::string, std::string>>& pipelineOptionStructs();

struct OptionsConfig {
  std::vector<std::string> names;  ///< the structs to show (OWNER names); none: the list of them all
  bool schema = false;             ///< the JSON Schema of the named ones, or of every one
  bool markdown = false;           ///< docs/options.md, or the named ones' sections
};

/// The JSON Schema document of every option object (maps/schema/mapnav-options-1.schema.json), as
/// one line of JSON: each table's optionSchemaJson() under $defs/OWNER.
std::string optionsSchemaDocument();
/// docs/options.md: a preamble, then each table's optionMarkdown() section.
std::string optionsMarkdownDocument();

int runOptions(const OptionsConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
