#pragma once
// The command line's side of the commands (internal to apps/; the one header that includes CLI11):
// each command group's file has a registrar that adds its subcommands with their options, --help
// texts and a callback choosing what runs once the whole line is parsed; cli.cpp calls the
// registrars in the order `mapnav --help` lists the commands.
#include <CLI/CLI.hpp>

#include <functional>
#include <iosfwd>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "mapnav/core/option_table.h"

namespace mapnav::cli {

/// The command the line chose, and the values the options are parsed into.
class Commands {
 public:
  /// What runs once the line is parsed, with the CLI's streams; returns the exit code.
  using Body = std::function<int(std::ostream& out, std::ostream& err)>;

  /// A new T that lives as long as this: what a registrar binds its options to and its body reads.
  template <class T>
  T* hold() {
    auto value = std::make_shared<T>();
    held_.push_back(value);
    return value.get();
  }
  /// A subcommand's callback: when CLI11 calls it (the subcommand was given), `body` is what runs.
  std::function<void()> choose(Body body);
  /// Runs the chosen body under guarded() (command_support.h), which turns what it throws into a
  /// message and the exit code of its kind; 2 (usage) when none was chosen.
  int run(std::ostream& out, std::ostream& err) const;

  /// `range` (CLI::Range, CLI::PositiveNumber, CLI::NonNegativeNumber) as a check of the value: a
  /// number out of its range is wrong input (exit 1), as every value mapnav checks itself, while CLI11
  /// still reports it in its words. A value that is not a number at all stays a usage error (exit 2),
  /// as CLI11's type check has it.
  CLI::Validator numberCheck(const CLI::Validator& range) { return valueCheck(range, true); }
  /// The rule of `table`'s field `field` as numberCheck() of a flag's value, in the table's words
  /// ("must be in [1, 8]"): a flag that sets an option states no range of its own.
  template <class T>
  CLI::Validator ruleCheck(const OptionTable<T>& table, std::string_view field) {
    for (const OptionFieldSpec& spec : table.fields())
      if (spec.name == field) return numberCheck(fieldRule(spec));
    throw std::logic_error(table.owner() + " has no field \"" + std::string(field) + "\"");
  }
  /// `names` (CLI::IsMember) as a check of the value: a name not among them is wrong input (exit 1).
  CLI::Validator nameCheck(const CLI::Validator& names) { return valueCheck(names, false); }
  /// Whether a numberCheck() or nameCheck() rejected a value of the line parsed (cli.cpp: the exit
  /// code of CLI11's error).
  bool valueRejected() const { return *value_rejected_; }

 private:
  CLI::Validator valueCheck(const CLI::Validator& check, bool numeric);
  static CLI::Validator fieldRule(const OptionFieldSpec& field);

  std::vector<std::shared_ptr<void>> held_;
  Body chosen_;
  std::shared_ptr<bool> value_rejected_ = std::make_shared<bool>(false);
};

/// Outputs whose format is chosen by the extension: pictures (.png, .svg), and where a command
/// can write GeoJSON, .geojson too.
CLI::Validator outputFile(bool geojson);

/// --pipeline (default `default_pipeline`), --options (a JSON object, default "{}") and --plugin, as
/// every command that runs a vision pipeline on frames has them.
void addPipelineOptions(CLI::App* command, std::string& pipeline, std::string& options_json,
                        std::vector<std::string>& plugins, const std::string& default_pipeline);

/// --map-options JSON: the Map module's options (MapModuleOptions) for the commands that run missions;
/// parseMapModuleOptions (command_support.h) reads it.
void addMapOptionsFlag(CLI::App* command, std::string& map_options_json);

// The registrars, in the order of `mapnav --help`; each is defined in its command group's file.
void registerMapCommands(CLI::App& app, Commands& commands);      // map validate|info|render|import-*|export-*
void registerPredictCommand(CLI::App& app, Commands& commands);   // predict
void registerRouteCommand(CLI::App& app, Commands& commands);     // route
void registerSimulateCommand(CLI::App& app, Commands& commands);  // simulate
void registerLogCommands(CLI::App& app, Commands& commands);      // log info|frame|import-kitti|track
void registerTrackCommand(CLI::App& log, Commands& commands);     // log track (under `log`)
void registerMissionCommands(CLI::App& app, Commands& commands);  // replay, run, demo, trace show
void registerPipelinesCommand(CLI::App& app, Commands& commands); // pipelines
void registerOptionsCommand(CLI::App& app, Commands& commands);   // options
void registerDetectCommands(CLI::App& app, Commands& commands);   // detect, segment
void registerVisionCommands(CLI::App& app, Commands& commands);   // rectify, calibrate chessboard|tilt
void registerEvalCommands(CLI::App& app, Commands& commands);     // eval segmentation
void registerBenchCommand(CLI::App& app, Commands& commands);     // bench
void registerTrainCommand(CLI::App& app, Commands& commands);     // train segmentation (MAPNAV_LEARNED builds)
void registerSuiteCommand(CLI::App& app, Commands& commands);     // suite random-campus

}  // namespace mapnav::cli
