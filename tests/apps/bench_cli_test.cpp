// `mapnav bench` end to end: the JSON's rows and that their numbers agree with each other, the table,
// the park finder's figures. No timing asserts: the machine decides how fast.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
using testing::runCli;

// `mapnav bench` end to end at two small sizes: the JSON's shape and that its numbers agree with each
// other. No timing asserts: the machine decides how fast.
TEST(Cli, BenchJsonHasTwoRowsPerSizeWithConsistentRatios) {
  const auto r = runCli({"bench", "--json", "--sizes", "64,128", "--min-time", "0.01", "--route-sizes", "400,100",
                         "--irregular-route-sizes", "100", "--loop-frames", "6", "--pipelines", "sidewalk,color-rgb"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("runtime")) << r.out;
  ASSERT_TRUE(j.contains("train_ms")) << r.out;
  ASSERT_TRUE(j["train_ms"].is_number()) << r.out;
  EXPECT_GT(j["train_ms"].get<double>(), 0.0);
  EXPECT_TRUE(std::isfinite(j["train_ms"].get<double>()));
  EXPECT_EQ(j["train_size"], 128);  // 512 is not measured: the largest size
  EXPECT_EQ(j["road_model"], "line");  // the default, the paper's
  // The two pipelines asked for, at 480x360 and 512x480, one thread each (neither has a threads
  // option); sidewalk's own ratio is 1.
  ASSERT_EQ(j["pipelines"].size(), 4u) << r.out;
  for (const auto& row : j["pipelines"]) {
    EXPECT_TRUE(row["pipeline"] == "sidewalk" || row["pipeline"] == "color-rgb") << row.dump();
    EXPECT_EQ(row["threads"], 1);
    EXPECT_GT(row["ms"].get<double>(), 0.0);
    if (row["pipeline"] == "sidewalk") {
      EXPECT_DOUBLE_EQ(row["sidewalk_ratio"].get<double>(), 1.0);
    }
  }
  const int cores = j["cores"].get<int>();
  EXPECT_GE(cores, 1);
  ASSERT_EQ(j["runtime"].size(), 4u) << r.out;
  std::map<int, std::set<int>> threads_by_size;
  for (const auto& row : j["runtime"]) {
    for (const char* key : {"size", "threads", "fps", "ms", "px_per_s", "memcpy_ratio", "reference_ratio", "memcpy_ms",
                            "reference_ms"}) {
      ASSERT_TRUE(row.contains(key) && row[key].is_number()) << key << " in " << row.dump();
      const double v = row[key].get<double>();
      EXPECT_TRUE(std::isfinite(v) && v > 0) << key << " in " << row.dump();
    }
    const int size = row["size"].get<int>();
    const double ms = row["ms"].get<double>(), fps = row["fps"].get<double>();
    threads_by_size[size].insert(row["threads"].get<int>());
    EXPECT_NEAR(ms, 1000.0 / fps, 1e-9 * ms) << row.dump();
    EXPECT_NEAR(row["px_per_s"].get<double>(), fps * size * size, 1e-9 * fps * size * size) << row.dump();
    EXPECT_NEAR(row["memcpy_ratio"].get<double>(), ms / row["memcpy_ms"].get<double>(),
                1e-9 * row["memcpy_ratio"].get<double>())
        << row.dump();
    EXPECT_NEAR(row["reference_ratio"].get<double>(), row["reference_ms"].get<double>() / ms,
                1e-9 * row["reference_ratio"].get<double>())
        << row.dump();
  }
  // Each size once with one thread and once with every core.
  EXPECT_EQ(threads_by_size.size(), 2u);
  for (const int size : {64, 128}) {
    ASSERT_TRUE(threads_by_size.count(size)) << size;
    EXPECT_TRUE(threads_by_size[size].count(1)) << size;
    EXPECT_TRUE(threads_by_size[size].count(cores)) << size;
  }
  int rows_per_size[2] = {0, 0};
  for (const auto& row : j["runtime"]) ++rows_per_size[row["size"] == 64 ? 0 : 1];
  EXPECT_EQ(rows_per_size[0], 2);
  EXPECT_EQ(rows_per_size[1], 2);
  // The sidewalk pipeline at the Terregator camera's 512 x 480, with its ratios from the same run.
  ASSERT_TRUE(j.contains("sidewalk")) << r.out;
  const auto& sw = j["sidewalk"];
  EXPECT_EQ(sw["width"], 512);
  EXPECT_EQ(sw["height"], 480);
  for (const char* key : {"ms", "fps", "memcpy_ratio", "reference_ratio", "reference_ms", "memcpy_ms", "with_prediction_ms"}) {
    ASSERT_TRUE(sw.contains(key) && sw[key].is_number()) << key << " in " << sw.dump();
    EXPECT_GT(sw[key].get<double>(), 0.0) << key;
  }
  const double sw_ms = sw["ms"].get<double>();
  EXPECT_NEAR(sw["fps"].get<double>(), 1000.0 / sw_ms, 1e-9 * sw["fps"].get<double>());
  EXPECT_NEAR(sw["memcpy_ratio"].get<double>(), sw_ms / sw["memcpy_ms"].get<double>(), 1e-9 * sw["memcpy_ratio"].get<double>());
  EXPECT_NEAR(sw["reference_ratio"].get<double>(), sw["reference_ms"].get<double>() / sw_ms,
              1e-9 * sw["reference_ratio"].get<double>());
  // The renderer at the same size, and the route queries on grids of 10 x 10 and 20 x 20, smallest first.
  const auto& render = j["render"];
  EXPECT_EQ(render["width"], 512);
  EXPECT_EQ(render["height"], 480);
  const double render_ms = render["ms"].get<double>();
  EXPECT_GT(render_ms, 0.0);
  EXPECT_NEAR(render["fps"].get<double>(), 1000.0 / render_ms, 1e-9 * render["fps"].get<double>());
  EXPECT_NEAR(render["memcpy_ratio"].get<double>(), render_ms / render["memcpy_ms"].get<double>(),
              1e-9 * render["memcpy_ratio"].get<double>());
  EXPECT_TRUE(j["park"].is_object() && j["park"].empty()) << j["park"].dump();  // neither 512 nor 1024 measured
  // The grids, then the irregular map of 10 x 10 intersections: 2 x 10 x 9 roads, each bent.
  ASSERT_EQ(j["route"].size(), 3u) << r.out;
  EXPECT_EQ(j["route"][0]["intersections"], 100);
  EXPECT_EQ(j["route"][1]["intersections"], 400);
  EXPECT_EQ(j["route"][2]["intersections"], 100);
  EXPECT_EQ(j["route"][0]["map"], "grid");
  EXPECT_EQ(j["route"][2]["map"], "irregular");
  EXPECT_EQ(j["route"][2]["roads"], 180);
  for (const auto& q : j["route"]) {
    EXPECT_GT(q["prep_s"].get<double>(), 0.0) << q.dump();
    EXPECT_NEAR(q["dijkstra_ratio"].get<double>(), q["dijkstra_ms"].get<double>() / q["astar_ms"].get<double>(),
                1e-9 * q["dijkstra_ratio"].get<double>())
        << q.dump();
    const double mean = q["query_mean_ms"].get<double>(), median = q["query_median_ms"].get<double>(),
                 max = q["query_max_ms"].get<double>();
    EXPECT_GT(median, 0.0) << q.dump();
    EXPECT_LE(median, max) << q.dump();
    EXPECT_LE(mean, max) << q.dump();
  }
  // The mission loop's latency over the frames asked for.
  const auto& loop = j["loop"];
  EXPECT_EQ(loop["mission"], "campus dialogue");
  EXPECT_EQ(loop["frames"], 6);
  EXPECT_GT(loop["latency_median_ms"].get<double>(), 0.0);
  EXPECT_GE(loop["latency_p99_ms"].get<double>(), loop["latency_median_ms"].get<double>());
  EXPECT_LE(loop["vision_median_ms"].get<double>(), loop["latency_median_ms"].get<double>());
}

TEST(Cli, BenchPrintsATableWithTheRatios) {
  const auto r = runCli({"bench", "--sizes", "32,64", "--min-time", "0.01", "--threads", "2", "--route-sizes", "100,400",
                         "--irregular-route-sizes", "100", "--loop-frames", "4", "--pipelines", "none"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* text : {"cores", "memcpy_ratio", "reference_ratio", "frames/s", "cost per pixel growth", "training at 64x64",
                           "sidewalk pipeline", "at 512x480", "renderer", "grid campus of 100 intersections",
                           "grid campus of 400 intersections", "route query growth from 100 to 400 intersections",
                           "irregular campus of 100 intersections (180 roads)", "mission loop (campus dialogue, closed loop, 4 frames)"}) {
    EXPECT_NE(r.out.find(text), std::string::npos) << text << "\n" << r.out;
  }
  EXPECT_NE(r.out.find("line road model"), std::string::npos) << r.out;  // the default, the paper's
  // The arc model (§9) is timed when asked for, and says so.
  const auto arc = runCli({"bench", "--sizes", "32", "--min-time", "0.01", "--threads", "1", "--road-model", "arc",
                           "--pipelines", "none", "--route-sizes", "", "--irregular-route-sizes", "", "--loop-frames", "0"});
  ASSERT_EQ(arc.exit_code, 0) << arc.err;
  EXPECT_NE(arc.out.find("arc road model"), std::string::npos) << arc.out;
  const auto help = runCli({"bench", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("memcpy_ratio"), std::string::npos) << help.out;
  EXPECT_NE(help.out.find("reference_ratio"), std::string::npos) << help.out;
}

// A pipeline's ratio to sidewalk's time needs sidewalk timed at its size: without it the JSON says
// null and the table "-", not 0.
TEST(Cli, BenchGivesNoSidewalkRatioWithoutSidewalk) {
  const std::vector<std::string> args = {"bench", "--sizes", "32", "--min-time", "0.01", "--route-sizes", "",
                                         "--irregular-route-sizes", "", "--loop-frames", "0", "--pipelines", "color-rgb"};
  std::vector<std::string> json_args = args;
  json_args.push_back("--json");
  const auto r = runCli(json_args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["pipelines"].size(), 2u) << r.out;
  for (const auto& row : j["pipelines"]) EXPECT_TRUE(row["sidewalk_ratio"].is_null()) << row.dump();
  const auto text = runCli(args);
  ASSERT_EQ(text.exit_code, 0) << text.err;
  const auto row = text.out.find("color-rgb        1");
  ASSERT_NE(row, std::string::npos) << text.out;
  const std::string line = text.out.substr(row, text.out.find('\n', row) - row);
  EXPECT_EQ(line.back(), '-') << line;
  EXPECT_EQ(line.find("0.00"), std::string::npos) << line;
}

// The park finder figures: at 512 the line with frames/s (one thread) and its target, the JSON's
// park.fps_512 the one-thread row's; no 1024 figure without 1024.
TEST(Cli, BenchPrintsTheParkFinderFiguresAndTheirTargets) {
  const auto r =
      runCli({"bench", "--json", "--sizes", "512", "--min-time", "0.01", "--route-sizes", "", "--irregular-route-sizes", "",
              "--loop-frames", "0", "--pipelines", "none"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j["park"].contains("fps_512")) << j["park"].dump();
  EXPECT_FALSE(j["park"].contains("memcpy_ratio_1024")) << j["park"].dump();
  // The first one-thread row (on a one-core machine both rows have one thread).
  const auto& rows = j["runtime"];
  const auto first = std::find_if(rows.begin(), rows.end(), [](const auto& row) { return row["threads"] == 1; });
  ASSERT_NE(first, rows.end()) << rows.dump();
  EXPECT_EQ(j["park"]["fps_512"].get<double>(), (*first)["fps"].get<double>());
  const auto text = runCli(
      {"bench", "--sizes", "512", "--min-time", "0.01", "--threads", "1", "--route-sizes", "", "--irregular-route-sizes", "",
       "--loop-frames", "0", "--pipelines", "none"});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("park road finder (the fast path, one thread): "), std::string::npos) << text.out;
  EXPECT_NE(text.out.find(" frames/s at 512x512 (target: >= 2000)"), std::string::npos) << text.out;
  EXPECT_EQ(text.out.find("at 1024x1024"), std::string::npos) << text.out;
}

}  // namespace
}  // namespace mapnav
