#include "bench_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <ostream>
#include <string>
#include <thread>
#include <vector>

#include "bench_measure.h"
#include "bench_pipelines.h"
#include "bench_sim_route.h"
#include "cli.h"
#include "command_line.h"
#include "command_support.h"
#include "pipelines_command.h"
#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/map/map_io.h"
#include "mapnav/map/predict.h"
#include "mapnav/scenes/park_scene.h"
#include "mapnav/scenes/sidewalk_scene.h"
#include "mapnav/vision/pipelines.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav::cli {

namespace {

// One row of the table: the runtime at one size and thread count, with what it is compared to.
struct Row {
  int size = 0;
  int threads = 1;
  Measured runtime;    // fast path: lookup table, block Hough
  Measured reference;  // the per-pixel path, same threads
  Measured memcpy;     // one plain memcpy of the frame (one thread)
  double ms() const { return 1e3 * runtime.s_per_frame; }
  double fps() const { return 1.0 / runtime.s_per_frame; }
  double pxPerS() const { return static_cast<double>(size) * size / runtime.s_per_frame; }
  double memcpyRatio() const { return runtime.s_per_frame / memcpy.s_per_frame; }
  double referenceRatio() const { return reference.s_per_frame / runtime.s_per_frame; }
};

struct Training {
  int size = 0;
  double cluster_ms = 0, perceptron_ms = 0;
  double ms() const { return cluster_ms + perceptron_ms; }
};

// Cost per pixel at the largest size over that at the smallest: 1 = time grows linearly with pixels.
double costPerPixelGrowth(double t_small, int small, double t_large, int large) {
  const double px = (static_cast<double>(large) * large) / (static_cast<double>(small) * small);
  return (t_large / t_small) / px;
}

Json number(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }

// One plain memcpy per call, cycling through the frames.
Measured timeMemcpy(const std::vector<Frame>& frames, double min_time_s) {
  std::vector<std::uint8_t> dst(frames.front().rgb.data.size());
  std::size_t k = 0;
  return measure(
      [&] {
        const Image& f = frames[k++ % frames.size()].rgb;
        std::memcpy(dst.data(), f.data.data(), f.data.size());
        keep(dst.front());
      },
      min_time_s);
}

// The default Vision pipeline ("sidewalk") per frame at 512 x 480 on the campus scene, one thread: its
// default (grid_px 2: classification on 2 x 2-pixel cells, fast paths), the same after the Map's
// prediction for the frame's pose (the mission loop's two costly steps: its latency less the
// matching and navigation), the reference (every pixel, reference implementations) and a memcpy of the frame.
struct SidewalkTimes {
  int width = 0, height = 0;
  Measured fast, predicted, reference, copy;
  double ms() const { return 1e3 * fast.s_per_frame; }
  double memcpyRatio() const { return fast.s_per_frame / copy.s_per_frame; }
  double referenceRatio() const { return reference.s_per_frame / fast.s_per_frame; }
};

SidewalkTimes timeSidewalk(const SidewalkScene& scene, double min_time_s) {
  loadPlugins({}, "learned");  // every pipeline this build has is timed
  SidewalkTimes t;
  t.width = scene.camera->width();
  t.height = scene.camera->height();
  const auto timeDetect = [&](const char* options, bool predict) {
    auto pipeline = createPipeline("sidewalk", options);
    ViewPredictor predictor(scene.map);  // kept across frames, as the Map module keeps one
    std::size_t k = 0;
    return measure(
        [&] {
          const std::size_t i = k++ % scene.frames.size();
          const Image& rgb = scene.frames[i].rgb;
          const VisionFrame frame{rgb.width, rgb.height, rgb.data.data(), scene.camera.get(), static_cast<double>(k),
                                  false};  // as in the loop without a trace: no region outline
          const DetectedObject d =
              predict ? pipeline->detect(frame, predictor.predict(scene.poses[i], *scene.camera).view)
                      : pipeline->detect(frame, scene.predictions[i]);
          keep(d.confidence);
        },
        min_time_s);
  };
  t.fast = timeDetect("{}", false);
  t.predicted = timeDetect("{}", true);
  t.reference = timeDetect(R"({"reference": true})", false);
  t.copy = timeMemcpy(scene.frames, min_time_s);
  return t;
}


// What one `mapnav bench` run measured.
struct Growth {
  std::string what;  // "runtime" or "memcpy"
  int threads;
  double ratio;      // costPerPixelGrowth from the smallest size to the largest
};

struct BenchResults {
  int cores = 1;
  std::vector<Row> rows;
  std::vector<Training> trainings;  // one per size
  Training train;                   // the one reported: at 512, else at the largest size
  int small = 0, large = 0;         // the smallest and the largest size
  std::vector<Growth> growth;       // empty with one size
  SidewalkTimes sidewalk;
  RenderTimes render;
  std::vector<PipelineTime> pipelines;
  std::vector<RouteTimes> routes;  // one per --route-sizes, then one per --irregular-route-sizes
  std::optional<LoopTimes> loop;
};

void printHeader(const BenchConfig& config, int cores, std::ostream& out) {
  out << "mapnav bench: park road finder runtime (Jochem & Baluja 1993, section 6) on this machine, " << cores
      << (cores == 1 ? " core" : " cores") << "\n"
      << "time per colour frame: find() without the mask on the park scene, " << toString(config.road_model)
      << " road model, median batch, >= "
      << strprintf("%g", config.min_time_s) << " s per cell\n"
      << "memcpy_ratio    = runtime time / time of a plain memcpy of the same frame (memory floor; lower is "
         "better)\n"
      << "reference_ratio = per-pixel reference path's time / runtime time, same threads (> 1 = faster than "
         "the reference)\n\n";
  out << pad("size", 6) << pad("threads", 9) << pad("ms/frame", 12) << pad("frames/s", 12) << pad("Mpx/s", 10)
      << pad("memcpy_ratio", 14) << pad("reference_ratio", 17) << "\n";
  out.flush();
}

void printRow(const Row& row, std::ostream& out) {
  out << pad(std::to_string(row.size), 6) << pad(std::to_string(row.threads), 9) << pad(sig(row.ms()), 12)
      << pad(strprintf("%.0f", row.fps()), 12) << pad(strprintf("%.1f", row.pxPerS() / 1e6), 10)
      << pad(strprintf("%.2f", row.memcpyRatio()), 14) << pad(strprintf("%.2f", row.referenceRatio()), 17) << "\n";
  out.flush();
}

// The park scene at every size: the training, then per thread count the runtime and the reference
// path (rows printed as they are measured unless --json).
void timePark(const Map& park, const BenchConfig& config, const std::vector<int>& thread_counts, BenchResults& r,
              std::ostream& out) {
  for (const int size : config.sizes) {
    const ParkScene scene = makeParkScene(park, size);
    const TrainedParkFinder trained = trainParkFinder(scene, parkFinderOptions(size, 1, config.road_model));
    r.trainings.push_back({size, trained.cluster_ms, trained.perceptron_ms});
    const std::vector<Frame>& frames = scene.frames;
    const Measured copy = timeMemcpy(frames, config.min_time_s);
    const auto timeFind = [&](const ClusterPerceptron& finder) {
      std::size_t j = 0;
      return measure(
          [&] {
            const Image& f = frames[j++ % frames.size()].rgb;
            const RoadFinding found = finder.find(f.data.data(), size, size, false);
            keep(found.centerline_image);
          },
          config.min_time_s);
    };
    for (const int threads : thread_counts) {
      ClusterPerceptron fast = trained.finder;
      fast.setThreads(threads);
      ClusterPerceptron reference = fast;
      reference.setFast(false);
      Row row;
      row.size = size;
      row.threads = threads;
      row.memcpy = copy;
      row.reference = timeFind(reference);
      row.runtime = timeFind(fast);
      r.rows.push_back(row);
      if (!config.json) printRow(row, out);
    }
  }
}

// Cost per pixel growth from the smallest to the largest size, per thread count and for memcpy.
std::vector<Growth> costGrowth(const std::vector<Row>& rows, int small, int large, const std::vector<int>& thread_counts) {
  std::vector<Growth> growth;
  if (small == large) return growth;
  for (const int threads : thread_counts) {
    const auto at = [&](int size) {
      return *std::find_if(rows.begin(), rows.end(), [&](const Row& r) { return r.size == size && r.threads == threads; });
    };
    growth.push_back({"runtime", threads,
                      costPerPixelGrowth(at(small).runtime.s_per_frame, small, at(large).runtime.s_per_frame, large)});
    if (threads == 1) {
      growth.push_back(
          {"memcpy", 1, costPerPixelGrowth(at(small).memcpy.s_per_frame, small, at(large).memcpy.s_per_frame, large)});
    }
  }
  return growth;
}

// The one-thread park finder row at `size`, if measured.
const Row* oneThreadRow(const std::vector<Row>& rows, int size) {
  const auto it = std::find_if(rows.begin(), rows.end(), [&](const Row& r) { return r.size == size && r.threads == 1; });
  return it == rows.end() ? nullptr : &*it;
}

// The two park finder figures, one thread, from the table's rows: frames/s at 512 x 512 and the
// memcpy ratio at 1024 x 1024 (each where that size was measured).
void printParkTargets(const std::vector<Row>& rows, std::ostream& out) {
  const Row *at512 = oneThreadRow(rows, 512), *at1024 = oneThreadRow(rows, 1024);
  if (at512 == nullptr && at1024 == nullptr) return;
  out << "park road finder (the fast path, one thread):";
  if (at512 != nullptr) out << " " << strprintf("%.0f", at512->fps()) << " frames/s at 512x512 (target: >= 2000)";
  if (at512 != nullptr && at1024 != nullptr) out << ",";
  if (at1024 != nullptr)
    out << " memcpy_ratio " << strprintf("%.2f", at1024->memcpyRatio()) << " at 1024x1024 (target: <= 5; memcpy "
        << sig(1e3 * at1024->memcpy.s_per_frame) << " ms)";
  out << "\n";
}

Json benchJson(const BenchConfig& config, const BenchResults& r) {
  Json doc = Json::object();
  const SidewalkTimes& sidewalk = r.sidewalk;
  doc["pipelines"] = pipelineTimesJson(r.pipelines);
  doc["sidewalk"] = {{"width", sidewalk.width},
                     {"height", sidewalk.height},
                     {"ms", number(sidewalk.ms())},
                     {"fps", number(1e3 / sidewalk.ms())},
                     {"memcpy_ratio", number(sidewalk.memcpyRatio())},
                     {"reference_ratio", number(sidewalk.referenceRatio())},
                     {"reference_ms", number(1e3 * sidewalk.reference.s_per_frame)},
                     {"with_prediction_ms", number(1e3 * sidewalk.predicted.s_per_frame)},
                     {"memcpy_ms", number(1e3 * sidewalk.copy.s_per_frame)}};
  Json runtime = Json::array();
  for (const Row& row : r.rows) {
    runtime.push_back({{"size", row.size},
                       {"threads", row.threads},
                       {"fps", number(row.fps())},
                       {"ms", number(row.ms())},
                       {"px_per_s", number(row.pxPerS())},
                       {"memcpy_ratio", number(row.memcpyRatio())},
                       {"reference_ratio", number(row.referenceRatio())},
                       {"memcpy_ms", number(1e3 * row.memcpy.s_per_frame)},
                       {"reference_ms", number(1e3 * row.reference.s_per_frame)},
                       {"batches", row.runtime.batches}});
  }
  doc["runtime"] = runtime;
  Json park = Json::object();  // the two park finder figures, one thread
  if (const Row* row = oneThreadRow(r.rows, 512)) park["fps_512"] = number(row->fps());
  if (const Row* row = oneThreadRow(r.rows, 1024)) park["memcpy_ratio_1024"] = number(row->memcpyRatio());
  doc["park"] = park;
  doc["road_model"] = toString(config.road_model);
  doc["train_ms"] = number(r.train.ms());
  doc["train_size"] = r.train.size;
  Json training = Json::array();
  for (const Training& t : r.trainings) {
    training.push_back({{"size", t.size},
                        {"train_ms", number(t.ms())},
                        {"cluster_ms", number(t.cluster_ms)},
                        {"perceptron_ms", number(t.perceptron_ms)}});
  }
  doc["training"] = training;
  Json g = Json::array();
  for (const Growth& x : r.growth) {
    g.push_back({{"what", x.what}, {"threads", x.threads}, {"from", r.small}, {"to", r.large},
                 {"cost_per_pixel_ratio", number(x.ratio)}});
  }
  doc["cost_per_pixel_growth"] = g;
  doc["render"] = {{"width", r.render.width},
                   {"height", r.render.height},
                   {"ms", number(r.render.ms())},
                   {"fps", number(1e3 / r.render.ms())},
                   {"memcpy_ms", number(1e3 * r.render.copy.s_per_frame)},
                   {"memcpy_ratio", number(r.render.memcpyRatio())},
                   {"per_pixel_ms", number(1e3 * r.render.per_pixel.s_per_frame)},
                   {"per_pixel_ratio", number(r.render.perPixelRatio())}};
  Json routes = Json::array();
  for (const RouteTimes& t : r.routes) {
    routes.push_back({{"intersections", t.intersections},
                      {"roads", t.roads},
                      {"map", t.bent ? "irregular" : "grid"},
                      {"prep_s", number(t.prep_s)},
                      {"astar_ms", number(1e3 * t.astar.s_per_frame)},
                      {"dijkstra_ms", number(1e3 * t.dijkstra.s_per_frame)},
                      {"dijkstra_ratio", number(t.dijkstraRatio())},
                      {"query_mean_ms", number(t.meanMs())},
                      {"query_median_ms", number(t.medianMs())},
                      {"query_max_ms", number(t.maxMs())}});
  }
  doc["route"] = routes;
  if (r.loop) {
    doc["loop"] = {{"mission", r.loop->mission},
                   {"frames", r.loop->frames},
                   {"latency_median_ms", number(r.loop->median_ms)},
                   {"latency_p99_ms", number(r.loop->p99_ms)},
                   {"vision_median_ms", number(r.loop->vision_median_ms)}};
  }
  doc["cores"] = r.cores;
  doc["min_time_s"] = config.min_time_s;
  return doc;
}

// The lines after the table: cost per pixel growth, training, the sidewalk pipeline.
void printSummary(const BenchResults& r, std::ostream& out) {
  if (!r.growth.empty()) {
    out << "\ncost per pixel growth, time(" << r.large << ") / time(" << r.small << ") / pixel ratio "
        << strprintf("%.0f", (static_cast<double>(r.large) * r.large) / (static_cast<double>(r.small) * r.small))
        << " (1 = linear):";
    const char* sep = " ";
    for (const Growth& x : r.growth) {
      out << sep
          << (x.what == "memcpy" ? std::string("memcpy")
                                 : "runtime " + std::to_string(x.threads) + (x.threads == 1 ? " thread" : " threads"))
          << " " << strprintf("%.2f", x.ratio);
      sep = ", ";
    }
    out << "\n";
  }
  const Training& train = r.train;
  out << "training at " << train.size << "x" << train.size
      << " (clustering + perceptron on the first frame, one thread): " << sig(train.ms()) << " ms (clustering "
      << sig(train.cluster_ms) << ", perceptron " << sig(train.perceptron_ms) << ")\n";
  const SidewalkTimes& sidewalk = r.sidewalk;
  out << "sidewalk pipeline (the default Vision in the mission loop) at " << sidewalk.width << "x" << sidewalk.height
      << " on the campus scene, one thread (the default, grid_px 2: 2 x 2-pixel cells): " << sig(sidewalk.ms())
      << " ms/frame (" << sig(1e3 * sidewalk.predicted.s_per_frame)
      << " with the Map's prediction first, the loop's two costly steps), memcpy_ratio "
      << sig(sidewalk.memcpyRatio()) << ", reference_ratio " << sig(sidewalk.referenceRatio()) << " (reference, every pixel: "
      << sig(1e3 * sidewalk.reference.s_per_frame) << " ms)\n";
  printParkTargets(r.rows, out);
  printPipelineTimes(r.pipelines, out);
  out << "renderer (the simulator's frames) at " << r.render.width << "x" << r.render.height
      << " on the campus scene, one thread, driving 0.1 m a frame, texel cache (texel_cache_mib 64): " << sig(r.render.ms()) << " ms/frame ("
      << strprintf("%.0f", 1e3 / r.render.ms()) << " frames/s), memcpy_ratio " << sig(r.render.memcpyRatio())
      << " (a copy of the frame's colour and mask planes: " << sig(1e3 * r.render.copy.s_per_frame)
      << " ms); per pixel (the default) " << sig(1e3 * r.render.per_pixel.s_per_frame) << " ms/frame, per_pixel_ratio "
      << sig(r.render.perPixelRatio()) << "\n";
  std::vector<const RouteTimes*> grid;
  for (const RouteTimes& t : r.routes) {
    out << "route query on " << (t.bent ? "an irregular" : "a grid") << " campus of " << t.intersections
        << " intersections (" << t.roads << " roads): A* " << sig(1e3 * t.astar.s_per_frame)
        << " ms, Dijkstra (the reference) " << sig(1e3 * t.dijkstra.s_per_frame) << " ms, ratio "
        << sig(t.dijkstraRatio()) << "; per query mean " << sig(t.meanMs()) << ", median " << sig(t.medianMs())
        << ", max " << sig(t.maxMs()) << " ms; preprocessing " << sig(t.prep_s) << " s\n";
    if (!t.bent) grid.push_back(&t);
  }
  if (r.loop) {
    out << "mission loop (" << r.loop->mission << ", closed loop, " << r.loop->frames << " frames): latency median "
        << sig(r.loop->median_ms) << " ms, p99 " << sig(r.loop->p99_ms) << " ms (Vision alone: median "
        << sig(r.loop->vision_median_ms) << " ms)\n";
  }
  if (grid.size() >= 2) {
    const RouteTimes &a = *grid.front(), &b = *grid.back();
    out << "route query growth from " << a.intersections << " to " << b.intersections
        << " intersections: A* " << strprintf("%.2f", b.astar.s_per_frame / a.astar.s_per_frame) << "x, Dijkstra "
        << strprintf("%.2f", b.dijkstra.s_per_frame / a.dijkstra.s_per_frame) << "x for "
        << strprintf("%.1f", static_cast<double>(b.intersections) / a.intersections) << "x the intersections\n";
  }
}

}  // namespace

std::string defaultParkMapPath() { return dataPath("maps/park_path.json"); }

namespace {

// Whole numbers in [lo, hi], comma-separated, sorted, without repeats; `what` says what they are
// (for the message).
std::vector<int> parseWholeNumbers(const std::string& option, const std::string& text, std::size_t max_count, int lo,
                                   int hi, const std::string& what) {
  const std::string range = strprintf("[%d, %d]", lo, hi);
  const std::vector<double> values = parseNumbers(option, text, 1, max_count, what + ", whole numbers in " + range);
  std::vector<int> out;
  for (double v : values) {
    if (v != std::floor(v) || v < lo || v > hi) {
      throw InvalidInput(option + " \"" + text + "\": " + strprintf("%g", v) + " is not a whole number in " + range);
    }
    out.push_back(static_cast<int>(v));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace

std::vector<int> parseBenchSizes(const std::string& text) {
  return parseWholeNumbers("--sizes", text, 64, 16, 4096, "sizes in pixels a side (e.g. 64,128,256,512,1024)");
}

std::vector<int> parseRouteSizes(const std::string& text, const std::string& flag) {
  if (text.empty()) return {};
  return parseWholeNumbers(flag, text, 16, 4, 4000000, "intersections (e.g. 10000,100000)");
}

double parseBenchMinTime(const std::string& text) {
  const double v = parseNumbers("--min-time", text, 1, 1, "seconds per measurement, a number in (0, 60]").front();
  if (!(v > 0 && v <= 60)) throw InvalidInput("--min-time \"" + text + "\": expected seconds in (0, 60]");
  return v;
}

int resolveThreads(int threads) {
  if (threads > 0) return threads;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

int runBench(const BenchConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    if (config.sizes.empty()) throw InvalidInput("--sizes: at least one size");
    BenchResults r;
    r.cores = resolveThreads(0);
    const Map park = loadMap(config.map.empty() ? defaultParkMapPath() : config.map);
    // Two rows per size: one thread, and every core (or --threads); on a one-core machine both are 1.
    const std::vector<int> thread_counts{1, resolveThreads(config.threads)};
    if (!config.json) printHeader(config, r.cores, out);
    timePark(park, config, thread_counts, r, out);
    // Training is reported at 512 when measured, else at the largest size.
    const int train_size =
        std::find(config.sizes.begin(), config.sizes.end(), 512) != config.sizes.end() ? 512 : config.sizes.back();
    r.train = *std::find_if(r.trainings.begin(), r.trainings.end(), [&](const Training& t) { return t.size == train_size; });
    r.small = config.sizes.front();
    r.large = config.sizes.back();
    r.growth = costGrowth(r.rows, r.small, r.large, thread_counts);
    const SidewalkScene scene = makeSidewalkScene(std::filesystem::path(defaultParkMapPath()).parent_path());
    r.sidewalk = timeSidewalk(scene, config.min_time_s);
    r.render = timeRender(scene, config.min_time_s);
    r.pipelines = timePipelines(scene, resolveThreads(config.threads), config.min_time_s, config.pipelines);
    r.routes = timeRoutes(config.route_sizes, config.min_time_s);
    for (RouteTimes& t : timeRoutes(config.irregular_route_sizes, config.min_time_s, true)) r.routes.push_back(std::move(t));
    if (config.loop_frames > 0) r.loop = timeLoop(dataPath("maps/missions/campus_dialogue.json"), config.loop_frames);
    if (config.json) {
      out << benchJson(config, r).dump() << "\n";
    } else {
      printSummary(r, out);
    }
    return static_cast<int>(kOk);
  });
}

// ---- the command line: `mapnav bench` -----------------------------------------------------------

void registerBenchCommand(CLI::App& app, Commands& commands) {
  auto* bench = commands.hold<BenchConfig>();
  struct Texts {
    std::string sizes = "64,128,256,512,1024", min_time = "0.2", road_model = "line", route_sizes = "10000,100000",
                irregular_route_sizes = "50000";
    std::optional<std::string> pipelines;
  };
  auto* text = commands.hold<Texts>();
  CLI::App* bn = app.add_subcommand("bench", "Time the park road finder's runtime per frame on this machine (Jochem & Baluja 1993, section 6), the sidewalk pipeline and the simulator's renderer at 512x480, and route queries at 10k and 100k intersections");
  bn->add_flag("--json", bench->json, "Print one JSON object instead of the table");
  bn->add_option("--sizes", text->sizes, "Square frame sizes, pixels a side, comma-separated, each in [16, 4096]")
      ->default_str("64,128,256,512,1024");
  bn->add_option("--min-time", text->min_time, "Seconds to spend on each measurement at least (> 0, at most 60)")
      ->default_str("0.2");
  bn->add_option("--pipelines", text->pipelines,
                 "Vision pipelines to time per frame, comma-separated (default: every one `mapnav pipelines` lists); "
                 "\"none\" = none");
  bn->add_option("--route-sizes", text->route_sizes,
                 "Grid campuses of the route queries, intersections each, comma-separated, each in [4, 4000000]; "
                 "\"\" = none")
      ->default_str("10000,100000");
  bn->add_option("--irregular-route-sizes", text->irregular_route_sizes,
                 "The same on irregular, OpenStreetMap-like campuses (every road bent at its middle up to 3 m "
                 "sideways: 50000 intersections are 99 904 ways); \"\" = none")
      ->default_str("50000");
  bn->add_option("--loop-frames", bench->loop_frames,
                 "Frames of the campus_dialogue closed loop whose module latency is measured; 0 = none")
      ->default_val(80)
      ->check(commands.numberCheck(CLI::Range(0, 100000)));
  bn->add_option("--threads", bench->threads, "Threads of the multi-threaded rows; 0 = every core")
      ->default_val(0)
      ->check(commands.numberCheck(CLI::Range(0, 256)));
  bn->add_option("--map", bench->map, "The park map the frames are rendered from (default: maps/park_path.json)")
      ->check(CLI::ExistingFile);
  bn->add_option("--road-model", text->road_model, "The road finder's model: line (the paper) or arc (section 9, bends)")
      ->default_str("line")
      ->check(commands.nameCheck(CLI::IsMember({"line", "arc"})));
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
      "The park finder line repeats two figures from the table, one thread: frames/s at 512 and\n"
      "memcpy_ratio at 1024 (targets >= 2000 and <= 5; \"park\":{\"fps_512\",\"memcpy_ratio_1024\"} in the JSON).\n"
      "Then, at 512x480 on the campus scene, one thread: the sidewalk pipeline (ms/frame, memcpy_ratio,\n"
      "reference_ratio) and the simulator's renderer on a drive of 0.1 m a frame with the texel cache\n"
      "(WorldOptions::texel_cache_mib 64; ms/frame, memcpy_ratio = render time / a copy of the frame's colour and\n"
      "mask planes, per_pixel_ratio = the per-pixel renderer's time (the default) / the cache's, > 1 = the cache\n"
      "is that much faster); and route queries on grid campuses of --route-sizes intersections (32 seeded\n"
      "queries, default turn penalties): A* and the Dijkstra reference per query, their ratio, the growth\n"
      "from the smallest to the largest (beside the ratio of their intersections: linear growth) and the\n"
      "preprocessing (graph and landmarks, once per map, seconds); each query's A* time (the best of three) gives\n"
      "its mean, median and max. The same on irregular campuses of --irregular-route-sizes intersections (every\n"
      "road bent at its middle up to 3 m sideways, as OpenStreetMap's ways are: 50000 intersections, 99 904 ways).\n"
      "Last, the mission loop's latency (the modules per frame, not the renderer): campus_dialogue in closed loop\n"
      "for --loop-frames frames, its median, p99 and Vision's median.\n"
      "--json prints {\"runtime\":[{\"size\",\"threads\",\"fps\",\"ms\",\"px_per_s\",\"memcpy_ratio\",\n"
      "\"reference_ratio\",...},...],\"train_ms\",...,\"sidewalk\":{...},\"render\":{\"ms\",\"fps\",\"memcpy_ratio\",\"per_pixel_ratio\",...},\n"
      "\"route\":[{\"intersections\",\"roads\",\"map\":\"grid\"|\"irregular\",\"prep_s\",\"astar_ms\",\"dijkstra_ms\",\n"
      "\"dijkstra_ratio\",\"query_mean_ms\",\"query_median_ms\",\"query_max_ms\"},...],\"loop\":{\"mission\",\"frames\",\n"
      "\"latency_median_ms\",\"latency_p99_ms\",\"vision_median_ms\"}}.\n"
      "Exit codes: 0 measured, 1 an invalid --map, 2 usage or I/O error.");
  bn->callback(commands.choose([bench, text](std::ostream& out, std::ostream& err) {
    bench->sizes = parseBenchSizes(text->sizes);
    bench->min_time_s = parseBenchMinTime(text->min_time);
    bench->route_sizes = parseRouteSizes(text->route_sizes);
    bench->irregular_route_sizes = parseRouteSizes(text->irregular_route_sizes, "--irregular-route-sizes");
    if (text->pipelines) {
      bench->pipelines.emplace();
      for (const std::string& name : splitNames(*text->pipelines))
        if (name != "none") bench->pipelines->push_back(name);
    }
    bench->road_model = roadModelFromString(text->road_model);
    return runBench(*bench, out, err);
  }));
}

}  // namespace mapnav::cli
