#include "eval_command.h"

#include <ostream>
#include <sstream>

#include "cli.h"
#include "command_line.h"
#include "command_support.h"
#include "mapnav/core/error.h"
#include "pipelines_command.h"

namespace mapnav::cli {

namespace {

std::string scoreOrNull(const std::optional<double>& v) { return fixedOr(v, 4, "null"); }

// Which space was scored, so that image and bird's-eye figures are never mistaken for each other.
std::string spaceText(const SegmentationEvaluation& e) {
  if (!e.bev) return "  scored per pixel, in the image\n";
  const BevGrid& g = e.bev->grid;
  std::ostringstream t;
  t << "  scored in a bird's-eye grid (KITTI road benchmark): x " << g.x_min_m << ".." << g.x_max_m << " m, z "
    << g.z_min_m << ".." << g.z_max_m << " m, " << g.cell_m << " m cells; " << e.bev->cells_in_image << " of "
    << e.bev->columns * e.bev->rows << " cells in the image\n";
  return t.str();
}

void printText(const EvalSegmentationConfig& config, const SegmentationEvaluation& e, std::ostream& out) {
  for (const PhotoScore& p : e.photos) {
    out << "  " << p.image << "  IoU " << scoreOrNull(p.counts.iou());
    if (!p.failure.empty()) out << "  (pipeline failed: " << p.failure << "; scored as no road)";
    out << "\n";
  }
  const SegmentationScores& s = e.scores;
  out << config.pipeline << " (bootstrap " << config.bootstrap << "): " << s.images << " images, " << e.failed
      << " failed\n"
      << spaceText(e) << "  IoU " << scoreOrNull(s.iou) << " (per image: median " << scoreOrNull(s.iou_median)
      << ", worst " << scoreOrNull(s.iou_worst) << ")\n"
      << "  precision " << scoreOrNull(s.precision) << ", recall " << scoreOrNull(s.recall) << "\n"
      << (e.confidence_given ? "  MaxF " + scoreOrNull(s.maxf) + ", AP " + scoreOrNull(s.ap) +
                                   " (from the per-pixel road confidence)\n"
                             : std::string("  MaxF null, AP null: no photo gave a per-pixel road confidence\n"))
      << "  baselines scored the same way: everything below the horizon IoU " << scoreOrNull(e.baseline_horizon.iou)
      << ", the bootstrap region alone IoU " << scoreOrNull(e.baseline_bootstrap.iou) << "\n"
      << "  margin over the better baseline " << (e.margin && *e.margin >= 0 ? "+" : "") << scoreOrNull(e.margin)
      << "\n";
  if (!config.options.overlays.empty())
    out << "overlays in " << config.options.overlays << " (green TP, red FP, blue FN"
        << (e.bev ? "; STEM.bev.png in the grid" : "") << ")\n";
}

}  // namespace

int runEvalSegmentation(const EvalSegmentationConfig& config, std::ostream& out, std::ostream& err) {
  if (config.options.bev && config.options.camera.empty()) {
    err << "mapnav: error: eval segmentation: --bev needs --camera FILE (the camera that took the photos: the "
           "bird's-eye grid is laid on the ground it sees; an assumed camera would give made-up metres)\n";
    return kUsage;
  }
  return guarded(err, [&] {
    config.classes.validate();
    SegmentationEvalOptions options = config.options;
    if (options.bev) namingFlag("--bev-range / --bev-cell", [&] { options.bev_grid.validate(); });
    options.bootstrap = namingFlag("--bootstrap", [&] { return evalBootstrapFromString(config.bootstrap); });
    loadPlugins(config.plugins, config.pipeline);
    auto pipeline = createPipeline(config.pipeline, config.options_json);
    const SegmentationEvaluation e =
        evaluateSegmentation(*pipeline, config.images, config.labels, config.classes, options);
    if (config.json) {
      out << evaluationJson(e);
    } else {
      printText(config, e, out);
    }
    return static_cast<int>(kOk);
  });
}

// ---- the command line: `mapnav eval segmentation` -----------------------------------------------

void registerEvalCommands(CLI::App& app, Commands& commands) {
  auto* eval = commands.hold<EvalSegmentationConfig>();
  struct Texts {
    std::string road = "3", ignore, bev_range, resize;
  };
  auto* text = commands.hold<Texts>();
  CLI::App* ev = app.add_subcommand("eval", "Score vision pipelines on labelled real photos (docs/eval.md)");
  ev->require_subcommand(1);
  CLI::App* es = ev->add_subcommand(
      "segmentation", "Run a pipeline over labelled photos: road IoU (set, per-image median and worst), precision, "
                      "recall, beside two baselines scored the same way (everything below the horizon is road; the "
                      "bootstrap region alone) and the margin over the better one");
  addPipelineOptions(es, eval->pipeline, eval->options_json, eval->plugins, "sidewalk");
  es->add_option("--images", eval->images, "Folder of RGB photos (PNG)")->required();
  es->add_option("--labels", eval->labels, "Folder of 1-channel class-index PNGs, one per photo, same file stem")->required();
  es->add_option("--road-values", text->road, "Label values that are road, comma-separated (CamVid: 3 road, 4 pavement)")
      ->default_val("3");
  es->add_option("--ignore-values", text->ignore, "Label values left out of the scores (CamVid: 11 unlabelled)");
  es->add_option("--bootstrap", eval->bootstrap,
                 "The road region the pipeline trains on: trapezoid (bottom centre, docs/eval.md) or labels-first-frame "
                 "(the first photo's largest labelled road region)")
      ->capture_default_str();
  es->add_option("--camera", eval->options.camera,
                 "Camera file, its image the photos' size (default: an assumed level pin-hole of the photos' size, "
                 "docs/eval.md)")
      ->check(CLI::ExistingFile);
  CLI::Option* bev = es->add_flag(
      "--bev", eval->options.bev,
      "Score in a bird's-eye grid on the ground, as the KITTI road benchmark does (needs --camera): one sample per "
      "grid cell, the pixel its centre projects to; cells outside the image are left out");
  es->add_option("--bev-range", text->bev_range,
                 "The grid, metres: X0,X1 across (right of the camera positive), Z0,Z1 ahead of it (default KITTI's "
                 "-10,10,6,46)")
      ->needs(bev);
  es->add_option("--bev-cell", eval->options.bev_grid.cell_m, "The grid's cell side, metres (default KITTI's 0.05)")
      ->needs(bev);
  es->add_option("--overlays", eval->options.overlays,
                 "Folder to write overlays to: true positives green, false positives red, false negatives blue, "
                 "ignored pixels dark");
  es->add_option("--resize", text->resize,
                 "Score the photos resized to WxH pixels (e.g. 320x240: a small robot's camera): each photo averaged "
                 "down (or interpolated up), its labels by the nearest pixel; --camera must then be of that size");
  es->add_flag("--grey", eval->options.grey,
               "Score the photos as a grey camera gives them: luminance 0.299 R + 0.587 G + 0.114 B in every channel");
  es->add_flag("--json", eval->json, "Print the scores as JSON");
  es->footer("Exit codes: 0 scored, 1 invalid input (an image without its label, a label of another size, a corrupt PNG), "
             "2 usage or I/O error (a missing folder).");
  es->callback(commands.choose([eval, text](std::ostream& out, std::ostream& err) {
    eval->classes.road = parseLabelValues("--road-values", text->road);
    eval->classes.ignore = parseLabelValues("--ignore-values", text->ignore);
    if (!text->resize.empty()) {
      const ImageSize size = parseImageSize("--resize", text->resize);
      eval->options.resize_width = size.width;
      eval->options.resize_height = size.height;
    }
    if (!text->bev_range.empty()) {
      const std::vector<double> r = parseNumbers("--bev-range", text->bev_range, 4, 4, "X0,X1,Z0,Z1 (metres)");
      BevGrid& grid = eval->options.bev_grid;
      grid.x_min_m = r[0], grid.x_max_m = r[1], grid.z_min_m = r[2], grid.z_max_m = r[3];
    }
    return runEvalSegmentation(*eval, out, err);
  }));
}

}  // namespace mapnav::cli
