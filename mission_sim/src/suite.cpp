// The suite of unseen maps: each seed's random campus and mission written as files, run closed loop
// through the ordinary runner, and the runs summed up against the suite's targets.
#include "mapnav/mission_sim/suite.h"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/core/json.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/map/map_io.h"
#include "mapnav/map/random_campus.h"
#include "mapnav/mission/mission_file.h"
#include "mapnav/mission/runner.h"
#include "mapnav/mission_sim/closed_loop.h"

namespace mapnav {

namespace fs = std::filesystem;

const OptionTable<SuiteOptions>& suiteOptionTable() {
  using O = SuiteOptions;
  static const OptionTable<O> table =
      OptionTable<O>("SuiteOptions")
          .nest(&O::campus, randomCampusOptionTable(), {}, {"seed"})
          .field("max_frames", &O::max_frames, "per run; 0: to the goal")
          .field("world_json", &O::world_json, "the missions' `world` object but its seed (the run's)")
          .field("odometry_json", &O::odometry_json, "the missions' `odometry` object but its seed (the run's + 1)")
          .field("map_error_m", &O::map_error_m, inRange(0, 10),
                 "how wrong each map is: the world's roads offset from the map's by this 1-sigma, m; 0: the world is the map")
          .field("threads", &O::threads, inRange(1, 64), "seeds run at once; the results do not depend on it");
  return table;
}

void SuiteOptions::validate() const {
  if (seeds.empty()) throw InvalidInput("SuiteOptions::seeds: empty; give at least one seed");
  if (folder.empty()) throw InvalidInput("SuiteOptions::folder: empty; each seed's map and mission are written there");
  suiteOptionTable().validate(*this);
}

namespace {

std::optional<std::uint64_t> parseSeed(std::string_view text) {
  std::uint64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

}  // namespace

std::vector<std::uint64_t> parseSeedList(std::string_view text) {
  const std::string quoted = "'" + std::string(text) + "'";
  const std::string expected = " (expected seeds and ranges of them, e.g. 1-30, 7 or 1,4,9-12)";
  if (text.empty()) throw InvalidInput("empty seed list" + expected);
  std::vector<std::uint64_t> seeds;
  std::set<std::uint64_t> seen;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t comma = std::min(text.find(',', begin), text.size());
    const std::string_view item = text.substr(begin, comma - begin);
    const std::size_t dash = item.find('-');
    const auto first = parseSeed(item.substr(0, dash));
    const auto last = dash == std::string_view::npos ? first : parseSeed(item.substr(dash + 1));
    if (!first || !last) throw InvalidInput(quoted + " is not a seed list: '" + std::string(item) + "' is not a seed or a range" + expected);
    if (*first > *last) {
      throw InvalidInput(quoted + " is not a seed list: the range '" + std::string(item) + "' runs backwards (its first seed is above its last)");
    }
    if (*last - *first >= 100000) throw InvalidInput(quoted + ": the range '" + std::string(item) + "' has more than 100000 seeds");
    for (std::uint64_t s = *first;; ++s) {
      if (seen.insert(s).second) seeds.push_back(s);
      if (s == *last) break;
    }
    begin = comma + 1;
  }
  return seeds;
}

namespace {

// The relative error of the roads' widths in a world that differs from its map (SuiteOptions::map_error_m).
constexpr double kSuiteMapWidthError = 0.05;

// The mission document of one campus: the defaults of a mission file but for the map, the
// positions and the seeds (SuiteOptions::world_json, odometry_json).
Json missionJson(std::uint64_t seed, const RandomCampus& campus, const SuiteOptions& options) {
  Issues issues;
  std::optional<Json> world = parseJson(options.world_json, issues);
  std::optional<Json> odometry = parseJson(options.odometry_json, issues);
  if (!world || !odometry || !world->is_object() || !odometry->is_object()) {
    throw InvalidInput("SuiteOptions.world_json / odometry_json: not JSON objects");
  }
  (*world)["seed"] = seed;
  if (options.map_error_m > 0) {
    (*world)["map_error"] = {{"offset_sigma_m", options.map_error_m}, {"width_sigma", kSuiteMapWidthError}, {"seed", seed + 2}};
  }
  (*odometry)["seed"] = seed + 1;
  Json m{{"format", kMissionFormat},
         {"name", "random campus " + std::to_string(seed)},
         {"x-note", "mapnav suite random-campus: makeRandomCampus(seed " + std::to_string(seed) + ", " +
                        std::to_string(options.campus.junctions) + " junctions); nothing tuned to this map"},
         {"map", "map.json"},
         {"camera", fs::absolute(options.camera).lexically_normal().string()},
         {"start", campus.start}};
  if (!campus.via.empty()) m["via"] = campus.via;
  m["goal"] = campus.goal;
  m["world"] = *world;
  m["odometry"] = *odometry;
  return m;
}

std::string junctionsText(const RandomCampus& campus) {
  std::string out;
  for (const IntersectionKind k : campus.junctions) {
    out += (out.empty() ? "" : " ") + std::string(k == IntersectionKind::Cross ? "cross" : toString(k));
  }
  return out;
}

// The timing figures vary from run to run; the rest of a run's JSON does not.
std::string runJsonWithoutTimes(const MissionRun& run) {
  Json j = Json::parse(runToJson(run));
  for (const char* key : {"latency_ms_median", "latency_ms_p99", "latency_ms_max", "vision_ms_median"}) j.erase(key);
  return j.dump();
}

std::string surfacesText(const RandomCampus& campus) {
  for (const Road& r : campus.map.roads) {
    if (r.surface == "concrete" || r.surface == "brick") return "concrete/brick";
  }
  return "asphalt/gravel";
}

}  // namespace

SuiteRun runSuiteSeed(std::uint64_t seed, const SuiteOptions& options) {
  options.validate();
  RandomCampusOptions campus_options = options.campus;
  campus_options.seed = seed;
  RandomCampus campus = makeRandomCampus(campus_options);
  // A map that is wrong says how wrong, as a map drawn over imagery or imported from OSM does.
  campus.map.position_sigma_m = options.map_error_m;
  const fs::path folder = options.folder / ("seed-" + std::to_string(seed));
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw IoError(folder.string() + ": cannot create the seed's folder: " + ec.message());
  saveMap(campus.map, folder / "map.json");
  writeFileAtomic(folder / "mission.json", dumpJson(missionJson(seed, campus, options)));

  SuiteRun r;
  r.seed = seed;
  r.junctions = junctionsText(campus);
  r.via = !campus.via.empty();
  r.surfaces = surfacesText(campus);
  r.mission = folder / "mission.json";
  const auto start = std::chrono::steady_clock::now();
  try {
    RunOptions run_options;
    run_options.max_frames = options.max_frames;
    run_options.map = options.map;
    const MissionRun run = runClosedLoop(loadMission(r.mission), run_options);
    r.pipeline = run.pipeline;
    r.route_m = run.route.length_m;
    r.outcome = run.outcome;
    r.stopped_early = run.stopped_early;
    r.metrics = run.metrics;
    r.run_json = runJsonWithoutTimes(run);
    r.reached = run.metrics.reached_goal && run.metrics.goal_distance_m <= kSuiteGoalToleranceM;
  } catch (const std::exception& e) {
    r.error = true;
    r.outcome = std::string("error: ") + e.what();
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

std::vector<SuiteRun> runSuite(const SuiteOptions& options, const std::function<void(const SuiteRun&)>& done) {
  options.validate();
  const std::size_t n = options.seeds.size();
  std::vector<SuiteRun> runs;
  const std::size_t workers = std::min<std::size_t>(static_cast<std::size_t>(options.threads), n);
  if (workers == 1) {
    for (const std::uint64_t seed : options.seeds) {
      runs.push_back(runSuiteSeed(seed, options));
      if (done) done(runs.back());
    }
    return runs;
  }
  // Workers take the next seed until none is left; the calling thread reports in seed order.
  std::vector<std::optional<SuiteRun>> results(n);
  std::vector<std::exception_ptr> failures(n);
  std::mutex mutex;
  std::condition_variable finished;
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t i = next++; i < n; i = next++) {
      std::optional<SuiteRun> r;
      std::exception_ptr failure;
      try {
        r = runSuiteSeed(options.seeds[i], options);
      } catch (...) {
        failure = std::current_exception();
      }
      const std::lock_guard<std::mutex> lock(mutex);
      results[i] = std::move(r);
      failures[i] = failure;
      finished.notify_all();
    }
  };
  std::vector<std::thread> threads;
  for (std::size_t k = 0; k < workers; ++k) threads.emplace_back(work);
  std::exception_ptr failure;
  for (std::size_t i = 0; i < n && !failure; ++i) {
    std::unique_lock<std::mutex> lock(mutex);
    finished.wait(lock, [&] { return results[i].has_value() || failures[i]; });
    if (failures[i]) {
      failure = failures[i];
      next = n;  // no new seeds: the suite cannot go on (bad options, an unwritable folder)
      continue;
    }
    runs.push_back(std::move(*results[i]));
    lock.unlock();
    try {
      if (done) done(runs.back());
    } catch (...) {  // the workers are joined before it goes on
      failure = std::current_exception();
      next = n;
    }
  }
  for (std::thread& t : threads) t.join();
  if (failure) std::rethrow_exception(failure);
  return runs;
}

// ---- a run as a record ------------------------------------------------------------------------

std::string suiteRunToJson(const SuiteRun& r) {
  const MissionMetrics& m = r.metrics;
  const FilterConsistency& c = m.consistency;
  const Json metrics{{"frames", m.frames},
                     {"has_truth", m.has_truth},
                     {"reached_goal", m.reached_goal},
                     {"goal_distance_m", m.goal_distance_m},
                     {"lateral_rms_m", m.estimate.lateral_rms_m},
                     {"along_max_m", m.estimate.along_max_m},
                     {"heading_rms_deg", m.estimate.heading_rms_deg},
                     {"left_path_frames", m.left_path_frames},
                     {"vision_failures", m.vision_failures},
                     {"replans", m.replans},
                     {"consistency_frames", c.frames},
                     {"within_2sigma_along", c.within_2sigma_along},
                     {"within_2sigma_lateral", c.within_2sigma_lateral},
                     {"within_2sigma_heading", c.within_2sigma_heading},
                     {"nees_frames", c.nees_frames},
                     {"nees_mean", c.nees_mean}};
  const Json j{{"seed", r.seed},         {"junctions", r.junctions},   {"via", r.via},
               {"surfaces", r.surfaces}, {"mission", r.mission.string()}, {"pipeline", r.pipeline},
               {"route_m", r.route_m},   {"outcome", r.outcome},       {"error", r.error},
               {"reached", r.reached},   {"stopped_early", r.stopped_early}, {"metrics", metrics},
               {"run_json", r.run_json}, {"wall_s", r.wall_s}};
  return j.dump();
}

SuiteRun suiteRunFromJson(std::string_view text) {
  try {
    const Json j = Json::parse(text);
    const Json& m = j.at("metrics");
    SuiteRun r;
    r.seed = j.at("seed").get<std::uint64_t>();
    r.junctions = j.at("junctions").get<std::string>();
    r.via = j.at("via").get<bool>();
    r.surfaces = j.at("surfaces").get<std::string>();
    r.mission = j.at("mission").get<std::string>();
    r.pipeline = j.at("pipeline").get<std::string>();
    r.route_m = j.at("route_m").get<double>();
    r.outcome = j.at("outcome").get<std::string>();
    r.error = j.at("error").get<bool>();
    r.reached = j.at("reached").get<bool>();
    r.stopped_early = j.at("stopped_early").get<bool>();
    r.run_json = j.at("run_json").get<std::string>();
    r.wall_s = j.at("wall_s").get<double>();
    MissionMetrics& out = r.metrics;
    out.frames = m.at("frames").get<std::size_t>();
    out.has_truth = m.at("has_truth").get<bool>();
    out.reached_goal = m.at("reached_goal").get<bool>();
    out.goal_distance_m = m.at("goal_distance_m").get<double>();
    out.estimate.lateral_rms_m = m.at("lateral_rms_m").get<double>();
    out.estimate.along_max_m = m.at("along_max_m").get<double>();
    out.estimate.heading_rms_deg = m.at("heading_rms_deg").get<double>();
    out.left_path_frames = m.at("left_path_frames").get<std::size_t>();
    out.vision_failures = m.at("vision_failures").get<std::size_t>();
    out.replans = m.at("replans").get<std::size_t>();
    FilterConsistency& c = out.consistency;
    c.frames = m.at("consistency_frames").get<std::size_t>();
    c.within_2sigma_along = m.at("within_2sigma_along").get<double>();
    c.within_2sigma_lateral = m.at("within_2sigma_lateral").get<double>();
    c.within_2sigma_heading = m.at("within_2sigma_heading").get<double>();
    c.nees_frames = m.at("nees_frames").get<std::size_t>();
    c.nees_mean = m.at("nees_mean").get<double>();
    return r;
  } catch (const Json::exception& e) {
    const std::string head(text.substr(0, 60));
    throw InvalidInput("not a suite run record (" + std::string(e.what()) + "): '" + head +
                       (text.size() > 60 ? "...'" : "'"));
  }
}

SuiteSummary summarizeSuite(const std::vector<SuiteRun>& runs) {
  SuiteSummary s;
  s.runs = runs.size();
  std::vector<double> lateral, along, heading, goal, nees;
  double along_in = 0, lateral_in = 0, heading_in = 0;
  std::size_t truth_frames = 0;
  for (const SuiteRun& r : runs) {
    const MissionMetrics& m = r.metrics;
    s.reached += r.reached;
    s.errors += r.error;
    s.wall_s += r.wall_s;
    if (r.error) continue;
    s.on_path += m.stayedOnPath();
    s.frames += m.frames;
    s.vision_failures += m.vision_failures;
    s.replans += m.replans;
    s.left_path_frames += m.left_path_frames;
    lateral.push_back(m.estimate.lateral_rms_m);
    along.push_back(m.estimate.along_max_m);
    heading.push_back(m.estimate.heading_rms_deg);
    goal.push_back(m.goal_distance_m);
    const FilterConsistency& c = m.consistency;
    if (c.nees_frames > 0) nees.push_back(c.nees_mean);
    s.consistent += c.frames > 0 && c.within_2sigma_along >= 0.9 && c.within_2sigma_lateral >= 0.9 &&
                    c.within_2sigma_heading >= 0.9;
    const double f = static_cast<double>(c.frames);
    along_in += c.within_2sigma_along * f;
    lateral_in += c.within_2sigma_lateral * f;
    heading_in += c.within_2sigma_heading * f;
    truth_frames += c.frames;
  }
  s.lateral_rms_median_m = percentile(lateral, 50);
  s.along_max_median_m = percentile(along, 50);
  s.heading_rms_median_deg = percentile(heading, 50);
  s.goal_distance_median_m = percentile(goal, 50);
  s.nees_median = percentile(nees, 50);
  if (truth_frames > 0) {
    const double n = static_cast<double>(truth_frames);
    s.within_2sigma_along = along_in / n;
    s.within_2sigma_lateral = lateral_in / n;
    s.within_2sigma_heading = heading_in / n;
  }
  return s;
}

// ---- text and JSON ------------------------------------------------------------------------------

std::string suiteHeaderText(bool wall_time) {
  std::string line = strprintf("%5s %-14s %-3s %-14s %-12s %6s %-7s %7s %5s %7s %7s %7s %6s %6s %6s %6s %5s %5s",
                               "seed", "junctions", "via", "surfaces", "pipeline", "frames", "reached", "goal_m",
                               "off", "lat_rms", "alg_max", "hd_rms", "2s_alg", "2s_lat", "2s_hd", "nees", "visF",
                               "repl");
  if (wall_time) line += strprintf(" %7s", "wall_s");
  return line + "\n";
}

std::string suiteRowText(const SuiteRun& r, bool wall_time) {
  const MissionMetrics& m = r.metrics;
  const FilterConsistency& c = m.consistency;
  std::string line = strprintf("%5llu %-14s %-3s %-14s ", static_cast<unsigned long long>(r.seed), r.junctions.c_str(),
                               r.via ? "yes" : "no", r.surfaces.c_str());
  if (r.error) return line + r.outcome + (wall_time ? strprintf(" (%.1f s)", r.wall_s) : std::string()) + "\n";
  line += strprintf("%-12s %6zu %-7s %7.3f %5zu %7.4f %7.3f %7.3f %6.3f %6.3f %6.3f %6s %5zu %5zu", r.pipeline.c_str(),
                    m.frames, r.reached ? "yes" : (r.stopped_early ? "cut" : "NO"), m.goal_distance_m,
                    m.left_path_frames, m.estimate.lateral_rms_m, m.estimate.along_max_m, m.estimate.heading_rms_deg,
                    c.within_2sigma_along, c.within_2sigma_lateral, c.within_2sigma_heading,
                    c.nees_frames > 0 ? strprintf("%.2f", c.nees_mean).c_str() : "-", m.vision_failures, m.replans);
  if (wall_time) line += strprintf(" %7.1f", r.wall_s);
  return line + "\n";
}

namespace {
const char* mark(bool met) { return met ? "met" : "NOT met"; }
}  // namespace

std::string suiteSummaryText(const SuiteSummary& s, bool wall_time) {
  const auto need = static_cast<std::size_t>(s.runs > 0 ? s.runs - s.runs / 30 : 0);  // 29 of 30
  std::string out = strprintf("summary of %zu runs (%zu frames; the suite's targets beside each figure):\n",
                              s.runs, s.frames);
  out += strprintf("  reached the goal within %.1f m: %zu of %zu (target >= %zu of %zu: %s)\n", kSuiteGoalToleranceM,
                   s.reached, s.runs, need, s.runs, mark(s.reached >= need));
  out += strprintf("  0 frames off the path: %zu of %zu runs, %zu frames off in all (target: all runs: %s)\n", s.on_path,
                   s.runs, s.left_path_frames, mark(s.on_path == s.runs));
  out += strprintf("  median run: lateral RMS %.4f m (target <= 0.05: %s), along max %.3f m (target <= 0.3: %s), "
                   "heading RMS %.2f deg, goal distance %.3f m\n",
                   s.lateral_rms_median_m, mark(s.lateral_rms_median_m <= 0.05), s.along_max_median_m,
                   mark(s.along_max_median_m <= 0.3), s.heading_rms_median_deg, s.goal_distance_median_m);
  const bool all_axes = s.within_2sigma_along >= 0.9 && s.within_2sigma_lateral >= 0.9 && s.within_2sigma_heading >= 0.9;
  out += strprintf("  true error within 2 sigma, frames of all runs: along %.1f %%, lateral %.1f %%, heading %.1f %% "
                   "(target >= 90 %% on every axis: %s); runs with >= 90 %% on every axis: %zu of %zu; median NEES "
                   "mean %.2f (expected 3)\n",
                   100 * s.within_2sigma_along, 100 * s.within_2sigma_lateral, 100 * s.within_2sigma_heading,
                   mark(all_axes), s.consistent, s.runs, s.nees_median);
  out += strprintf("  vision failures %zu, replans %zu, runs that threw %zu\n", s.vision_failures, s.replans, s.errors);
  if (wall_time) out += strprintf("  wall time %.1f s over the runs\n", s.wall_s);
  return out;
}

namespace {

Json runJson(const SuiteRun& r, bool wall_time) {
  Json j{{"seed", r.seed},
         {"junctions", r.junctions},
         {"via", r.via},
         {"surfaces", r.surfaces},
         {"error", r.error},
         {"outcome", r.outcome},
         {"reached", r.reached},
         {"stopped_early", r.stopped_early},
         {"run", r.run_json.empty() ? Json(nullptr) : Json::parse(r.run_json)}};
  if (wall_time) j["wall_s"] = roundTo(r.wall_s, 1e2);
  return j;
}

}  // namespace

std::string suiteJson(const SuiteOptions& options, const std::vector<SuiteRun>& runs, const SuiteSummary& s,
                      bool wall_time) {
  Json list = Json::array();
  for (const SuiteRun& r : runs) list.push_back(runJson(r, wall_time));
  Json summary{{"runs", s.runs},
               {"reached", s.reached},
               {"on_path", s.on_path},
               {"consistent", s.consistent},
               {"lateral_rms_median_m", roundTo(s.lateral_rms_median_m, 1e5)},
               {"along_max_median_m", roundTo(s.along_max_median_m, 1e5)},
               {"heading_rms_median_deg", roundTo(s.heading_rms_median_deg, 1e4)},
               {"goal_distance_median_m", roundTo(s.goal_distance_median_m, 1e4)},
               {"within_2sigma_along", roundTo(s.within_2sigma_along, 1e4)},
               {"within_2sigma_lateral", roundTo(s.within_2sigma_lateral, 1e4)},
               {"within_2sigma_heading", roundTo(s.within_2sigma_heading, 1e4)},
               {"nees_median", roundTo(s.nees_median, 1e3)},
               {"frames", s.frames},
               {"left_path_frames", s.left_path_frames},
               {"vision_failures", s.vision_failures},
               {"replans", s.replans},
               {"errors", s.errors},
               {"targets",
                {{"reached_fraction", 29.0 / 30.0},
                 {"left_path_frames", 0},
                 {"lateral_rms_median_m", 0.05},
                 {"along_max_median_m", 0.3},
                 {"within_2sigma", 0.9}}}};
  if (wall_time) summary["wall_s"] = roundTo(s.wall_s, 1e2);
  Json j{{"suite", "random-campus"},
         {"junctions", options.campus.junctions},
         {"max_frames", options.max_frames},
         {"map_error_m", options.map_error_m},
         {"map_options", Json::parse(mapModuleOptionTable().json(options.map))},
         {"goal_tolerance_m", kSuiteGoalToleranceM},
         {"runs", list},
         {"summary", summary}};
  return j.dump() + "\n";
}

}  // namespace mapnav
