// `mapnav log track`: the options, the call to the tracking loop (mapnav/mission/track.h), the
// overlays and contact sheet, and the per-frame table or JSON.
#include "track_command.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <ostream>
#include <sstream>

#include "cli.h"
#include "command_line.h"
#include "command_support.h"
#include "json_numbers.h"
#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/image/png.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/mission/track.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision_iface/pipeline.h"
#include "pipelines_command.h"

namespace mapnav::cli {

namespace fs = std::filesystem;

namespace {

/// `v` with `digits` decimals, or "-".
std::string fixedOrDash(const std::optional<double>& v, int digits) { return fixedOr(v, digits, "-"); }

/// One overlay per frame, 000000.png, 000001.png, ... in config.overlays.
void writeOverlays(const LogTrackConfig& config, const std::vector<Image>& overlays) {
  if (config.overlays.empty()) return;
  fs::create_directories(config.overlays);
  for (std::size_t i = 0; i < overlays.size(); ++i) {
    std::ostringstream name;
    name << std::setw(6) << std::setfill('0') << i << ".png";
    writePng(overlays[i], fs::path(config.overlays) / name.str());
  }
}

/// Eight frames evenly spread from the first to the last, at half size, two a row.
void writeContactSheet(const LogTrackConfig& config, const std::vector<Image>& overlays) {
  if (config.contact_sheet.empty() || overlays.empty()) return;
  constexpr std::size_t kTiles = 8;
  std::vector<Image> tiles;
  std::vector<std::string> captions;
  const std::size_t n = std::min(kTiles, overlays.size());
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = n == 1 ? 0 : (k * (overlays.size() - 1) + (n - 1) / 2) / (n - 1);
    tiles.push_back(overlays[i]);
    captions.push_back(config.pipeline + ", frame " + std::to_string(i));
  }
  writePng(contactSheet(tiles, captions, 2, 0.5), config.contact_sheet);
}

void printJson(const LogTrackConfig& config, const TrackRun& run, std::ostream& out) {
  Json per_frame = Json::array();
  for (std::size_t i = 0; i < run.frames.size(); ++i) {
    const TrackedFrame& f = run.frames[i];
    per_frame.push_back({{"frame", i},
                         {"ok", f.ok},
                         {"reason", f.ok ? Json(nullptr) : Json(f.reason)},
                         {"left_u", roundedOrNull(f.left_u, 1)},
                         {"right_u", roundedOrNull(f.right_u, 1)},
                         {"centre_u", roundedOrNull(f.centre_u, 1)},
                         {"path_status", std::string(toString(f.path.status))},
                         {"path_inside", roundedOrNull(f.path.inside_fraction, 3)},
                         {"ground_share", roundedOrNull(f.path.ground_share, 3)},
                         {"path_angle_deg", roundedOrNull(f.path.angle_deg, 2)},
                         {"path_offset_m", roundedOrNull(f.path.offset_m, 3)}});
  }
  const Json j = {{"log", config.dir},
                  {"pipeline", config.pipeline},
                  {"frames", run.frames.size()},
                  {"tracked", run.tracked()},
                  {"row", run.row},
                  {"max_jump_px",
                   {{"left", roundedOrNull(run.maxJump(&TrackedFrame::left_u), 1)},
                    {"right", roundedOrNull(run.maxJump(&TrackedFrame::right_u), 1)},
                    {"centre", roundedOrNull(run.maxJump(&TrackedFrame::centre_u), 1)}}},
                  {"path_agreement", Json::parse(pathAgreementJson(run.pathAgreement(), run.path_options))},
                  {"per_frame", per_frame}};
  out << dumpJson(j);
}

void printTable(const LogTrackConfig& config, const TrackRun& run, std::ostream& out) {
  out << "frame  left_u  right_u  centre_u  inside  angle_deg  offset_m   (row " << run.row << "; path agreement)\n";
  for (std::size_t i = 0; i < run.frames.size(); ++i) {
    const TrackedFrame& f = run.frames[i];
    out << std::setw(5) << i << "  " << std::setw(6) << fixedOrDash(f.left_u, 1) << "  " << std::setw(7)
        << fixedOrDash(f.right_u, 1) << "  " << std::setw(8) << fixedOrDash(f.centre_u, 1) << "  " << std::setw(6)
        << fixedOrDash(f.path.inside_fraction, 3) << "  " << std::setw(9) << fixedOrDash(f.path.angle_deg, 2) << "  "
        << std::setw(8) << fixedOrDash(f.path.offset_m, 3);
    if (f.path.status != PathStatus::Measured) out << "  " << toString(f.path.status);
    if (!f.ok) out << "  failed: " << f.reason;
    out << "\n";
  }
  out << pathAgreementText(run.pathAgreement(), run.path_options);
  out << config.pipeline << ": " << run.tracked() << " of " << run.frames.size()
      << " frames tracked; largest frame-to-frame jump on row " << run.row << ": left "
      << fixedOrDash(run.maxJump(&TrackedFrame::left_u), 1) << " px, right "
      << fixedOrDash(run.maxJump(&TrackedFrame::right_u), 1) << " px, centre " << fixedOrDash(run.maxJump(&TrackedFrame::centre_u), 1) << " px\n";
  if (!config.overlays.empty()) out << "overlays in " << config.overlays << "\n";
  if (!config.contact_sheet.empty()) out << "contact sheet " << config.contact_sheet << "\n";
}

/// The pipeline's options with config.prior_px as its `prior_px` when it has that option and the
/// options do not set it.
std::string withTrackingPrior(const LogTrackConfig& config) {
  if (!(config.prior_px > 0)) return config.options_json;
  const auto pipelines = listPipelines();
  const auto info = std::find_if(pipelines.begin(), pipelines.end(), [&](const PipelineInfo& p) { return p.name == config.pipeline; });
  if (info == pipelines.end() ||
      std::none_of(info->options.begin(), info->options.end(), [](const OptionInfo& o) { return o.name == "prior_px"; }))
    return config.options_json;
  nlohmann::json options;
  try {
    options = nlohmann::json::parse(config.options_json);
  } catch (const nlohmann::json::exception&) {
    return config.options_json;  // createPipeline() reports it
  }
  if (!options.is_object() || options.contains("prior_px")) return config.options_json;
  options["prior_px"] = config.prior_px;
  return options.dump();
}

}  // namespace

int runLogTrack(const LogTrackConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    if (config.trapezoid) namingFlag("--trapezoid", [&] { config.trapezoid->validate(); });
    loadPlugins(config.plugins, config.pipeline);
    auto pipeline = createPipeline(config.pipeline, withTrackingPrior(config));
    const ReplayLog log = ReplayLog::open(config.dir);
    const std::shared_ptr<const Camera> camera =
        config.camera.empty() ? log.header().camera : std::shared_ptr<const Camera>(loadCamera(config.camera));
    const int w = camera->width(), h = camera->height();
    if (config.track.row > h - 1)
      throw InvalidInput("--row " + std::to_string(config.track.row) + ": beyond the image's " + std::to_string(h) + " rows");

    std::vector<Image> overlays;
    TrackObserver draw;
    if (!config.overlays.empty() || !config.contact_sheet.empty())
      draw = [&](const Image& rgb, const PredictedObject& prediction, const DetectedObject& detection,
                 const TrackedFrame& measured) {
        overlays.push_back(drawDetection(rgb, prediction, detection, *camera));
        drawGroundPath(overlays.back(), measured.path.path, *camera);
      };
    const Polygon2 bootstrap = config.trapezoid ? bottomTrapezoid(w, h, *config.trapezoid)
                                                : namingFlag("--lane", [&] { return laneOutline(*camera, config.lane_width_m, config.lane_far_m); });
    const TrackRun run = trackLog(log, *pipeline, *camera, bootstrap,
                                  config.track, draw);
    writeOverlays(config, overlays);
    writeContactSheet(config, overlays);
    if (config.json) {
      printJson(config, run, out);
    } else {
      printTable(config, run, out);
    }
    return static_cast<int>(kOk);
  });
}

void registerTrackCommand(CLI::App& log, Commands& commands) {
  auto* track = commands.hold<LogTrackConfig>();
  auto* trapezoid = commands.hold<std::string>();
  CLI::App* lt = log.add_subcommand("track",
                                    "Run a vision pipeline over a log without a map, tracking the road's edges and centre "
                                    "line frame to frame, and measure its agreement with the true future path (docs/kitti.md)");
  lt->add_option("dir", track->dir, "Log folder")->required()->check(CLI::ExistingDirectory);
  addPipelineOptions(lt, track->pipeline, track->options_json, track->plugins, "edge-tracker");
  lt->add_option("--camera", track->camera, "Camera file instead of the log's own")->check(CLI::ExistingFile);
  auto* lane = commands.hold<std::string>();
  CLI::Option* lane_opt =
      lt->add_option("--lane", *lane,
                     "The first frame's road outline as WIDTH,FAR: the vehicle's lane on the ground, WIDTH metres wide "
                     "from the nearest ground in view to FAR metres ahead, projected with the camera (default 3,30: "
                     "a car's lane; give a sidewalk's width for a sidewalk vehicle)");
  lt->add_option("--trapezoid", *trapezoid,
                 "The first frame's road outline as an image trapezoid BOTTOM_WIDTH,TOP_WIDTH,TOP,BOTTOM (fractions "
                 "of the image's width and height, as mapnav eval segmentation's) instead of the lane")
      ->excludes(lane_opt);
  lt->add_option("--prior-px", track->prior_px,
                 "Tracking: a pipeline with a prior_px option (cluster-perceptron) keeps to this many pixels of the "
                 "road it found a frame before, unless --options sets prior_px; 0: the pipeline's default")
      ->capture_default_str()
      ->check(commands.numberCheck(CLI::Range(0.0, 1e6)));
  lt->add_option("--row", track->track.row, "Image row where the edges and the centre line are measured (default: 85 % of the height)")
      ->check(commands.ruleCheck(trackOptionTable(), "row"));
  lt->add_option("--max-frames", track->track.max_frames, "Stop after this many frames (0: all)")->capture_default_str();
  lt->add_option("--overlays", track->overlays, "Folder to write one overlay per frame to");
  lt->add_option("--contact-sheet", track->contact_sheet, "PNG of 8 overlays spread over the run, half size, two a row");
  lt->add_flag("--json", track->json, "Print the per-frame measurements as JSON");
  lt->footer("Exit codes: 0 ran (the frames where the pipeline failed are listed), 1 invalid input, 2 usage or I/O error.");
  lt->callback(commands.choose([track, trapezoid, lane](std::ostream& out, std::ostream& err) {
    if (!trapezoid->empty()) {
      const auto v = parseNumbers("--trapezoid", *trapezoid, 4, 4, "BOTTOM_WIDTH,TOP_WIDTH,TOP,BOTTOM (fractions)");
      track->trapezoid = TrapezoidOptions{v[0], v[1], v[2], v[3]};
    }
    if (!lane->empty()) {
      const auto v = parseNumbers("--lane", *lane, 2, 2, "WIDTH,FAR (metres)");
      track->lane_width_m = v[0];
      track->lane_far_m = v[1];
    }
    return runLogTrack(*track, out, err);
  }));
}

}  // namespace mapnav::cli
