#include "mapnav/logs/kitti_import.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <optional>
#include <vector>

#include "mapnav/core/error.h"
#include "kitti_text.h"
#include "mapnav/core/io.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/image/png.h"
#include "mapnav/logs/replay_log.h"

namespace mapnav {

namespace fs = std::filesystem;

namespace {

using kitti::badLine;

/// One non-blank line of a whitespace-separated number file, with its 1-based line number.
struct NumberLine {
  int line = 0;
  std::string label;  ///< a leading "NAME:" (calib.txt's "P0:"), else ""
  std::vector<double> values;
};

/// Every non-blank line of `file` as numbers; a token that is not a finite number is
/// `kitti.number` naming the line.
std::vector<NumberLine> readNumberLines(const fs::path& file) {
  const std::string text = readFile(file);
  std::vector<NumberLine> lines;
  std::istringstream in(text);
  int number = 0;
  for (std::string row; std::getline(in, row);) {
    ++number;
    std::istringstream tokens(row);
    NumberLine l;
    l.line = number;
    for (std::string token; tokens >> token;) {
      if (l.values.empty() && l.label.empty() && token.back() == ':') {
        l.label = token.substr(0, token.size() - 1);
        continue;
      }
      const std::optional<double> v = kitti::finiteNumber(token);
      if (!v) {
        badLine(file, number, "kitti.number",
                "value " + std::to_string(l.values.size() + 1) + " \"" + token + "\" is not a finite number");
      }
      l.values.push_back(*v);
    }
    if (!l.values.empty() || !l.label.empty()) lines.push_back(std::move(l));
  }
  return lines;
}

void expectTwelve(const fs::path& file, const NumberLine& l, const std::string& what) {
  if (l.values.size() != 12)
    badLine(file, l.line, "kitti.count",
            "expected 12 numbers (" + what + "), got " + std::to_string(l.values.size()));
}

fs::path findImages(const fs::path& dir, const std::string& option) {
  if (!option.empty()) {
    const fs::path p = dir / option;
    if (!fs::is_directory(p)) throw IoError(p.string() + ": no such image folder");
    return p;
  }
  std::vector<fs::path> found;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    if (e.is_directory() && e.path().filename().string().rfind("image_", 0) == 0) found.push_back(e.path());
  }
  if (found.empty()) throw IoError(dir.string() + ": no image folder (image_0, image_2, ...)");
  std::sort(found.begin(), found.end());
  return found.front();
}

/// The projection matrix of an image folder: image_N → PN, anything else P0.
std::string calibRowFor(const fs::path& images) {
  const std::string name = images.filename().string();
  if (name.size() == 7 && name.rfind("image_", 0) == 0 && std::isdigit(static_cast<unsigned char>(name[6])))
    return std::string("P") + name[6];
  return "P0";
}

/// fx, fy, cx, cy of projection matrix `row` of calib.txt: the line labelled "P2:", or, when the
/// lines carry no labels, the Nth line (P0 the first).
CameraIntrinsics readCalib(const fs::path& file, const std::string& row) {
  const std::vector<NumberLine> lines = readNumberLines(file);
  const NumberLine* p = nullptr;
  for (const NumberLine& l : lines)
    if (l.label == row) p = &l;
  const std::size_t index = static_cast<std::size_t>(row[1] - '0');
  if (p == nullptr && index < lines.size() && lines[index].label.empty()) p = &lines[index];
  if (p == nullptr) throw InvalidInput(file.string() + ": no projection matrix " + row);
  expectTwelve(file, *p, "the 3x4 projection matrix " + row + ", row-major");
  const std::vector<double>& v = p->values;
  if (!(v[0] > 0) || !(v[5] > 0))
    badLine(file, p->line, "kitti.calib", row + ": the focal lengths (values 1 and 6) must be > 0");
  CameraIntrinsics in;
  in.fx = v[0];
  in.fy = v[5];
  in.cx = v[2];
  in.cy = v[6];
  return in;
}

std::vector<fs::path> listPngs(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".png") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InvalidInput(dir.string() + ": no .png images in the folder");
  return files;
}

}  // namespace

const OptionTable<KittiImportOptions>& kittiImportOptionTable() {
  using O = KittiImportOptions;
  static const OptionTable<O> table =
      OptionTable<O>("KittiImportOptions")
          .field("camera_height_m", &O::camera_height_m, above(0), "the optical centre's height above the road, m")
          .field("camera_tilt_deg", &O::camera_tilt_deg, inRange(-90, 90), "the optical axis' angle below the horizon, degrees")
          .field("frame_rate_hz", &O::frame_rate_hz, above(0), "frame rate without times.txt, and the log's nominal rate, Hz")
          .field("images", &O::images, "the image folder inside the sequence (\"\": the first image_*)")
          .field("name", &O::name, "the log's name (\"\": \"KITTI \" and the sequence folder's name)");
  return table;
}

void KittiImportOptions::validate() const { kittiImportOptionTable().validate(*this); }

Pose2 kittiGroundPose(const double (&m)[12]) {
  // The optical axis (R's third column) in KITTI's world: (m[2], m[6], m[10]); on the ground plane
  // (KITTI x, z) it points to mapnav (z, -x).
  return Pose2(m[11], -m[3], std::atan2(-m[2], m[10]));
}

KittiImportResult importKitti(const fs::path& dir, const fs::path& out, const KittiImportOptions& options) {
  options.validate();
  if (!fs::is_directory(dir)) throw IoError(dir.string() + ": no such sequence folder");
  KittiImportResult result;
  result.images = findImages(dir, options.images);
  result.calib_row = calibRowFor(result.images);
  const std::vector<fs::path> images = listPngs(result.images);

  // Everything is read and checked before the log is started.
  const fs::path poses_file = dir / "poses.txt";
  const std::vector<NumberLine> pose_lines = readNumberLines(poses_file);
  std::vector<Pose2> truth;
  for (const NumberLine& l : pose_lines) {
    expectTwelve(poses_file, l, "a 3x4 camera-to-world matrix, row-major");
    double m[12];
    std::copy(l.values.begin(), l.values.end(), m);
    // R must be a rotation: RᵀR = I (KITTI prints 7 significant digits).
    double worst = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double dot = 0;
        for (int k = 0; k < 3; ++k) dot += m[4 * k + i] * m[4 * k + j];
        worst = std::max(worst, std::abs(dot - (i == j ? 1.0 : 0.0)));
      }
    if (worst > 1e-3) badLine(poses_file, l.line, "kitti.rotation", "the matrix's left 3x3 is not a rotation");
    if (std::hypot(m[2], m[10]) < 1e-3)
      badLine(poses_file, l.line, "kitti.rotation", "the camera looks straight up or down: no heading on the ground");
    truth.push_back(kittiGroundPose(m));
  }
  if (truth.size() != images.size()) {
    const int line = truth.size() > images.size() ? pose_lines[images.size()].line
                                                  : (pose_lines.empty() ? 1 : pose_lines.back().line + 1);
    badLine(poses_file, line, "kitti.count",
            std::to_string(truth.size()) + " poses for " + std::to_string(images.size()) + " images in " +
                result.images.string() + ": expected one pose line per image");
  }

  std::vector<double> times;
  const fs::path times_file = dir / "times.txt";
  if (fs::exists(times_file)) {
    const std::vector<NumberLine> lines = readNumberLines(times_file);
    for (const NumberLine& l : lines) {
      if (l.values.size() != 1) badLine(times_file, l.line, "kitti.count", "expected one time, s");
      if (!times.empty() && !(l.values[0] > times.back()))
        badLine(times_file, l.line, "kitti.time_order", "the time is not after the previous line's");
      times.push_back(l.values[0]);
    }
    if (times.size() != images.size())
      badLine(times_file, lines.empty() ? 1 : lines.back().line, "kitti.count",
              std::to_string(times.size()) + " times for " + std::to_string(images.size()) + " images");
  } else {
    for (std::size_t i = 0; i < images.size(); ++i) times.push_back(static_cast<double>(i) / options.frame_rate_hz);
  }

  const Image first = readPng(images.front());
  CameraIntrinsics in = readCalib(dir / "calib.txt", result.calib_row);
  in.width = first.width;
  in.height = first.height;
  CameraMount mount;
  mount.height_m = options.camera_height_m;
  mount.tilt_rad = degToRad(options.camera_tilt_deg);
  LogHeader header;
  header.name = options.name;
  if (header.name.empty()) {
    fs::path d = fs::absolute(dir).lexically_normal();
    if (d.filename().empty()) d = d.parent_path();
    header.name = "KITTI " + d.filename().string();
  }
  header.camera = createCamera(LensModel::Pinhole, in, mount);
  header.frame_rate_hz = options.frame_rate_hz;

  ReplayLogWriter writer(out, header);
  for (std::size_t i = 0; i < images.size(); ++i) {
    const Image image = i == 0 ? first : readPng(images[i]);
    if (image.width != first.width || image.height != first.height)
      throw InvalidInput(images[i].string() + ": the image is " + std::to_string(image.width) + "x" +
                         std::to_string(image.height) + " but the first is " + std::to_string(first.width) + "x" +
                         std::to_string(first.height));
    LogFrame f;
    f.t = times[i];
    f.truth = truth[i];
    if (i > 0) {
      const Pose2& a = truth[i - 1];
      const Pose2& b = truth[i];
      f.odometry.dheading_rad = normalizeAngle(b.heading() - a.heading());
      // The chord, negative when it points backwards from the mid-step heading.
      const Vec2 step = b.translation() - a.translation();
      const double mid = a.heading() + 0.5 * f.odometry.dheading_rad;
      const double along = step.dot(Vec2(std::cos(mid), std::sin(mid)));
      f.odometry.distance_m = along < 0 ? -step.norm() : step.norm();
    }
    writer.add(f, image);
    result.distance_m += f.odometry.distance_m;
  }
  writeFileAtomic(writer.partialDir() / "camera.json", cameraToJson(*header.camera, header.name));
  writer.finish();
  result.frames = images.size();
  result.duration_s = times.back() - times.front();
  result.width = first.width;
  result.height = first.height;
  result.channels = first.channels;
  return result;
}

}  // namespace mapnav
