// The random-campus suite (mission_sim/suite.h) a seed at a time, for mapnav.distributed: one seed's
// run as its record (suiteRunToJson), and records gathered into what `mapnav suite random-campus`
// prints. The seed list is read as the CLI reads it.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "convert.h"
#include "mapnav/core/error.h"
#include "mapnav/mission_sim/suite.h"

namespace mapnav::python {

namespace {

namespace fs = std::filesystem;

// SuiteOptions from a dict of its table's fields (junctions, max_frames, map_error_m, ...: `mapnav
// options SuiteOptions`) and the Map module's options; the seeds, camera and folder are given.
SuiteOptions suiteOptions(const py::object& options, const py::object& map_options, std::vector<std::uint64_t> seeds,
                          const std::string& camera, const std::string& folder) {
  SuiteOptions base;
  base.seeds = std::move(seeds);
  base.camera = camera;
  base.folder = folder;
  SuiteOptions o = options.is_none() ? base : suiteOptionTable().parse(optionsText(options), base, "options");
  if (!map_options.is_none()) o.map = mapModuleOptionTable().parse(optionsText(map_options), {}, "map_options");
  o.validate();
  return o;
}

std::string suiteSeed(std::uint64_t seed, const std::string& folder, const std::string& camera,
                      const py::object& options, const py::object& map_options) {
  const SuiteOptions o = suiteOptions(options, map_options, {seed}, camera, folder);
  py::gil_scoped_release unlocked;
  return suiteRunToJson(runSuiteSeed(seed, o));
}

std::string suiteReport(const std::vector<std::string>& records, const py::object& options,
                        const py::object& map_options, bool json, bool wall_time) {
  std::vector<SuiteRun> runs;
  std::vector<std::uint64_t> seeds;
  for (const std::string& record : records) {
    runs.push_back(suiteRunFromJson(record));
    seeds.push_back(runs.back().seed);
  }
  if (runs.empty()) throw InvalidInput("records: empty; give at least one run's record");
  const SuiteOptions o = suiteOptions(options, map_options, seeds, "-", "-");
  const SuiteSummary summary = summarizeSuite(runs);
  if (json) return suiteJson(o, runs, summary, wall_time);
  std::string text = suiteHeaderText(wall_time);
  for (const SuiteRun& r : runs) text += suiteRowText(r, wall_time);
  return text + suiteSummaryText(summary, wall_time);
}

}  // namespace

void bindSuite(py::module_& m) {
  m.def("parse_seed_list", &parseSeedList, py::arg("text"),
        "\"1-30\", \"7\", \"1,4,9-12\": the seeds in the order given, each once (as `mapnav suite --seeds`);\n"
        "InvalidInput says what is wrong (a range that runs backwards, not a number, empty).");
  m.def("_suite_seed", &suiteSeed, py::arg("seed"), py::arg("folder"), py::arg("camera"),
        py::arg("options") = py::none(), py::arg("map_options") = py::none(),
        "For mapnav.distributed: one seed of `mapnav suite random-campus`, its map and mission written to\n"
        "FOLDER/seed-N/, run closed loop; its record (JSON text).");
  m.def("_suite_report", &suiteReport, py::arg("records"), py::arg("options") = py::none(),
        py::arg("map_options") = py::none(), py::arg("json") = true, py::arg("wall_time") = false,
        "For mapnav.distributed: the records of _suite_seed, in the suite's order, as `mapnav suite\n"
        "random-campus` prints them (--json: its one line; else the table and the summary).");
}

}  // namespace mapnav::python
