#include "log_command.h"

#include <cmath>
#include <ostream>
#include <sstream>

#include "cli.h"
#include "command_line.h"
#include "command_support.h"
#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/image/png.h"
#include "mapnav/logs/replay_log.h"

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

int runLogImportKittiRaw(const LogImportKittiRawConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    KittiRawImportOptions options = config.options;
    if (!config.origin.empty()) {
      const GeoOrigin o = parseOrigin(config.origin, false);
      options.origin = LatLon{o.lat, o.lon};
    }
    const KittiRawImportResult r = importKittiRaw(config.dir, config.output, options);
    const CameraMount& m = r.mount;
    out << strprintf("wrote %s: %zu frames (%dx%d), %.1f s, %.1f m along the OXTS track; world frame east-north about "
                     "%.8f, %.8f; camera %s from the calibration chain: fx %.1f, %.2f m up, tilt %.2f deg, yaw %.2f deg, "
                     "roll %.2f deg, %.2f m ahead of and %.2f m left of the OXTS unit (also in %s/camera.json); %zu GNSS "
                     "fixes (sigma %.2f m); odometry from the OXTS speed and yaw rate%s\n",
                     config.output.c_str(), r.frames, r.intrinsics.width, r.intrinsics.height, r.duration_s, r.distance_m,
                     r.origin.lat, r.origin.lon, options.camera.c_str(), r.intrinsics.fx, m.height_m, radToDeg(m.tilt_rad),
                     radToDeg(m.yaw_rad), radToDeg(m.roll_rad), m.offset.x(), m.offset.y(), config.output.c_str(),
                     r.gnss_fixes, options.gnss.statedSigma(),
                     options.scale_error != 0 || options.gyro_bias_deg_s != 0
                         ? strprintf(", degraded: scale error %g, gyro bias %g deg/s (seed %llu)", options.scale_error,
                                     options.gyro_bias_deg_s, static_cast<unsigned long long>(options.seed)).c_str()
                         : "");
    return static_cast<int>(kOk);
  });
}

// ---- the command line: `mapnav log ...` -------------------------------------------------------

namespace {

void addLogInfo(CLI::App& log, Commands& commands) {
  auto* info = commands.hold<LogInfoConfig>();
  CLI::App* li = log.add_subcommand("info", "Summarise a log: frames, duration, distance, camera, ground truth");
  li->add_option("dir", info->dir, "Log folder")->required()->check(CLI::ExistingDirectory);
  li->add_flag("--json", info->json, "Print one JSON object");
  li->callback(commands.choose([info](std::ostream& out, std::ostream& err) { return runLogInfo(*info, out, err); }));
}

void addLogFrame(CLI::App& log, Commands& commands) {
  auto* frame = commands.hold<LogFrameConfig>();
  CLI::App* lf = log.add_subcommand("frame", "Write frame N with its ground-truth road mask overlaid");
  lf->add_option("dir", frame->dir, "Log folder")->required()->check(CLI::ExistingDirectory);
  lf->add_option("index", frame->index, "Frame number, from 0")->required();
  lf->add_option("-o,--output", frame->output, "PNG to write")->required();
  lf->callback(commands.choose([frame](std::ostream& out, std::ostream& err) { return runLogFrame(*frame, out, err); }));
}

void addLogImportKitti(CLI::App& log, Commands& commands) {
  auto* kitti = commands.hold<LogImportKittiConfig>();
  CLI::App* lk = log.add_subcommand("import-kitti", "Turn a KITTI odometry sequence (images, poses.txt, calib.txt) into a log with truth (docs/kitti.md)");
  lk->add_option("dir", kitti->dir, "KITTI sequence folder")->required()->check(CLI::ExistingDirectory);
  lk->add_option("-o,--output", kitti->output, "Log folder to write (must not exist, or be empty)")->required();
  lk->add_option("--camera-height", kitti->options.camera_height_m, "Camera height above the road, m")->capture_default_str();
  lk->add_option("--camera-tilt", kitti->options.camera_tilt_deg, "Camera pitch below the horizon, degrees")->capture_default_str();
  lk->add_option("--frame-rate", kitti->options.frame_rate_hz, "Frame rate when there is no times.txt, Hz")->capture_default_str();
  lk->add_option("--images", kitti->options.images, "Image folder inside the sequence (default: the first image_* folder)");
  lk->add_option("--name", kitti->options.name, "The log's name (default: KITTI and the folder's name)");
  lk->footer("Exit codes: 0 written, 1 invalid input (a malformed poses.txt line, fewer poses than images; the file and "
             "line are named and nothing is written), 2 usage or I/O error (a missing poses.txt or calib.txt).");
  lk->callback(commands.choose([kitti](std::ostream& out, std::ostream& err) { return runLogImportKitti(*kitti, out, err); }));
}

void addLogImportKittiRaw(CLI::App& log, Commands& commands) {
  auto* raw = commands.hold<LogImportKittiRawConfig>();
  CLI::App* lr = log.add_subcommand(
      "import-kitti-raw", "Turn a KITTI raw drive (camera frames, OXTS GPS/IMU packets, calibration) into a log with "
                          "truth, GNSS fixes and odometry (docs/real-drive.md)");
  lr->add_option("dir", raw->dir, "Drive folder, DATE/DATE_drive_NNNN_sync (the calibration files are read from DATE/)")
      ->required()
      ->check(CLI::ExistingDirectory);
  lr->add_option("-o,--output", raw->output, "Log folder to write (must not exist, or be empty)")->required();
  lr->add_option("--camera", raw->options.camera, "The camera: image_NN and P_rect_NN (02: the left colour camera)")
      ->capture_default_str();
  lr->add_option("--origin", raw->origin, "The world frame's origin LAT,LON, degrees (default: the first OXTS fix; use "
                                          "the map's origin to replay on a map)");
  lr->add_option("--imu-height", raw->options.imu_height_m, "The OXTS unit's height above the road, m (KITTI's set-up drawing)")
      ->capture_default_str();
  lr->add_option("--gnss-every", raw->options.gnss_every, "A GNSS fix every n-th frame (0 = none)")->capture_default_str();
  lr->add_option("--gnss-sigma", raw->options.gnss.sigma_m,
                 "The fixes' white noise, 1-sigma per axis, m (the fixes are the OXTS positions as a consumer receiver "
                 "would give them, never the truth itself)")
      ->capture_default_str()
      ->check(commands.ruleCheck(kittiRawImportOptionTable(), "gnss_sigma_m"));
  lr->add_option("--gnss-bias-sigma", raw->options.gnss.bias_sigma_m,
                 "The fixes' slowly drifting bias, steady 1-sigma per axis, m")
      ->capture_default_str()
      ->check(commands.ruleCheck(kittiRawImportOptionTable(), "gnss_bias_sigma_m"));
  lr->add_option("--gnss-bias-time", raw->options.gnss.bias_time_s, "The bias's correlation time, s")
      ->capture_default_str()
      ->check(commands.ruleCheck(kittiRawImportOptionTable(), "gnss_bias_time_s"));
  lr->add_option("--odometry-scale-error", raw->options.scale_error, "Degrade the odometry: relative distance error (0.02 = 2 % long)")
      ->capture_default_str();
  lr->add_option("--gyro-bias-deg-s", raw->options.gyro_bias_deg_s, "Degrade the odometry: constant yaw-rate bias, deg/s")
      ->capture_default_str();
  lr->add_option("--seed", raw->options.seed, "Seed of the odometry's degradation (the GNSS errors': seed + 1)")
      ->capture_default_str();
  lr->add_option("--name", raw->options.name, "The log's name (default: KITTI raw and the drive folder's name)");
  lr->add_flag("--grey", raw->options.grey,
               "The frames as a grey camera gives them: luminance 0.299 R + 0.587 G + 0.114 B in every channel (to "
               "measure the pipelines on a grey camera with a colour camera's drive)");
  lr->footer("Exit codes: 0 written, 1 invalid input (a malformed OXTS packet, calibration entry or timestamp: the file "
             "and line are named and nothing is written), 2 usage or I/O error (a missing folder or file).");
  lr->callback(commands.choose([raw](std::ostream& out, std::ostream& err) { return runLogImportKittiRaw(*raw, out, err); }));
}

}  // namespace

void registerLogCommands(CLI::App& app, Commands& commands) {
  CLI::App* log = app.add_subcommand("log", "Inspect replay logs (docs/replay-log-format.md)");
  log->require_subcommand(1);
  addLogInfo(*log, commands);
  addLogFrame(*log, commands);
  addLogImportKitti(*log, commands);
  addLogImportKittiRaw(*log, commands);
  registerTrackCommand(*log, commands);
}

}  // namespace mapnav::cli
