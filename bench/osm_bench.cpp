// `mapnav map import-osm` on a city-sized file: a generated OSM XML file of 10 000 and
// 100 000 walkable ways — a grid of footways 40 m apart, each way bent at a middle node jittered
// up to 3 m sideways (seeded), every grid node shared by the ways meeting there — imported as the
// command does before it writes (importOsm, then validation by building the Map). Counters:
// import_MiB, the rise of the process's peak resident memory during the import (Linux), roads and
// intersections. BM_OsmRoute then times route queries on the imported map between 32 seeded
// random road positions (after the landmark preprocessing, prep_s), median_ms over the queries.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <unistd.h>

#include "bench_util.h"
#include "mapnav/navigator/route.h"
#include "mapnav/osm/osm_import.h"

namespace {

using namespace mapnav;
using bench::resetPeakMemory;
using bench::secondsSince;
using bench::statusKb;

constexpr double kLat0 = 42.05, kLon0 = -87.67, kSpacing = 40.0;

// Writes the grid of `ways` footways and returns the file.
std::filesystem::path writeCity(int ways) {
  int n = 2;
  while (2 * n * (n - 1) < ways) ++n;  // n × n grid nodes give 2 n (n - 1) edges
  const double m_per_deg_lat = 111132.95, m_per_deg_lon = 111319.49 * std::cos(kLat0 * 3.14159265358979 / 180);
  auto node = [&](std::ofstream& out, long id, double east, double north) {
    char text[160];
    std::snprintf(text, sizeof text, " <node id=\"%ld\" version=\"1\" lat=\"%.8f\" lon=\"%.8f\"/>\n", id,
                  kLat0 + north / m_per_deg_lat, kLon0 + east / m_per_deg_lon);
    out << text;
  };
  const auto file = std::filesystem::temp_directory_path() /
                    ("mapnav_osm_bench_" + std::to_string(ways) + "_" + std::to_string(getpid()) + ".osm");
  std::ofstream out(file);
  out << "<?xml version='1.0' encoding='UTF-8'?>\n<osm version=\"0.6\" generator=\"mapnav bench\">\n";
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < n; ++r) node(out, c * n + r + 1, c * kSpacing, r * kSpacing);
  }
  std::mt19937 rng(27);
  std::uniform_real_distribution<double> jitter(-3.0, 3.0);
  std::string way_text;
  long way = 0;
  for (int c = 0; c < n && way < ways; ++c) {
    for (int r = 0; r < n && way < ways; ++r) {
      for (const bool east : {true, false}) {
        if ((east ? c : r) + 1 >= n || way >= ways) continue;
        const long a = c * n + r + 1, b = a + (east ? n : 1), bend = static_cast<long>(n) * n + way + 1;
        const double side = jitter(rng);
        node(out, bend, c * kSpacing + (east ? kSpacing / 2 : side), r * kSpacing + (east ? side : kSpacing / 2));
        way_text += " <way id=\"" + std::to_string(++way) + "\" version=\"1\"><nd ref=\"" + std::to_string(a) +
                    "\"/><nd ref=\"" + std::to_string(bend) + "\"/><nd ref=\"" + std::to_string(b) +
                    "\"/><tag k=\"highway\" v=\"footway\"/></way>\n";
      }
    }
  }
  out << way_text << "</osm>\n";
  return file;
}

struct City {
  std::unique_ptr<Map> map;
  double import_s = 0, import_mib = 0, file_mib = 0;
};

OsmImportOptions importOptions() {
  OsmImportOptions o;
  o.origin = GeoOrigin{kLat0, kLon0, 0};
  return o;
}

// One import of `file` as `mapnav map import-osm` does it (without writing), timed.
City importCity(const std::filesystem::path& file) {
  City city;
  resetPeakMemory();
  const double rss0 = statusKb("VmRSS");
  const auto t0 = std::chrono::steady_clock::now();
  OsmImport imported = importOsm(file, importOptions());
  city.map = std::make_unique<Map>(std::move(imported.map), file.string());  // validates; throws when invalid
  city.import_s = secondsSince(t0);
  city.import_mib = (statusKb("VmHWM") - rss0) / 1024;
  city.file_mib = static_cast<double>(std::filesystem::file_size(file)) / (1 << 20);
  return city;
}

// The generated files, written once per process and removed when it ends.
const std::filesystem::path& cityFile(int ways) {
  static struct Files {
    std::map<int, std::filesystem::path> paths;
    ~Files() {
      for (const auto& [n, path] : paths) std::filesystem::remove(path);
    }
  } files;
  auto it = files.paths.find(ways);
  if (it == files.paths.end()) it = files.paths.emplace(ways, writeCity(ways)).first;
  return it->second;
}

void BM_OsmImport(benchmark::State& state) {
  const auto& file = cityFile(static_cast<int>(state.range(0)));
  City city;
  for (auto _ : state) {
    city = importCity(file);
    benchmark::DoNotOptimize(city.map.get());
  }
  state.counters["roads"] = static_cast<double>(city.map->roads().size());
  state.counters["intersections"] = static_cast<double>(city.map->intersections().size());
  state.counters["import_MiB"] = city.import_mib;
  state.counters["file_MiB"] = city.file_mib;
}
BENCHMARK(BM_OsmImport)->Arg(10000)->Arg(100000)->Iterations(1)->Unit(benchmark::kSecond);

void BM_OsmRoute(benchmark::State& state) {
  static std::map<int, City> cities;
  const int ways = static_cast<int>(state.range(0));
  if (!cities.contains(ways)) cities.emplace(ways, importCity(cityFile(ways)));
  const Map& map = *cities.at(ways).map;
  auto t0 = std::chrono::steady_clock::now();
  RoadGraph graph(map);
  std::mt19937 rng(31);
  std::uniform_int_distribution<std::size_t> pick(0, map.roads().size() - 1);
  std::vector<std::pair<RoadPosition, RoadPosition>> queries;
  for (int i = 0; i < 32; ++i) {
    const Road& a = map.roads()[pick(rng)];
    const Road& b = map.roads()[pick(rng)];
    queries.push_back({{a.id, a.from, a.centerline.length() / 2}, {b.id, b.from, b.centerline.length() / 2}});
  }
  benchmark::DoNotOptimize(graph.route(queries[0].first, queries[0].second));  // computes the landmarks
  const double prep_s = secondsSince(t0);
  std::vector<double> ms;
  std::size_t i = 0;
  for (auto _ : state) {
    const auto& [from, to] = queries[i++ % queries.size()];
    t0 = std::chrono::steady_clock::now();
    const RouteResult r = graph.route(from, to);
    ms.push_back(1e3 * secondsSince(t0));
    benchmark::DoNotOptimize(r);
  }
  std::sort(ms.begin(), ms.end());
  state.counters["median_ms"] = ms[ms.size() / 2];
  state.counters["max_ms"] = ms.back();
  state.counters["prep_s"] = prep_s;
}
BENCHMARK(BM_OsmRoute)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

}  // namespace
