#include "log_command.h"

#include <cmath>
#include <ostream>
#include <sstream>

#include "cli.h"
#include "command_support.h"
#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/image/png.h"
#include "mapnav/sim/replay_log.h"

namespace mapnav::cli {

namespace {

struct LogSummary {
  std::size_t frames = 0;
  double duration_s = 0.0;
  std::optional<double> mean_rate_hz;  ///< nothing with fewer than 2 frames
  double odometry_distance_m = 0.0;    ///< the sum of every frame's distance_m
  std::size_t with_truth = 0, with_gnss = 0, with_mask = 0;
};

LogSummary summarize(const ReplayLog& log) {
  LogSummary s;
  const auto& frames = log.frames();
  s.frames = frames.size();
  if (frames.size() >= 2) {
    s.duration_s = frames.back().t - frames.front().t;
    if (s.duration_s > 0.0) s.mean_rate_hz = static_cast<double>(frames.size() - 1) / s.duration_s;
  }
  for (const LogFrame& f : frames) {
    s.odometry_distance_m += f.odometry.distance_m;
    s.with_truth += f.truth ? 1 : 0;
    s.with_gnss += f.gnss ? 1 : 0;
    s.with_mask += f.mask ? 1 : 0;
  }
  return s;
}

std::string presence(std::size_t count, std::size_t frames) {
  if (count == 0) return "no";
  if (count == frames) return "yes (every frame)";
  return "partly (" + std::to_string(count) + " of " + std::to_string(frames) + " frames)";
}

/// Blends road pixels 40 % towards magenta and draws the road's outline (road pixels with a
/// non-road 4-neighbour) in magenta.
Image overlayMask(const Image& frame, const Image& mask) {
  Image rgb = toRgb(frame);
  auto road = [&](int x, int y) { return mask.pixel(x, y)[0] >= 128; };
  constexpr std::uint8_t kMagenta[3] = {255, 0, 255};
  for (int y = 0; y < frame.height; ++y) {
    for (int x = 0; x < frame.width; ++x) {
      if (!road(x, y)) continue;
      const bool edge = (x > 0 && !road(x - 1, y)) || (x + 1 < frame.width && !road(x + 1, y)) ||
                        (y > 0 && !road(x, y - 1)) || (y + 1 < frame.height && !road(x, y + 1));
      std::uint8_t* q = rgb.pixel(x, y);
      for (int c = 0; c < 3; ++c) {
        q[c] = edge ? kMagenta[c] : static_cast<std::uint8_t>(std::lround(0.6 * q[c] + 0.4 * kMagenta[c]));
      }
    }
  }
  return rgb;
}

}  // namespace

int runLogInfo(const LogInfoConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    const ReplayLog log = ReplayLog::open(config.dir);
    const LogSummary s = summarize(log);
    const LogHeader& h = log.header();
    const std::string model(toString(h.camera->model()));
    if (config.json) {
      Json doc = Json::object();
      doc["dir"] = config.dir;
      doc["name"] = h.name;
      doc["frames"] = s.frames;
      doc["duration_s"] = s.duration_s;
      doc["mean_frame_rate_hz"] = s.mean_rate_hz ? Json(*s.mean_rate_hz) : Json(nullptr);
      doc["frame_rate_hz"] = h.frame_rate_hz;
      doc["odometry_distance_m"] = s.odometry_distance_m;
      doc["frames_with_truth"] = s.with_truth;
      doc["frames_with_gnss"] = s.with_gnss;
      doc["frames_with_mask"] = s.with_mask;
      doc["camera"] = {{"model", model}, {"width", h.camera->width()}, {"height", h.camera->height()}};
      doc["map"] = h.map.empty() ? Json(nullptr) : Json(h.map);
      out << dumpJson(doc);
      return static_cast<int>(kOk);
    }
    std::ostringstream text;
    text.precision(6);
    text << "log:        " << config.dir << (h.name.empty() ? "" : " (" + h.name + ")") << "\n"
         << "frames:     " << s.frames << "\n"
         << "duration:   " << s.duration_s << " s\n"
         << "frame rate: ";
    if (s.mean_rate_hz) {
      text << *s.mean_rate_hz << " Hz mean";
    } else {
      text << "-";
    }
    text << " (nominal " << h.frame_rate_hz << " Hz)\n"
         << "odometry:   " << s.odometry_distance_m << " m driven\n"
         << "truth:      " << presence(s.with_truth, s.frames) << "\n"
         << "gnss:       " << presence(s.with_gnss, s.frames) << "\n"
         << "masks:      " << presence(s.with_mask, s.frames) << "\n"
         << "camera:     " << model << ", " << h.camera->width() << "x" << h.camera->height() << " px\n"
         << "map:        " << (h.map.empty() ? std::string("none") : h.map) << "\n";
    out << text.str();
    return static_cast<int>(kOk);
  });
}

int runLogFrame(const LogFrameConfig& config, std::ostream& out, std::ostream& err) {
  if (config.output.empty()) {
    err << "mapnav: error: log frame: an output PNG is required (-o FILE.png)\n";
    return kUsage;
  }
  return guarded(err, [&] {
    const ReplayLog log = ReplayLog::open(config.dir);
    const std::size_t n = log.frames().size();
    if (config.index >= n) {
      throw InvalidInput("frame " + std::to_string(config.index) + " is out of range: " + config.dir + " has " +
                         std::to_string(n) + " frames" +
                         (n == 0 ? std::string() : " (0 to " + std::to_string(n - 1) + ")"));
    }
    const Image image = log.image(config.index);
    const std::optional<Image> mask = log.mask(config.index);
    if (!mask) {
      writePng(image, config.output);
      err << "mapnav: note: frame " << config.index << " has no ground-truth mask; wrote it without an overlay\n";
    } else {
      if (mask->width != image.width || mask->height != image.height) {
        throw InvalidInput(config.dir + ": frame " + std::to_string(config.index) + ": the mask is " +
                           std::to_string(mask->width) + "x" + std::to_string(mask->height) + " but the image is " +
                           std::to_string(image.width) + "x" + std::to_string(image.height));
      }
      writePng(overlayMask(image, *mask), config.output);
    }
    out << "wrote " << config.output << " (frame " << config.index << ", t = " << log.frames()[config.index].t
        << " s" << (mask ? ", road mask overlaid" : "") << ")\n";
    return static_cast<int>(kOk);
  });
}

int runLogImportKitti(const LogImportKittiConfig& config, std::ostream& out, std::ostream& err) {
  if (config.output.empty()) {
    err << "mapnav: error: log import-kitti: an output folder is required (-o LOGDIR)\n";
    return kUsage;
  }
  return guarded(err, [&] {
    const KittiImportResult r = importKitti(config.dir, config.output, config.options);
    std::ostringstream text;
    text.precision(4);
    text << "wrote " << config.output << ": " << r.frames << " frames (" << r.width << "x" << r.height << ", "
         << (r.channels == 1 ? "grey" : "RGB") << ", from " << r.images.string() << "), " << r.duration_s << " s, "
         << r.distance_m << " m driven; camera from calib.txt " << r.calib_row << ", " << config.options.camera_height_m
         << " m up, tilt " << config.options.camera_tilt_deg << " deg (also in " << config.output
         << "/camera.json); truth and odometry from poses.txt\n";
    out << text.str();
    return static_cast<int>(kOk);
  });
}

}  // namespace mapnav::cli
