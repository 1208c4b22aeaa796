// What the registrars share (command_line.h): the chosen command and the checks of common options.
#include "command_line.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "cli.h"
#include "command_support.h"

namespace mapnav::cli {

std::function<void()> Commands::choose(Body body) {
  return [this, body = std::move(body)] { chosen_ = body; };
}

int Commands::run(std::ostream& out, std::ostream& err) const {
  if (!chosen_) return kUsage;
  return guarded(err, [&] { return chosen_(out, err); });
}

namespace {

/// Whether `text` is a number as a whole (what CLI11's conversion of a numeric option accepts).
bool isNumber(const std::string& text) {
  char* end = nullptr;
  errno = 0;
  std::strtod(text.c_str(), &end);
  return !text.empty() && end == text.c_str() + text.size() && errno != ERANGE;
}

}  // namespace

CLI::Validator Commands::valueCheck(const CLI::Validator& check, bool numeric) {
  return CLI::Validator(
      [check, numeric, rejected = value_rejected_](std::string& value) {
        std::string message = check(value);
        if (!message.empty() && (!numeric || isNumber(value))) *rejected = true;
        return message;
      },
      check.get_description(), check.get_name());
}

CLI::Validator Commands::fieldRule(const OptionFieldSpec& field) {
  const bool integer = field.kind == OptionKind::Integer;
  const std::string rule = (integer ? "an integer " : "") + field.rule.rangeText(false);
  return CLI::Validator(
      [field, rule, integer](std::string& text) {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size()) return std::string();  // CLI11's type check says it
        const bool ok = field.rule.allows(value) && (!integer || value == std::floor(value)) &&
                        (!field.rule.odd || std::fmod(std::abs(value), 2.0) == 1.0);
        return ok ? std::string() : "Value " + text + " must be " + rule + (field.rule.odd ? ", odd" : "");
      },
      rule, field.name);
}

CLI::Validator outputFile(bool geojson) {
  return CLI::Validator(
      [geojson](std::string& path) {
        std::string ext = std::filesystem::path(path).extension().string();
        for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (ext == ".png" || ext == ".svg" || (geojson && ext == ".geojson")) return std::string();
        return "\"" + path + "\": the output must be .png or .svg" + std::string(geojson ? " or .geojson" : "");
      },
      geojson ? "OUT.png|OUT.svg|OUT.geojson" : "OUT.png|OUT.svg");
}

void addPipelineOptions(CLI::App* command, std::string& pipeline, std::string& options_json,
                        std::vector<std::string>& plugins, const std::string& default_pipeline) {
  command->add_option("--pipeline", pipeline, "Vision pipeline (mapnav pipelines lists them)")->default_val(default_pipeline);
  command->add_option("--options", options_json, "The pipeline's options as a JSON object")->default_val("{}");
  command->add_option("--plugin", plugins, "Load a vision plug-in first");
}

void addMapOptionsFlag(CLI::App* command, std::string& map_options_json) {
  command->add_option("--map-options", map_options_json,
                      "The Map module's options as a JSON object (`mapnav options MapModuleOptions` lists them; default: "
                      "theirs), e.g. '{\"park_reset_after_rejections\": 3}' to turn the filter's supervisor on");
}

}  // namespace mapnav::cli
