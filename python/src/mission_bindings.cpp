// Replay logs (frames, truth, odometry) and missions (replay, closed loop) with their metrics.

#include <cmath>
#include <optional>
#include <tuple>

#include "convert.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/mission/mission_file.h"
#include "mapnav/mission/modules.h"
#include "mapnav/mission/runner.h"
#include "mapnav/mission_sim/closed_loop.h"

namespace mapnav::python {

namespace {

using namespace pybind11::literals;

py::object frameDict(const LogFrame& f) {
  py::dict d("t"_a = f.t, "image"_a = f.image, "mask"_a = f.mask,
             "odometry"_a = py::make_tuple(f.odometry.distance_m, f.odometry.dheading_rad));
  d["truth"] = f.truth ? py::object(fromPose(*f.truth)) : py::object(py::none());
  d["gnss"] = f.gnss ? py::object(py::make_tuple(f.gnss->position.x(), f.gnss->position.y(), f.gnss->sigma_m))
                     : py::object(py::none());
  return d;
}

// One row per frame of `columns` numbers, NaN where the frame has none.
template <typename Row>
py::array perFrame(const ReplayLog& log, py::ssize_t columns, Row row) {
  const auto n = static_cast<py::ssize_t>(log.frames().size());
  py::array_t<double> out({n, columns});
  auto o = out.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const std::vector<double> values = row(log.frames()[static_cast<std::size_t>(i)]);
    for (py::ssize_t c = 0; c < columns; ++c) o(i, c) = values.empty() ? std::nan("") : values[static_cast<std::size_t>(c)];
  }
  return out;
}

void bindReplayLog(py::module_& m) {
  py::class_<ReplayLog>(m, "ReplayLog", "A replay log folder (docs/replay-log-format.md); images read on demand.")
      .def_static(
          "open",
          [](const std::string& dir, bool skip_bad_frames) {
            ReadOptions options;
            options.skip_bad_frames = skip_bad_frames;
            return ReplayLog::open(dir, options);
          },
          py::arg("dir"), py::arg("skip_bad_frames") = false,
          "Reads log.json and frames.jsonl; ValidationError names the file and line of a bad frame.")
      .def_property_readonly("name", [](const ReplayLog& l) { return l.header().name; })
      .def_property_readonly("camera", [](const ReplayLog& l) { return std::const_pointer_cast<Camera>(l.header().camera); })
      .def_property_readonly("frame_rate_hz", [](const ReplayLog& l) { return l.header().frame_rate_hz; })
      .def_property_readonly("map", [](const ReplayLog& l) {
        const auto path = l.mapPath();
        return path ? py::object(py::str(path->string())) : py::object(py::none());
      })
      .def_property_readonly("skipped", &ReplayLog::skipped)
      .def_property_readonly("issues", &ReplayLog::issues)
      .def("__len__", [](const ReplayLog& l) { return l.frames().size(); })
      .def_property_readonly("frames", [](const ReplayLog& l) {
        py::list out;
        for (const LogFrame& f : l.frames()) out.append(frameDict(f));
        return out;
      }, "One dict per frame: t, image, mask, odometry (distance_m, dheading_rad), truth (x, y, heading_rad) or None, gnss.")
      .def_property_readonly("times", [](const ReplayLog& l) {
        return perFrame(l, 1, [](const LogFrame& f) { return std::vector<double>{f.t}; }).attr("reshape")(-1);
      }, "N, s")
      .def_property_readonly("odometry", [](const ReplayLog& l) {
        return perFrame(l, 2, [](const LogFrame& f) { return std::vector<double>{f.odometry.distance_m, f.odometry.dheading_rad}; });
      }, "N x 2: distance_m and dheading_rad since the previous frame")
      .def_property_readonly("truth", [](const ReplayLog& l) {
        return perFrame(l, 3, [](const LogFrame& f) {
          return f.truth ? std::vector<double>{f.truth->x(), f.truth->y(), f.truth->heading()} : std::vector<double>{};
        });
      }, "N x 3: x, y, heading_rad in the world frame; NaN rows where a frame has no truth")
      .def("image", [](const ReplayLog& l, std::size_t i) { return toArray(l.image(i)); }, py::arg("i"),
           "Frame i's image, H x W x 3 (or H x W) uint8.")
      .def("mask", [](const ReplayLog& l, std::size_t i) {
        const auto mask = l.mask(i);
        return mask ? py::object(toArray(*mask)) : py::object(py::none());
      }, py::arg("i"), "Frame i's ground-truth road mask, H x W uint8, or None.");
}

RunOptions runOptions(const std::optional<std::string>& pipeline, const py::object& options, std::size_t max_frames,
                      const std::optional<std::string>& trace, const py::object& map_options) {
  RunOptions run;
  run.pipeline = pipeline.value_or("");
  if (!options.is_none()) run.pipeline_options_json = optionsText(options);
  if (!map_options.is_none()) run.map = mapModuleOptionTable().parse(optionsText(map_options), {}, "map_options");
  run.max_frames = max_frames;
  run.trace = trace.value_or("");
  return run;
}

void bindRuns(py::module_& m) {
  m.def(
      "replay",
      [](const std::string& mission, const std::string& log, const std::optional<std::string>& pipeline,
         const py::object& options, std::size_t max_frames, const std::optional<std::string>& trace, bool strict,
         const py::object& map_options) {
        RunOptions run = runOptions(pipeline, options, max_frames, trace, map_options);
        run.strict = strict;
        const MissionFile file = loadMission(mission);
        std::string json;
        {
          py::gil_scoped_release unlocked;
          json = runToJson(runReplay(file, log, run));
        }
        return fromJson(json);
      },
      py::arg("mission"), py::arg("log"), py::arg("pipeline") = py::none(), py::arg("options") = py::none(),
      py::arg("max_frames") = 0, py::arg("trace") = py::none(), py::arg("strict") = false,
      py::arg("map_options") = py::none(),
      "A mission in open loop over a replay log: the metrics dict of `mapnav replay --json`. map_options: the\n"
      "Map module's options (dict or JSON text, `mapnav options MapModuleOptions`; as --map-options).");
  // For mapnav.distributed: a replay as the bytes `mapnav replay --json` prints, its summary as
  // `mapnav replay` prints it, and whether its exit code is 0 (the goal reached, or max_frames stopped it).
  m.def(
      "_replay_task",
      [](const std::string& mission, const std::string& log, const std::optional<std::string>& pipeline,
         const py::object& options, std::size_t max_frames, bool strict, const py::object& map_options) {
        RunOptions run = runOptions(pipeline, options, max_frames, std::nullopt, map_options);
        run.strict = strict;
        const MissionFile file = loadMission(mission);
        py::gil_scoped_release unlocked;
        const MissionRun done = runReplay(file, log, run);
        return std::make_tuple(runToJson(done), summaryText(done), done.metrics.reached_goal || done.stopped_early);
      },
      py::arg("mission"), py::arg("log"), py::arg("pipeline") = py::none(), py::arg("options") = py::none(),
      py::arg("max_frames") = 0, py::arg("strict") = false, py::arg("map_options") = py::none());
  m.def(
      "run",
      [](const std::string& mission, const std::optional<std::uint64_t>& seed, const std::optional<std::string>& pipeline,
         const py::object& options, std::size_t max_frames, const std::optional<std::string>& trace,
         const py::object& map_options) {
        RunOptions run = runOptions(pipeline, options, max_frames, trace, map_options);
        run.seed = seed;
        const MissionFile file = loadMission(mission);
        std::string json;
        {
          py::gil_scoped_release unlocked;
          json = runToJson(runClosedLoop(file, run));
        }
        return fromJson(json);
      },
      py::arg("mission"), py::arg("seed") = py::none(), py::arg("pipeline") = py::none(), py::arg("options") = py::none(),
      py::arg("max_frames") = 0, py::arg("trace") = py::none(), py::arg("map_options") = py::none(),
      "A mission in closed loop in the simulator: the metrics dict of `mapnav run --json`.");
}

}  // namespace

void bindMission(py::module_& m) {
  bindReplayLog(m);
  bindRuns(m);
}

}  // namespace mapnav::python
