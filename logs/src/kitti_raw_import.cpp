// KITTI raw drives as replay logs (kitti_raw_import.h; docs/real-drive.md).
#include "mapnav/logs/kitti_raw_import.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "mapnav/core/error.h"
#include "kitti_text.h"
#include "mapnav/core/io.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/image/png.h"
#include "mapnav/logs/odometry.h"
#include "mapnav/logs/replay_log.h"

namespace mapnav {

namespace fs = std::filesystem;

namespace {

using kitti::badLine;

using kitti::finiteNumber;

/// A calibration file's "KEY: v v v" lines (a key whose values are not all numbers, e.g.
/// calib_time, keeps no values and is only an error when it is asked for).
struct Keyed {
  int line = 0;
  bool numeric = true;
  std::vector<double> values;
};

std::map<std::string, Keyed> readKeyed(const fs::path& file) {
  std::map<std::string, Keyed> out;
  std::istringstream in(readFile(file));
  int n = 0;
  for (std::string row; std::getline(in, row);) {
    ++n;
    const std::size_t colon = row.find(':');
    if (colon == std::string::npos) continue;
    Keyed k;
    k.line = n;
    std::istringstream tokens(row.substr(colon + 1));
    for (std::string t; tokens >> t;) {
      const auto v = finiteNumber(t);
      if (!v) k.numeric = false;
      else k.values.push_back(*v);
    }
    out[row.substr(0, colon)] = k;
  }
  return out;
}

const std::vector<double>& need(const std::map<std::string, Keyed>& keyed, const fs::path& file, const std::string& key,
                                std::size_t count) {
  const auto it = keyed.find(key);
  if (it == keyed.end()) badLine(file, 1, "kitti.calib", "no " + key + " (expected \"" + key + ": \" and " + std::to_string(count) + " numbers)");
  if (!it->second.numeric || it->second.values.size() != count)
    badLine(file, it->second.line, "kitti.calib", key + ": expected " + std::to_string(count) + " numbers");
  return it->second.values;
}

Mat3 rowMajor3(const std::vector<double>& v, std::size_t first = 0, std::size_t stride = 3) {
  Mat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = v[first + static_cast<std::size_t>(r) * stride + static_cast<std::size_t>(c)];
  return m;
}

/// One OXTS packet: the fields the import uses (oxts/dataformat.txt).
struct Oxts {
  double lat = 0, lon = 0, yaw = 0, vf = 0, wu = 0, pos_accuracy = 0;
};

Oxts readOxts(const fs::path& file) {
  std::istringstream in(readFile(file));
  std::vector<double> v;
  for (std::string t; in >> t;) {
    const auto x = finiteNumber(t);
    if (!x) badLine(file, 1, "kitti.number", "value " + std::to_string(v.size() + 1) + " \"" + t + "\" is not a finite number");
    v.push_back(*x);
  }
  if (v.size() != 30) badLine(file, 1, "kitti.count", "expected the 30 OXTS fields, got " + std::to_string(v.size()));
  if (std::abs(v[0]) > 90 || std::abs(v[1]) > 180) badLine(file, 1, "kitti.range", "latitude or longitude out of range");
  return {v[0], v[1], v[5], v[8], v[22], v[23]};
}

std::vector<double> readTimes(const fs::path& file) {
  std::vector<double> out;
  std::istringstream in(readFile(file));
  int n = 0;
  for (std::string row; std::getline(in, row);) {
    ++n;
    if (row.find_first_not_of(" \t\r") == std::string::npos) continue;
    const auto t = kittiTimeOfDay(row);
    if (!t) badLine(file, n, "kitti.time", "\"" + row + "\" is not a time YYYY-MM-DD HH:MM:SS.fraction");
    if (!out.empty() && !(*t > out.back())) badLine(file, n, "kitti.time_order", "the time is not after the previous line's");
    out.push_back(*t);
  }
  return out;
}

std::vector<fs::path> listFiles(const fs::path& dir, const std::string& extension) {
  if (!fs::is_directory(dir)) throw IoError(dir.string() + ": no such folder");
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == extension) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InvalidInput(dir.string() + ": no " + extension + " files in the folder");
  return files;
}

/// The camera from the calibration chain (header comment), its image `width` x `height`.
std::pair<CameraIntrinsics, CameraMount> cameraFromCalibration(const fs::path& date_dir, const std::string& camera,
                                                               double imu_height_m, int width, int height) {
  const fs::path cam_file = date_dir / "calib_cam_to_cam.txt", imu_file = date_dir / "calib_imu_to_velo.txt",
                 velo_file = date_dir / "calib_velo_to_cam.txt";
  const auto cam = readKeyed(cam_file), imu = readKeyed(imu_file), velo = readKeyed(velo_file);
  const std::vector<double>& p = need(cam, cam_file, "P_rect_" + camera, 12);
  const Mat3 k = rowMajor3(p, 0, 4);
  if (!(k(0, 0) > 0) || !(k(1, 1) > 0)) badLine(cam_file, cam.at("P_rect_" + camera).line, "kitti.calib", "P_rect_" + camera + ": focal lengths must be > 0");
  const Mat3 r_rect = rowMajor3(need(cam, cam_file, "R_rect_00", 9));
  const Mat3 r_iv = rowMajor3(need(imu, imu_file, "R", 9)), r_vc = rowMajor3(need(velo, velo_file, "R", 9));
  const Vec3 t_iv(need(imu, imu_file, "T", 3).data()), t_vc(need(velo, velo_file, "T", 3).data());
  // Rectified camera -> IMU: x_imu = R_iv^T (R_vc^T (R_rect^T x_rect - T_vc) - T_iv).
  const Mat3 imu_from_rect = r_iv.transpose() * r_vc.transpose() * r_rect.transpose();
  const Vec3 centre_rect = -k.inverse() * Vec3(p[3], p[7], p[11]);  // P = K [I | t]: the centre is -t
  const Vec3 centre = r_iv.transpose() * (r_vc.transpose() * (r_rect.transpose() * centre_rect - t_vc) - t_iv);
  CameraIntrinsics in;
  in.width = width;
  in.height = height;
  in.fx = k(0, 0);
  in.fy = k(1, 1);
  in.cx = k(0, 2);
  in.cy = k(1, 2);
  CameraMount mount;
  mount.offset = Vec2(centre.x(), centre.y());
  mount.height_m = imu_height_m + centre.z();
  const Vec3 axis = imu_from_rect.col(2);  // the optical axis
  mount.tilt_rad = std::atan2(-axis.z(), std::hypot(axis.x(), axis.y()));
  mount.yaw_rad = std::atan2(axis.y(), axis.x());
  // vehicle_from_camera = Rz(yaw) Ry(tilt) N Rz(roll) (geometry/camera.cpp): the roll is what is left.
  Mat3 nominal;
  nominal << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const Mat3 base = Eigen::AngleAxisd(mount.yaw_rad, Vec3::UnitZ()).toRotationMatrix() *
                    Eigen::AngleAxisd(mount.tilt_rad, Vec3::UnitY()).toRotationMatrix() * nominal;
  const Mat3 roll = base.transpose() * imu_from_rect;
  mount.roll_rad = std::atan2(roll(1, 0), roll(0, 0));
  return {in, mount};
}

}  // namespace

namespace {

/// The odometry's rule of a field KittiRawImportOptions hands on to OdometryNoiseOptions.
OptionRule odometryRule(std::string_view name) {
  for (const OptionFieldSpec& field : odometryNoiseOptionTable().fields())
    if (field.name == name) return field.rule;
  throw std::logic_error("OdometryNoiseOptions has no field " + std::string(name));
}

}  // namespace

const OptionTable<KittiRawImportOptions>& kittiRawImportOptionTable() {
  using O = KittiRawImportOptions;
  static const OptionTable<O> table =
      OptionTable<O>("KittiRawImportOptions")
          .field("camera", &O::camera, "the camera: image_NN and P_rect_NN (02: the left colour camera)")
          .field("imu_height_m", &O::imu_height_m, OptionRule{.min = 0, .max = 10, .min_open = true, .max_open = true},
                 "the OXTS unit's height above the road, m")
          .field("gnss_every", &O::gnss_every, atLeast(0), "a GNSS fix every n-th frame; 0: none")
          .nest(&O::gnss, gnssReceiverOptionTable(),
                {{"sigma_m", "gnss_sigma_m"}, {"bias_sigma_m", "gnss_bias_sigma_m"}, {"bias_time_s", "gnss_bias_time_s"}},
                {"seed"})
          .field("scale_error", &O::scale_error, odometryRule("scale_error"), "odometry: relative distance error")
          .field("gyro_bias_deg_s", &O::gyro_bias_deg_s, odometryRule("gyro_bias_deg_s"),
                 "odometry: constant yaw-rate bias, deg/s")
          .field("seed", &O::seed, "odometry's noise")
          .field("name", &O::name, "the log's name (\"\": \"KITTI raw \" and the drive folder's name)")
          .field("grey", &O::grey, "the frames as a grey camera gives them (luminance in every channel)")
          .check("camera", [](const O& o) {
            return o.camera.size() == 2 && o.camera[0] == '0' && o.camera[1] >= '0' && o.camera[1] <= '3';
          }, "00, 01, 02 or 03");
  return table;
}

void KittiRawImportOptions::validate() const {
  kittiRawImportOptionTable().validate(*this);
  // A latitude and longitude that may be absent: no value a table holds.
  if (origin && (!(std::abs(origin->lat) <= 90) || !(std::abs(origin->lon) <= 180)))
    throw InvalidInput("KittiRawImportOptions::origin = " + std::to_string(origin->lat) + "," + std::to_string(origin->lon) +
                       ": must be a latitude in [-90, 90] and longitude in [-180, 180]");
}

std::optional<double> kittiTimeOfDay(const std::string& text) {
  int y = 0, mo = 0, d = 0, h = 0, mi = 0;
  char sep[4] = {};
  std::istringstream in(text);
  double s = 0;
  in >> y >> sep[0] >> mo >> sep[1] >> d >> h >> sep[2] >> mi >> sep[3] >> s;
  if (in.fail() || sep[0] != '-' || sep[1] != '-' || sep[2] != ':' || sep[3] != ':') return std::nullopt;
  std::string rest;
  if (in >> rest) return std::nullopt;
  if (mo < 1 || mo > 12 || d < 1 || d > 31 || h < 0 || h > 23 || mi < 0 || mi > 59 || !(s >= 0 && s < 61)) return std::nullopt;
  return 3600.0 * h + 60.0 * mi + s;
}

KittiRawImportResult importKittiRaw(const fs::path& drive, const fs::path& out, const KittiRawImportOptions& options) {
  options.validate();
  if (!fs::is_directory(drive)) throw IoError(drive.string() + ": no such drive folder");
  const fs::path date_dir = fs::absolute(drive).lexically_normal().parent_path();
  const fs::path image_dir = drive / ("image_" + options.camera);
  const std::vector<fs::path> images = listFiles(image_dir / "data", ".png");
  const std::vector<fs::path> packets = listFiles(drive / "oxts" / "data", ".txt");
  const std::vector<double> times = readTimes(image_dir / "timestamps.txt");
  if (images.size() != packets.size() || images.size() != times.size())
    throw InvalidInput(drive.string() + ": " + std::to_string(images.size()) + " images, " + std::to_string(packets.size()) +
                       " OXTS packets and " + std::to_string(times.size()) + " image times: the synced drive pairs them one to one");
  std::vector<Oxts> oxts;
  for (const fs::path& f : packets) oxts.push_back(readOxts(f));

  const Image first = readPng(images.front());
  const auto [in, mount] = cameraFromCalibration(date_dir, options.camera, options.imu_height_m, first.width, first.height);
  KittiRawImportResult result;
  result.origin = options.origin.value_or(LatLon{oxts.front().lat, oxts.front().lon});
  const LocalFrame local(GeoOrigin{result.origin.lat, result.origin.lon, 0.0});
  result.intrinsics = in;
  result.mount = mount;

  LogHeader header;
  header.name = options.name.empty() ? "KITTI raw " + fs::absolute(drive).lexically_normal().filename().string() : options.name;
  header.camera = createCamera(LensModel::Pinhole, in, mount);
  header.frame_rate_hz = times.size() > 1 ? (times.size() - 1) / (times.back() - times.front()) : 10.0;

  OdometryNoiseOptions noise;
  noise.seed = options.seed;
  noise.scale_error = options.scale_error;
  noise.gyro_bias_deg_s = options.gyro_bias_deg_s;
  OdometrySensor odometry(noise);
  GnssReceiverOptions receiver_options = options.gnss;
  receiver_options.seed = options.seed + 1;
  GnssReceiver receiver(receiver_options);
  ReplayLogWriter writer(out, header);
  std::optional<Pose2> previous;
  for (std::size_t i = 0; i < images.size(); ++i) {
    const Image image = i == 0 ? first : readPng(images[i]);
    if (image.width != first.width || image.height != first.height)
      throw InvalidInput(images[i].string() + ": the image is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                         " but the first is " + std::to_string(first.width) + "x" + std::to_string(first.height));
    LogFrame f;
    f.t = times[i];
    const Pose2 truth(local.toLocal({oxts[i].lat, oxts[i].lon}), oxts[i].yaw);
    f.truth = truth;
    if (i > 0) {
      // The OXTS forward speed and yaw rate, trapezoid over the interval (what wheel encoders and a gyro measure).
      const double dt = times[i] - times[i - 1];
      const double distance = 0.5 * (oxts[i - 1].vf + oxts[i].vf) * dt, dheading = 0.5 * (oxts[i - 1].wu + oxts[i].wu) * dt;
      f.odometry = odometry.measure(distance, dheading, dt);
      result.distance_m += (truth.translation() - previous->translation()).norm();
    }
    if (options.gnss_every > 0 && i % static_cast<std::size_t>(options.gnss_every) == 0) {
      f.gnss = receiver.measure(truth.translation(), f.t);
      ++result.gnss_fixes;
    }
    previous = truth;
    writer.add(f, options.grey ? greyed(image) : image);
  }
  writeFileAtomic(writer.partialDir() / "camera.json", cameraToJson(*header.camera, header.name));
  writer.finish();
  result.frames = images.size();
  result.duration_s = times.back() - times.front();
  return result;
}

}  // namespace mapnav
