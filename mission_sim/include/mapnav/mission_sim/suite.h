#pragma once
// The suite of unseen maps: random small campuses (map/random_campus.h), each with its mission, run
// closed loop in the simulator (closed_loop.h) at the defaults of a mission file, and what came of
// them — per seed and summed up against the suite's targets. Nothing in it is tuned per map: every
// seed's mission is the same document but for the map, its positions and its seeds.
//
// Each seed's map and mission are written to a folder (SuiteOptions::folder) and the mission is
// read back with loadMission, so that the run sees exactly what `mapnav run --mission
// FOLDER/seed-N/mission.json` sees: a failure is reproduced with that command.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/map/random_campus.h"
#include "mapnav/mission/metrics.h"
#include "mapnav/mission/modules.h"

namespace mapnav {

/// The suite's threshold: a run reaches its goal when the Navigator has arrived and the true
/// position is within this of the goal, m (stricter than a mission's 0.5 m).
inline constexpr double kSuiteGoalToleranceM = 0.3;

struct SuiteOptions {
  std::vector<std::uint64_t> seeds;  ///< one map and mission each (parseSeedList)
  /// Each seed's campus (its seed is the run's): RandomCampusOptions' junctions, widths and lengths.
  RandomCampusOptions campus;
  std::size_t max_frames = 0;        ///< per run, 0: to the goal (RunOptions::max_frames)
  std::filesystem::path camera;      ///< the missions' camera file (the shipped missions': terregator_pinhole)
  /// Where each seed's map.json and mission.json go, in seed-N/ (created; existing files replaced).
  std::filesystem::path folder;
  /// The missions' `world` and `odometry` blocks but for their seeds (world: the seed; odometry: the
  /// seed + 1): the shipped campus missions' shadows, sensor noise and odometry errors (1 % scale
  /// error, 0.05 deg/s gyro bias), the same on every map.
  std::string world_json = R"({"shadow_density": 0.05, "leaf_density": 0.02, "noise_sigma": 2.0})";
  std::string odometry_json =
      R"({"scale_error": 0.01, "gyro_bias_deg_s": 0.05, "distance_sigma_m": 0.005, "heading_sigma_deg": 0.1})";
  /// How wrong each campus's map is, m: > 0 renders each seed's world from the map perturbed
  /// (sim/map_error.h: lateral offsets of this standard deviation, correlated over 30 m, widths to
  /// 5 %; seeded by the run's seed + 2) while the vehicle navigates by the map itself, whose
  /// position_sigma_m says this, and judges the run against the world's roads and goal. 0 (the
  /// default): the world is the map. In [0, 10].
  double map_error_m = 0;
  /// Seeds run at once (>= 1). Each run is independent and deterministic: the results do not
  /// depend on it, only the wall time does.
  int threads = 1;
  /// The Map module's options in every run (RunOptions::map; their own table, mapModuleOptionTable).
  MapModuleOptions map;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// SuiteOptions' options (the campus's but its seed, max_frames, world_json, odometry_json, threads);
/// the seeds, the camera and the folder are the caller's.
const OptionTable<SuiteOptions>& suiteOptionTable();

/// What one seed's run came to.
struct SuiteRun {
  std::uint64_t seed = 0;
  std::string junctions;         ///< the spine's junctions in order, "cross T Y"
  bool via = false;              ///< the mission has a via point (out and back along a branch)
  std::string surfaces;          ///< the map's surface family, "concrete/brick" or "asphalt/gravel"
  std::filesystem::path mission; ///< its mission file (SuiteOptions::folder/seed-N/mission.json)
  std::string pipeline;          ///< the pipeline its route's surfaces called for
  double route_m = 0;            ///< the route's length as planned
  std::string outcome;           ///< the runner's one line, or "error: ..." when the run threw
  bool error = false;            ///< the run threw (outcome says what)
  bool reached = false;          ///< the Navigator arrived and the truth is within kSuiteGoalToleranceM
  bool stopped_early = false;    ///< max_frames ended it
  MissionMetrics metrics;
  /// runToJson of the run (what `mapnav run --json` prints) without its wall-clock figures
  /// (latency_ms_*, vision_ms_median); "" when the run threw.
  std::string run_json;
  double wall_s = 0;             ///< the run's wall time (the only figure that varies between runs)
};

/// The runs summed up; medians by nearest rank (metrics.h percentile).
struct SuiteSummary {
  std::size_t runs = 0;
  std::size_t reached = 0;              ///< within kSuiteGoalToleranceM
  std::size_t on_path = 0;              ///< runs with 0 frames off the path
  std::size_t consistent = 0;           ///< runs with >= 90 % of frames within 2 sigma on every axis
  double lateral_rms_median_m = 0, along_max_median_m = 0, heading_rms_median_deg = 0;
  double goal_distance_median_m = 0;
  /// Over the frames of all runs (weighted by frames): the fraction within 2 sigma, per axis.
  double within_2sigma_along = 0, within_2sigma_lateral = 0, within_2sigma_heading = 0;
  double nees_median = 0;               ///< the median of the runs' mean NEES
  std::size_t frames = 0, vision_failures = 0, replans = 0, left_path_frames = 0, errors = 0;
  double wall_s = 0;                    ///< summed over the runs
};

/// "1-30", "7", "1,4,9-12": the seeds in the order given (each once, first occurrence). Throws
/// InvalidInput saying what is wrong with `text` (not a number, a range whose first seed is above
/// its last, empty).
std::vector<std::uint64_t> parseSeedList(std::string_view text);

/// One seed: makes its campus, writes its map and mission to `options.folder`/seed-N, runs it closed
/// loop (the pipelines must be registered) and returns what came of it. A run that throws is a run
/// with `error` set, not an exception; bad options and an unwritable folder throw.
SuiteRun runSuiteSeed(std::uint64_t seed, const SuiteOptions& options);

/// Every seed of `options`, `options.threads` at a time; `done` is called with each run in the
/// order of the seeds, on the calling thread, as soon as it and those before it are done.
std::vector<SuiteRun> runSuite(const SuiteOptions& options, const std::function<void(const SuiteRun&)>& done = {});

/// One run as a one-line JSON record holding every field that the rows, the summary and suiteJson
/// read (numbers at full precision), and back: what a run done elsewhere sends home (the Python
/// module's mapnav.distributed runs each seed as a task). suiteRunFromJson(suiteRunToJson(r)) gives
/// the same rows, summary and suiteJson as r. suiteRunFromJson throws InvalidInput naming what is
/// missing or wrong in `text`.
std::string suiteRunToJson(const SuiteRun& run);
SuiteRun suiteRunFromJson(std::string_view text);

SuiteSummary summarizeSuite(const std::vector<SuiteRun>& runs);

/// The table's header line and one run's row (with the wall time when `wall_time`).
std::string suiteHeaderText(bool wall_time);
std::string suiteRowText(const SuiteRun& run, bool wall_time);
/// The summary, each figure beside its target.
std::string suiteSummaryText(const SuiteSummary& summary, bool wall_time);
/// {"suite","junctions","max_frames","goal_tolerance_m","runs":[{"seed","junctions","via","surfaces",
/// "error","outcome","reached","stopped_early","run":{run_json}|null},...],"summary":{...,"targets":{...}}};
/// one line. Wall times only when `wall_time` (the rest is the same bytes for the same seeds).
std::string suiteJson(const SuiteOptions& options, const std::vector<SuiteRun>& runs, const SuiteSummary& summary,
                      bool wall_time);

}  // namespace mapnav
