#include "cli.h"

#include <CLI/CLI.hpp>
#include <unistd.h>

#include <cctype>
#include <filesystem>
#include <functional>
#include <sstream>
#include <ostream>

#include "command_support.h"
#include "map_commands.h"
#include "predict_command.h"
#include "route_command.h"
#include "simulate_command.h"
#include "log_command.h"
#include "pipelines_command.h"
#include "detect_command.h"
#include "eval_command.h"
#include "track_command.h"
#include "vision_commands.h"
#include "bench_command.h"
#include "mission_commands.h"
#include "mapnav/core/error.h"

namespace mapnav::cli {

namespace {

constexpr const char* kMapFooter = R"(Map files are mapnav-map/1 JSON (docs/map-format.md) or, where a command says so,
GeoJSON from QGIS or geojson.io. Exit codes: 0 success, 1 the input is wrong (an invalid map),
2 usage or I/O error.)";

void addOrigin(CLI::App* command, std::string& text) {
  command->add_option("--origin", text,
                      "Geodetic origin of the local frame as LAT,LON or LAT,LON,ALT (degrees, metres)");
}

// Outputs whose format is chosen by the extension: pictures (.png, .svg), and where a command
// can write GeoJSON, .geojson too.
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

}  // namespace

int run(int argc, char** argv, std::ostream& out, std::ostream& err) {
  CLI::App app{"mapnav: map-based navigation of small vehicles on sidewalks and park paths with one camera.\n"
               "Author and check sidewalk maps, predict views, plan routes and run missions."};
  app.name("mapnav");
  const std::string version = std::string("mapnav ") + MAPNAV_VERSION;
  app.set_version_flag("--version", version);
  app.require_subcommand(1);
  app.footer("Run `mapnav COMMAND --help` for a command's options.");

  std::function<int()> command;  // set by the chosen command's callback

  CLI::App* map = app.add_subcommand("map", "Validate, inspect, draw and convert sidewalk maps");
  map->require_subcommand(1);
  map->footer(kMapFooter);

  ValidateConfig validate;
  CLI::App* v = map->add_subcommand("validate", "Check map files and report every problem as FILE:/pointer: severity: check: message");
  v->add_option("files", validate.files, "Map files (.json, or .geojson)")->required()->check(CLI::ExistingFile);
  v->add_flag("-q,--quiet", validate.quiet, "Print only the problems, not a summary line per file");
  v->footer("Exit code 0 when every file is valid (warnings allowed), 1 when any has an error, 2 when a file cannot be read.");
  v->callback([&] { command = [&] { return runValidate(validate, out, err); }; });

  InfoConfig info;
  CLI::App* i = map->add_subcommand("info", "Summarise a map: counts by kind, total length, bounds, components");
  i->add_option("file", info.file, "Map file")->required()->check(CLI::ExistingFile);
  i->add_flag("--json", info.json, "Print one JSON object instead of text");
  i->callback([&] { command = [&] { return runInfo(info, out, err); }; });

  RenderConfig render;
  CLI::App* r = map->add_subcommand("render", "Draw a map as PNG or SVG: roads in their surface colours, ids, scale bar, north arrow");
  r->add_option("file", render.file, "Map file")->required()->check(CLI::ExistingFile);
  r->add_option("-o,--output", render.output, "Picture to write: OUT.png or OUT.svg")
      ->required()
      ->check(outputFile(false));
  r->add_option("--width", render.width_px, "Picture width in pixels; the height follows the map")
      ->default_val(1600)
      ->check(CLI::Range(64, 20000));
  bool no_labels = false;
  r->add_flag("--no-labels", no_labels, "Leave out road and intersection ids");
  r->callback([&] {
    render.labels = !no_labels;
    command = [&] { return runRender(render, out, err); };
  });

  ImportGeoJsonConfig import;
  std::string import_origin;
  CLI::App* im = map->add_subcommand("import-geojson", "Convert GeoJSON (LineString roads, Point/Polygon intersections) to a mapnav map");
  im->add_option("input", import.input, "GeoJSON FeatureCollection in lon/lat")->required()->check(CLI::ExistingFile);
  im->add_option("-o,--output", import.output, "mapnav-map/1 JSON to write (only when the import is valid)")->required();
  addOrigin(im, import_origin);
  im->add_option("--snap", import.snap_tolerance_m, "Road ends this close (m) to an intersection or to each other share it")
      ->default_val(1.0)
      ->check(CLI::Range(0.0, 100.0));
  im->add_option("--name", import.name, "The map's name (default: the file's, or \"imported from GeoJSON\")");
  im->footer("Without --origin, the origin is the file's mapnav.origin, else the centroid of its coordinates.");
  im->callback([&] {
    command = [&] {
      if (!import_origin.empty()) import.origin = parseOrigin(import_origin);
      return runImportGeoJson(import, out, err);
    };
  });

  ImportOsmConfig osm;
  std::string osm_origin, osm_bbox;
  CLI::App* io = map->add_subcommand("import-osm", "Convert OpenStreetMap data (walkable ways) to a mapnav map");
  io->add_option("input", osm.input, "OpenStreetMap file: .osm (XML), .osm.pbf, .osm.bz2")->required()->check(CLI::ExistingFile);
  io->add_option("-o,--output", osm.output, "mapnav-map/1 JSON to write (only when the imported map is valid)")->required();
  io->add_option("--bbox", osm_bbox, "Keep only W,S,E,N (degrees); ways leaving it are cut at its border");
  io->add_option("--highways", osm.highways, "highway values kept, comma-separated (default footway,path,pedestrian,steps,cycleway)");
  addOrigin(io, osm_origin);
  io->add_flag("--repair", osm.repair,
               "Merge nodes closer than 0.5 m, add an intersection where kept ways cross without a shared node, "
               "drop stubs and loops shorter than 1 m; every repair is listed");
  io->add_option("--name", osm.name, "The map's name (default: \"imported from FILE\")");
  io->footer(
      "Ways are split at every node two kept ways share; those nodes and way ends become intersections (id n<node>, "
      "x<k> for one --repair added), roads are w<way> or w<way>-<k>, with the OSM ids in their properties. Widths "
      "from `width` or per highway (footway 2 m, path 1.5, pedestrian 4, steps 2, cycleway 2), surfaces from "
      "`surface`, grass shoulders, steps with route cost factor 20. Without --origin the origin is the centre of the "
      "kept data. Data problems are reported as warnings (where = way/ID or node/ID); nothing is written when the "
      "map is invalid.");
  io->callback([&] {
    command = [&] {
      if (!osm_origin.empty()) osm.origin = parseOrigin(osm_origin);
      if (!osm_bbox.empty()) osm.bbox = parseBbox(osm_bbox);
      return runImportOsm(osm, out, err);
    };
  });

  ExportGeoJsonConfig exp;
  std::string export_origin;
  CLI::App* ex = map->add_subcommand("export-geojson", "Write a map as GeoJSON in lon/lat, for QGIS");
  ex->add_option("input", exp.input, "Map file")->required()->check(CLI::ExistingFile);
  ex->add_option("-o,--output", exp.output, "GeoJSON file to write")->required();
  addOrigin(ex, export_origin);
  ex->footer("The map's own origin is used unless --origin is given; a map without one needs --origin.");
  ex->callback([&] {
    command = [&] {
      if (!export_origin.empty()) exp.origin = parseOrigin(export_origin);
      return runExportGeoJson(exp, out, err);
    };
  });

  PredictConfig predict;
  std::string predict_pose, predict_at;
  CLI::App* p = app.add_subcommand("predict", "What the camera should see from a pose: objects, interest segments, relations");
  p->add_option("--map", predict.map, "Map file")->required()->check(CLI::ExistingFile);
  p->add_option("--camera", predict.camera, "Camera file (mapnav-camera/1, docs/camera-format.md)")
      ->required()
      ->check(CLI::ExistingFile);
  auto* pose = p->add_option("--pose", predict_pose, "Vehicle pose X,Y,HEADING_DEG in the map's frame (metres, degrees CCW from east)");
  auto* at = p->add_option("--at", predict_at, "Vehicle on a road: ROAD@NODE+METERS[/LATERAL], e.g. R1@I1+3 (facing away from NODE)");
  pose->excludes(at);
  at->excludes(pose);
  p->add_flag("--json", predict.json, "Print the prediction as JSON instead of sentences");
  p->add_option("-o,--output", predict.output, "Also draw the map with the footprint beside the predicted image: OUT.png or OUT.svg")
      ->check(outputFile(false));
  p->add_option("--near", predict.near_m, "Nearest ground distance ahead of the camera to predict, m")->default_val(1.0)->check(CLI::Range(0.0, 1000.0));
  p->add_option("--far", predict.far_m, "Farthest ground distance ahead of the camera to predict, m")->default_val(15.0)->check(CLI::Range(0.0, 1000.0));
  p->footer("Exactly one of --pose and --at. Exit codes: 0 success (an empty view too), 1 invalid map, camera or\n"
            "position, 2 usage or I/O error.");
  p->callback([&] {
    command = [&] {
      if (predict_pose.empty() && predict_at.empty()) {
        throw InvalidInput("predict needs the vehicle's pose: --pose X,Y,HEADING_DEG or --at ROAD@NODE+METERS");
      }
      if (!predict_pose.empty()) predict.pose = parsePose(predict_pose);
      if (!predict_at.empty()) predict.at = parseRoadPosition(predict_at);
      return runPredict(predict, out, err);
    };
  });

  RouteConfig route;
  std::string route_from, route_to, route_block;
  CLI::App* rt = app.add_subcommand("route", "Plan a route between two road positions and say it as motion commands");
  rt->add_option("--map", route.map, "Map file")->required()->check(CLI::ExistingFile);
  rt->add_option("--from", route_from, "Start: ROAD@NODE+METERS, e.g. R1@I1+3")->required();
  rt->add_option("--to", route_to, "Goal: ROAD@NODE+METERS, e.g. R3@I3+2")->required();
  rt->add_option("--block", route_block, "Roads and intersections not to use, comma-separated: R2,I5");
  rt->add_flag("--json", route.json, "Print the route as JSON instead of the dialogue");
  rt->add_option("-o,--output", route.output, "Also draw the route on the map (OUT.png, OUT.svg) or write it as OUT.geojson")
      ->check(outputFile(true));
  rt->footer("Cost = length x the road's cost_factor + a turn penalty by angle. Exit codes: 0 a route, 1 no route\n"
             "(the reason is printed) or an invalid map or position, 2 usage or I/O error.");
  rt->callback([&] {
    command = [&] {
      route.from = parseRoadPosition(route_from);
      route.to = parseRoadPosition(route_to);
      std::stringstream ids(route_block);
      for (std::string id; std::getline(ids, id, ',');) {
        if (!id.empty()) route.blocked.push_back(id);
      }
      return runRoute(route, out, err);
    };
  });

  SimulateConfig simulate;
  std::int64_t simulate_seed = -1;
  CLI::App* sim = app.add_subcommand("simulate", "Drive a mission in the synthetic world and write its replay log");
  sim->add_option("--mission", simulate.mission, "Mission file (mapnav-mission/1, docs/mission-format.md)")
      ->required()
      ->check(CLI::ExistingFile);
  sim->add_option("-o,--output", simulate.output, "Log folder to write (must not exist, or be empty)")->required();
  sim->add_option("--seed", simulate_seed, "Seed for the world and the odometry noise (default: the mission's)")
      ->check(CLI::Range(std::int64_t{0}, std::int64_t{9007199254740991}));
  sim->add_option("--max-frames", simulate.max_frames, "Stop after this many frames (default: drive to the goal)");
  sim->footer("The same mission and seed give the same bytes. Exit codes: 0 written, 1 invalid mission or no route,\n"
              "2 usage or I/O error (nothing is left in the output folder on failure).");
  sim->callback([&] {
    if (simulate_seed >= 0) simulate.seed = static_cast<std::uint64_t>(simulate_seed);
    command = [&] { return runSimulate(simulate, out, err); };
  });

  CLI::App* log = app.add_subcommand("log", "Inspect replay logs (docs/replay-log-format.md)");
  log->require_subcommand(1);
  LogInfoConfig log_info;
  CLI::App* li = log->add_subcommand("info", "Summarise a log: frames, duration, distance, camera, ground truth");
  li->add_option("dir", log_info.dir, "Log folder")->required()->check(CLI::ExistingDirectory);
  li->add_flag("--json", log_info.json, "Print one JSON object");
  li->callback([&] { command = [&] { return runLogInfo(log_info, out, err); }; });
  LogFrameConfig log_frame;
  CLI::App* lf = log->add_subcommand("frame", "Write frame N with its ground-truth road mask overlaid");
  lf->add_option("dir", log_frame.dir, "Log folder")->required()->check(CLI::ExistingDirectory);
  lf->add_option("index", log_frame.index, "Frame number, from 0")->required();
  lf->add_option("-o,--output", log_frame.output, "PNG to write")->required();
  lf->callback([&] { command = [&] { return runLogFrame(log_frame, out, err); }; });
  LogImportKittiConfig log_kitti;
  CLI::App* lk = log->add_subcommand("import-kitti", "Turn a KITTI odometry sequence (images, poses.txt, calib.txt) into a log with truth (docs/kitti.md)");
  lk->add_option("dir", log_kitti.dir, "KITTI sequence folder")->required()->check(CLI::ExistingDirectory);
  lk->add_option("-o,--output", log_kitti.output, "Log folder to write (must not exist, or be empty)")->required();
  lk->add_option("--camera-height", log_kitti.options.camera_height_m, "Camera height above the road, m")->default_val(1.65);
  lk->add_option("--camera-tilt", log_kitti.options.camera_tilt_deg, "Camera pitch below the horizon, degrees")->default_val(0.0);
  lk->add_option("--frame-rate", log_kitti.options.frame_rate_hz, "Frame rate when there is no times.txt, Hz")->default_val(10.0);
  lk->add_option("--images", log_kitti.options.images, "Image folder inside the sequence (default: the first image_* folder)");
  lk->add_option("--name", log_kitti.options.name, "The log's name (default: KITTI and the folder's name)");
  lk->footer("Exit codes: 0 written, 1 invalid input (a malformed poses.txt line, fewer poses than images; the file and "
             "line are named and nothing is written), 2 usage or I/O error (a missing poses.txt or calib.txt).");
  lk->callback([&] { command = [&] { return runLogImportKitti(log_kitti, out, err); }; });
  LogTrackConfig log_track;
  std::string track_trapezoid;
  CLI::App* lt = log->add_subcommand("track", "Run a vision pipeline over a log without a map, tracking the road's edges and centre line frame to frame (docs/kitti.md)");
  lt->add_option("dir", log_track.dir, "Log folder")->required()->check(CLI::ExistingDirectory);
  lt->add_option("--pipeline", log_track.pipeline, "Vision pipeline (mapnav pipelines lists them)")->default_val("edge-tracker");
  lt->add_option("--options", log_track.options_json, "The pipeline's options as a JSON object")->default_val("{}");
  lt->add_option("--plugin", log_track.plugins, "Load a vision plug-in first");
  lt->add_option("--camera", log_track.camera, "Camera file instead of the log's own")->check(CLI::ExistingFile);
  lt->add_option("--trapezoid", track_trapezoid,
                 "The first frame's road outline as BOTTOM_WIDTH,TOP_WIDTH,TOP,BOTTOM (fractions of the image's width "
                 "and height; default 0.5,0.2,0.7,0.98)");
  lt->add_option("--row", log_track.row, "Image row where the edges and the centre line are measured (default: 85 % of the height)");
  lt->add_option("--max-frames", log_track.max_frames, "Stop after this many frames (0: all)")->default_val(0);
  lt->add_option("--overlays", log_track.overlays, "Folder to write one overlay per frame to");
  lt->add_option("--contact-sheet", log_track.contact_sheet, "PNG of 8 overlays spread over the run, half size, two a row");
  lt->add_flag("--json", log_track.json, "Print the per-frame measurements as JSON");
  lt->footer("Exit codes: 0 ran (the frames where the pipeline failed are listed), 1 invalid input, 2 usage or I/O error.");
  lt->callback([&] {
    command = [&] {
      if (!track_trapezoid.empty()) {
        const auto v = parseNumbers("--trapezoid", track_trapezoid, 4, 4, "BOTTOM_WIDTH,TOP_WIDTH,TOP,BOTTOM (fractions)");
        log_track.trapezoid = TrapezoidOptions{v[0], v[1], v[2], v[3]};
      }
      return runLogTrack(log_track, out, err);
    };
  });

  // replay and run share their options.
  const bool stderr_is_tty = ::isatty(STDERR_FILENO) == 1;
  auto missionOptions = [&](CLI::App* c, MissionRunConfig& config) {
    c->add_option("--mission", config.mission, "Mission file (mapnav-mission/1, docs/mission-format.md)")
        ->required()
        ->check(CLI::ExistingFile);
    c->add_option("--pipeline", config.pipeline, "Vision pipeline (default: the mission's vision.pipeline, else sidewalk)");
    c->add_option("--plugin", config.plugins, "Load a vision plug-in first");
    c->add_option("--trace", config.trace, "Write the JSONL trace of every token (docs/trace-format.md)");
    c->add_option("--max-frames", config.max_frames, "Stop after this many frames (default: to the end)");
    c->add_flag("--json", config.json, "Print the metrics as one JSON object instead of the summary");
    c->add_option("--report", config.report_dir,
                  "Write the HTML report (report.html), trajectories.geojson and, without --trace, trace.jsonl "
                  "to this folder (docs/report.md)");
    config.progress = stderr_is_tty;
  };
  constexpr const char* kMissionFooter =
      "Prints a summary (or --json: {\"frames\",\"reached_goal\",\"lateral_rms_m\",\"along_rms_m\",\"heading_rms_deg\",\n"
      "\"max_error_m\",\"odometry_only_max_error_m\",\"vision_failures\",\"replans\",\"latency_ms_median\",\n"
      "\"latency_ms_p99\",\"along_after_intersection_max_m\",...}); a progress bar on a terminal. Exit codes: 0 the goal\n"
      "was reached (or --max-frames stopped it first), 1 the mission failed (halted, goal not reached) or the input\n"
      "is invalid, 2 usage or I/O error.";

  ReplayConfig replay;
  CLI::App* rp = app.add_subcommand("replay", "Run a mission open loop over a recorded log: localisation and commands per frame, against the truth");
  missionOptions(rp, replay);
  rp->add_option("--log", replay.log, "Replay log folder (mapnav simulate, docs/replay-log-format.md)")
      ->required()
      ->check(CLI::ExistingDirectory);
  rp->add_flag("--strict", replay.strict,
               "Stop at the first fault of the log (missing or corrupt frame, time order, odometry spike, cut line) "
               "with an error naming frames.jsonl and the line; by default faults are skipped, counted and traced");
  rp->footer(kMissionFooter);
  rp->callback([&] { command = [&] { return runReplayCommand(replay, out, err); }; });

  RunConfig run_config;
  std::int64_t run_seed = -1;
  CLI::App* rn = app.add_subcommand("run", "Run a mission closed loop in the simulator: each frame rendered from where the commands drove");
  missionOptions(rn, run_config);
  rn->add_option("--seed", run_seed, "Seed for the world and the odometry noise (default: the mission's)")
      ->check(CLI::Range(std::int64_t{0}, std::int64_t{9007199254740991}));
  rn->footer(kMissionFooter);
  rn->callback([&] {
    if (run_seed >= 0) run_config.seed = static_cast<std::uint64_t>(run_seed);
    command = [&] { return runRunCommand(run_config, out, err); };
  });

  DemoConfig demo;
  CLI::App* dm = app.add_subcommand("demo", "Simulate the paper's dialogue mission on the campus map, replay it and write the HTML report");
  dm->add_option("-o,--output", demo.output, "Folder to write (default: out/demo)");
  dm->add_option("--mission", demo.mission, "Another mission (default: maps/missions/campus_dialogue.json)")
      ->check(CLI::ExistingFile);
  dm->add_option("--max-frames", demo.max_frames, "Stop after this many frames (default: the whole mission)");
  dm->footer(
      "The whole system of Wallace et al. 1985 on one mission: \"the robot is at road R1, 3 m from I1; navigate to\n"
      "R3, 2 m from I3\". The same as\n"
      "  mapnav simulate --mission maps/missions/campus_dialogue.json -o DIR/log\n"
      "  mapnav replay --mission maps/missions/campus_dialogue.json --log DIR/log --report DIR\n"
      "Writes DIR/log/ (the replay log: frames, odometry, truth; an earlier demo's log there is replaced),\n"
      "DIR/trace.jsonl (every blackboard token; `mapnav trace show` prints the dialogue), DIR/report.html (one\n"
      "self-contained page: map, route and trajectories, errors over time, frames with predicted and detected\n"
      "lines, the dialogue; open it in any browser) and DIR/trajectories.geojson (for QGIS). Prints the summary\n"
      "and the report's path. Exit codes: 0 the goal was reached (or --max-frames stopped it first), 1 the\n"
      "mission failed or the input is invalid, 2 usage or I/O error.");
  demo.progress = stderr_is_tty;
  dm->callback([&] { command = [&] { return runDemo(demo, out, err); }; });

  CLI::App* trace = app.add_subcommand("trace", "Read mission traces (docs/trace-format.md)");
  trace->require_subcommand(1);
  TraceShowConfig trace_show;
  CLI::App* ts = trace->add_subcommand("show", "Print a trace as the paper's dialogue (Map, Vision, Navigator, Motion Control)");
  ts->add_option("file", trace_show.file, "Trace (JSONL) written by replay or run --trace")->required();
  ts->footer("Exit codes: 0 printed, 1 a bad line (FILE:LINE:1: error: check: message), 2 the file cannot be read.");
  ts->callback([&] { command = [&] { return runTraceShow(trace_show, out, err); }; });

  PipelinesConfig pipelines;
  CLI::App* pl = app.add_subcommand("pipelines", "List the vision pipelines available, with their options and defaults");
  pl->add_flag("--names", pipelines.names_only, "One name a line");
  pl->add_option("--plugin", pipelines.plugins, "Load a vision plug-in (a shared library; see examples/vision_plugin)");
  pl->callback([&] { command = [&] { return runPipelines(pipelines, out, err); }; });

  // detect and segment share their options.
  DetectConfig detect;
  std::string detect_pose, detect_at;
  auto visionOptions = [&](CLI::App* c) {
    c->add_option("--pipeline", detect.pipeline, "Vision pipeline (mapnav pipelines lists them)")->default_val("sidewalk");
    c->add_option("--options", detect.options_json, "The pipeline's options as a JSON object")->default_val("{}");
    c->add_option("--plugin", detect.plugins, "Load a vision plug-in first");
    c->add_option("image", detect.image, "Camera frame (RGB PNG)")->required()->check(CLI::ExistingFile);
    c->add_option("--map", detect.map, "Map file, for the prediction")->check(CLI::ExistingFile);
    c->add_option("--camera", detect.camera, "Camera file")->required()->check(CLI::ExistingFile);
    auto* pose = c->add_option("--pose", detect_pose, "Vehicle pose X,Y,HEADING_DEG, for the prediction");
    auto* at = c->add_option("--at", detect_at, "Vehicle on a road: ROAD@NODE+METERS");
    pose->excludes(at);
    at->excludes(pose);
  };
  std::string train_region;
  auto visionCommand = [&](auto run) {
    return [&, run] {
      command = [&, run] {
        if (!train_region.empty()) {
          detect.train_region = parsePixelPolygon(train_region);
          return run(detect, out, err);
        }
        if (detect.map.empty() || (detect_pose.empty() && detect_at.empty())) {
          throw InvalidInput("the prediction needs --map and --pose (or --at); segment also takes --train-region instead");
        }
        if (!detect_pose.empty()) detect.pose = parsePose(detect_pose);
        if (!detect_at.empty()) detect.at = parseRoadPosition(detect_at);
        return run(detect, out, err);
      };
    };
  };
  CLI::App* dt = app.add_subcommand("detect", "Run a vision pipeline on a frame against the prediction: the Detected Object");
  visionOptions(dt);
  dt->add_flag("--json", detect.json, "Print the DetectedObject as JSON");
  dt->add_option("-o,--output", detect.output, "Overlay picture (PNG): predicted segments thin, detected lines bold")
      ->check(outputFile(false));
  dt->footer("Exit codes: 0 detected, 1 the pipeline failed on the frame (the reason is printed) or bad input, 2 usage/I-O.");
  dt->callback(visionCommand(runDetect));
  CLI::App* sg = app.add_subcommand("segment", "Run a vision pipeline on a frame and write the road mask it finds");
  visionOptions(sg);
  sg->add_option("-o,--output", detect.output, "Road mask to write (PNG, 255 = road)")->required();
  sg->add_option("--overlay", detect.overlay, "Also the overlay picture (PNG)");
  sg->add_option("--train-region", train_region, "Train on this image polygon U,V;U,V;U,V (pixels) instead of a map prediction");
  sg->callback(visionCommand(runSegment));

  RectifyConfig rectify;
  CLI::App* rc = app.add_subcommand("rectify", "Warp a camera frame to a top view of the ground (Wallace 1985, 3.5.1)");
  rc->add_option("image", rectify.image, "Camera frame (PNG or JPEG)")->required()->check(CLI::ExistingFile);
  rc->add_option("--camera", rectify.camera, "Camera file")->required()->check(CLI::ExistingFile);
  rc->add_option("--x-min", rectify.options.x_min_m, "Nearest ground ahead, m")->default_val(1.0);
  rc->add_option("--x-max", rectify.options.x_max_m, "Farthest ground ahead, m")->default_val(15.0);
  rc->add_option("--y-min", rectify.options.y_min_m, "Rightmost ground, m (right negative)")->default_val(-6.0);
  rc->add_option("--y-max", rectify.options.y_max_m, "Leftmost ground, m")->default_val(6.0);
  rc->add_option("--resolution", rectify.options.metres_per_pixel, "Metres per output pixel")->default_val(0.02);
  rc->add_option("-o,--output", rectify.output, "Top view to write (PNG): far at the top, left on the left")->required();
  rc->add_flag("--undistort", rectify.undistort,
               "Write the frame undistorted instead (same size, as the camera's ideal pin-hole would see it: "
               "straight lines straight); the ground options are then unused");
  rc->callback([&] { command = [&] { return runRectify(rectify, out, err); }; });

  CLI::App* cal = app.add_subcommand("calibrate", "Camera calibration (Wallace 1985, 3.5.2; OpenCV chessboards)");
  cal->require_subcommand(1);
  CalibrateChessboardConfig chessboard;
  std::string board = "9x6";
  CLI::App* cb = cal->add_subcommand("chessboard", "Intrinsics from chessboard photos; reports the reprojection error");
  cb->add_option("images", chessboard.images, "Photos of the board (PNG or JPEG)")->required()->check(CLI::ExistingFile);
  cb->add_option("--board", board, "Inner corners COLSxROWS")->default_val("9x6");
  cb->add_option("--square", chessboard.square_m, "Square size, m")->default_val(0.025)->check(CLI::PositiveNumber);
  cb->add_option("-o,--output", chessboard.output, "Camera file to write (mapnav-camera/1; fill in the mount)")->required();
  cb->add_option("--corners", chessboard.corners_dir, "Folder to draw the detected corners into");
  cb->callback([&] {
    command = [&] {
      const auto x = board.find('x');
      try {
        if (x == std::string::npos) throw std::invalid_argument(board);
        chessboard.cols = std::stoi(board.substr(0, x));
        chessboard.rows = std::stoi(board.substr(x + 1));
      } catch (const std::exception&) {
        throw InvalidInput("--board \"" + board + "\": expected COLSxROWS, e.g. 9x6");
      }
      return runCalibrateChessboard(chessboard, out, err);
    };
  });

  std::string tilt_camera, tilt_output;
  std::vector<std::string> tilt_lines;
  CLI::App* tl = cal->add_subcommand("tilt", "Camera tilt from the vanishing point of two ground-parallel lines (the paper's poles)");
  tl->add_option("--camera", tilt_camera, "Camera file (its intrinsics are used)")->required()->check(CLI::ExistingFile);
  tl->add_option("--line", tilt_lines, "A ground-parallel line's image end points U1,V1,U2,V2 (give two)")->required()->expected(2);
  tl->add_option("-o,--output", tilt_output, "Write the camera with this tilt");
  tl->callback([&] {
    command = [&] {
      std::vector<Segment2> lines;
      for (const std::string& text : tilt_lines) {
        const auto v = parseNumbers("--line", text, 4, 4, "U1,V1,U2,V2 (pixels)");
        lines.push_back(Segment2{Vec2(v[0], v[1]), Vec2(v[2], v[3])});
      }
      return runCalibrateTilt(tilt_camera, lines.at(0), lines.at(1), tilt_output, out, err);
    };
  });

  EvalSegmentationConfig eval_seg;
  std::string eval_road = "3", eval_ignore;
  CLI::App* ev = app.add_subcommand("eval", "Score vision pipelines on labelled real photos (docs/eval.md)");
  ev->require_subcommand(1);
  CLI::App* es = ev->add_subcommand(
      "segmentation", "Run a pipeline over labelled photos: road IoU (set, per-image median and worst), precision, recall");
  es->add_option("--pipeline", eval_seg.pipeline, "Vision pipeline (mapnav pipelines lists them)")->default_val("sidewalk");
  es->add_option("--options", eval_seg.options_json, "The pipeline's options as a JSON object")->default_val("{}");
  es->add_option("--plugin", eval_seg.plugins, "Load a vision plug-in first");
  es->add_option("--images", eval_seg.images, "Folder of RGB photos (PNG)")->required();
  es->add_option("--labels", eval_seg.labels, "Folder of 1-channel class-index PNGs, one per photo, same file stem")->required();
  es->add_option("--road-values", eval_road, "Label values that are road, comma-separated (CamVid: 3 road, 4 pavement)")
      ->default_val("3");
  es->add_option("--ignore-values", eval_ignore, "Label values left out of the scores (CamVid: 11 unlabelled)");
  es->add_option("--bootstrap", eval_seg.bootstrap,
                 "The road region the pipeline trains on: trapezoid (bottom centre, docs/eval.md) or labels-first-frame "
                 "(the first photo's largest labelled road region)")
      ->default_val("trapezoid");
  es->add_option("--camera", eval_seg.camera, "Camera file (default: an assumed level pin-hole of the photos' size, docs/eval.md)")
      ->check(CLI::ExistingFile);
  es->add_option("--overlays", eval_seg.overlays, "Folder to write overlays to: true positives green, false positives red, "
                                                  "false negatives blue, ignored pixels dark");
  es->add_flag("--json", eval_seg.json, "Print the scores as JSON");
  es->footer("Exit codes: 0 scored, 1 invalid input (an image without its label, a label of another size, a corrupt PNG), "
             "2 usage or I/O error (a missing folder).");
  es->callback([&] {
    command = [&] {
      auto values = [](const std::string& option, const std::string& text) {
        std::vector<int> out;
        if (text.empty()) return out;
        for (double v : parseNumbers(option, text, 1, 256, "label values V[,V...] (0-255)")) {
          if (v != std::floor(v)) throw InvalidInput(option + " \"" + text + "\": label values are whole numbers");
          out.push_back(static_cast<int>(v));
        }
        return out;
      };
      eval_seg.classes.road = values("--road-values", eval_road);
      eval_seg.classes.ignore = values("--ignore-values", eval_ignore);
      return runEvalSegmentation(eval_seg, out, err);
    };
  });

  BenchConfig bench;
  std::string bench_sizes = "64,128,256,512,1024", bench_min_time = "0.2";
  CLI::App* bn = app.add_subcommand("bench", "Time the park road finder's runtime per frame on this machine (Jochem & Baluja 1993, section 6) and the sidewalk pipeline at 512x480");
  bn->add_flag("--json", bench.json, "Print one JSON object instead of the table");
  bn->add_option("--sizes", bench_sizes, "Square frame sizes, pixels a side, comma-separated, each in [16, 4096]")
      ->default_str("64,128,256,512,1024");
  bn->add_option("--min-time", bench_min_time, "Seconds to spend on each measurement at least (> 0, at most 60)")
      ->default_str("0.2");
  bn->add_option("--threads", bench.threads, "Threads of the multi-threaded rows; 0 = every core")
      ->default_val(0)
      ->check(CLI::Range(0, 256));
  bn->add_option("--map", bench.map, "The park map the frames are rendered from (default: maps/park_path.json)")
      ->check(CLI::ExistingFile);
  std::string bench_road_model = "line";
  bn->add_option("--road-model", bench_road_model, "The road finder's model: line (the paper) or arc (section 9, bends)")
      ->default_str("line")
      ->check(CLI::IsMember({"line", "arc"}));
  bn->footer(
      "What is measured, per size: the park scene (maps/park_path.json, a SIZE x SIZE pin-hole scaled from the\n"
      "Terregator camera, synthetic frames with tree shadows) is rendered, the road finder is trained on the\n"
      "first frame, then find() without the mask (lookup-table classification, block certainty, Hough) is\n"
      "timed per colour frame with one thread and with every core (or --threads), reported as ms/frame,\n"
      "frames/s and pixels/s. Each measurement runs in batches for at least --min-time seconds and takes the\n"
      "median batch (steady_clock). Two ratios are measured in the same run:\n"
      "  memcpy_ratio    = runtime time / time of a plain memcpy of the same frame (1 = the memory floor)\n"
      "  reference_ratio = time of the per-pixel reference path (float distance to every cluster, std::tanh)\n"
      "                    with the same threads / runtime time (> 1 = the runtime is that much faster)\n"
      "Cost per pixel growth = (time at the largest size / time at the smallest) / pixel ratio: 1 = linear.\n"
      "Training (clustering + perceptron on the first frame, one thread) is reported at 512, or at the largest\n"
      "size when 512 is not measured; train_ms in the JSON, with every size's under \"training\".\n"
      "--json prints {\"runtime\":[{\"size\",\"threads\",\"fps\",\"ms\",\"px_per_s\",\"memcpy_ratio\",\n"
      "\"reference_ratio\",...},...],\"train_ms\",...}. Exit codes: 0 measured, 1 an invalid --map, 2 usage or I/O error.");
  bn->callback([&] {
    command = [&] {
      bench.sizes = parseBenchSizes(bench_sizes);
      bench.min_time_s = parseBenchMinTime(bench_min_time);
      bench.road_model = roadModelFromString(bench_road_model);
      return runBench(bench, out, err);
    };
  });

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    out << app.help();
    return kOk;
  } catch (const CLI::CallForAllHelp&) {
    out << app.help("", CLI::AppFormatMode::All);
    return kOk;
  } catch (const CLI::CallForVersion&) {
    out << version << "\n";
    return kOk;
  } catch (const CLI::ParseError& e) {
    err << "mapnav: error: " << e.what() << "\n";
    err << "Run with --help for more information.\n";
    return kUsage;
  }
  try {
    return command ? command() : static_cast<int>(kUsage);
  } catch (const InvalidInput& e) {  // bad option values found after parsing (--origin)
    err << "mapnav: error: " << e.what() << "\n";
    return kUsage;
  }
}

}  // namespace mapnav::cli
