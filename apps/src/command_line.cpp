// What the registrars share (command_line.h): the chosen command and the checks of common options.
#include "command_line.h"

#include <cctype>
#include <filesystem>

#include "cli.h"

namespace mapnav::cli {

std::function<void()> Commands::choose(Body body) {
  return [this, body = std::move(body)] { chosen_ = body; };
}

int Commands::run(std::ostream& out, std::ostream& err) const {
  return chosen_ ? chosen_(out, err) : static_cast<int>(kUsage);
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

}  // namespace mapnav::cli
