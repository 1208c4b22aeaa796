#include "bench_pipelines.h"

#include <algorithm>
#include <optional>
#include <ostream>

#include "bench_measure.h"
#include "command_support.h"
#include "json_numbers.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/mission/image_region.h"
#include "mapnav/vision/segmentation_eval.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav::cli {

namespace {

/// `frame` resized to w x h (nearest pixel: a frame to time, not to look at).
Image resized(const Image& frame, int w, int h) {
  Image out(w, h, 3);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const std::uint8_t* p = frame.pixel(u * frame.width / w, v * frame.height / h);
      std::copy(p, p + 3, out.pixel(u, v));
    }
  return out;
}

bool hasThreadsOption(const PipelineInfo& info) {
  return std::any_of(info.options.begin(), info.options.end(), [](const OptionInfo& o) { return o.name == "threads"; });
}

/// The time over sidewalk's at the same size on one thread; none when sidewalk was not timed there.
std::optional<double> ratioToSidewalk(const std::vector<PipelineTime>& times, const PipelineTime& t) {
  for (const PipelineTime& s : times)
    if (s.pipeline == "sidewalk" && s.width == t.width && s.height == t.height && s.threads == 1) return t.ms / s.ms;
  return std::nullopt;
}

}  // namespace

std::vector<PipelineTime> timePipelines(const SidewalkScene& scene, int threads, double min_time_s,
                                        const std::optional<std::vector<std::string>>& names) {
  std::vector<PipelineInfo> infos;
  for (const PipelineInfo& info : listPipelines()) {
    const bool wanted = names ? std::find(names->begin(), names->end(), info.name) != names->end()
                              : info.name.rfind("example-", 0) != 0;
    if (wanted) infos.push_back(info);
  }
  if (names)
    for (const std::string& name : *names)
      if (std::none_of(infos.begin(), infos.end(), [&](const PipelineInfo& i) { return i.name == name; }))
        createPipeline(name, "{}");  // throws NotFound naming the pipelines there are
  std::vector<PipelineTime> out;
  for (const auto& [w, h] : {std::pair{480, 360}, std::pair{512, 480}}) {
    std::vector<Image> frames;
    for (const Frame& f : scene.frames) frames.push_back(resized(f.rgb, w, h));
    const std::unique_ptr<Camera> camera = assumedPhotoCamera(w, h);
    const PredictedObject prediction = predictionFromImageRegion(bottomTrapezoid(w, h), *camera).view;
    for (const PipelineInfo& info : infos) {
      std::vector<int> counts{1};
      if (hasThreadsOption(info) && threads > 1) counts.push_back(threads);
      for (const int n : counts) {
        auto pipeline = createPipeline(info.name, hasThreadsOption(info) ? strprintf(R"({"threads": %d})", n) : "{}");
        std::size_t k = 0;
        const Measured m = measure(
            [&] {
              const Image& rgb = frames[k++ % frames.size()];
              const DetectedObject d =
                  pipeline->detect(VisionFrame{w, h, rgb.data.data(), camera.get(), static_cast<double>(k), false}, prediction);
              keep(d.confidence);
            },
            min_time_s);
        out.push_back({info.name, w, h, n, 1e3 * m.s_per_frame});
      }
    }
  }
  return out;
}

void printPipelineTimes(const std::vector<PipelineTime>& times, std::ostream& out) {
  out << "vision pipelines: detect() per frame (the sidewalk scene's frames, a bottom trapezoid as the prediction), "
         "x sidewalk = time / sidewalk's at the same size on one thread (one run)\n";
  out << pad("size", 10) << pad("pipeline", 22) << pad("threads", 9) << pad("ms/frame", 12) << pad("x sidewalk", 12) << "\n";
  for (const PipelineTime& t : times)
    out << pad(strprintf("%dx%d", t.width, t.height), 10) << pad(t.pipeline, 22) << pad(std::to_string(t.threads), 9)
        << pad(sig(t.ms), 12) << pad(fixedOr(ratioToSidewalk(times, t), 2, "-"), 12) << "\n";
}

Json pipelineTimesJson(const std::vector<PipelineTime>& times) {
  Json rows = Json::array();
  for (const PipelineTime& t : times)
    rows.push_back({{"pipeline", t.pipeline},
                    {"width", t.width},
                    {"height", t.height},
                    {"threads", t.threads},
                    {"ms", roundedOrNull(t.ms, 3)},
                    {"sidewalk_ratio", roundedOrNull(ratioToSidewalk(times, t), 3)}});
  return rows;
}

}  // namespace mapnav::cli
