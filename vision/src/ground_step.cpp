// How far the vehicle drove between two frames, measured from the ground (ground_step.h).
#include "mapnav/vision/ground_step.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "mapnav/core/error.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/geometry/pose2.h"
#include "subpixel.h"

namespace mapnav {

const OptionTable<GroundStepOptions>& groundStepOptionTable() {
  using O = GroundStepOptions;
  static const OptionTable<O> table =
      OptionTable<O>("GroundStepOptions")
          .field("near_m", &O::near_m, above(0), "the patch of ground compared: from this far ahead, m")
          .field("far_m", &O::far_m, OptionRule{.max = 100}, "... to this far ahead, m")
          .field("half_width_m", &O::half_width_m, aboveUpTo(0, 50), "... and this far to either side, m")
          .field("cell_m", &O::cell_m, above(0), "the patch's cell, m")
          .field("min_texture", &O::min_texture, atLeast(0),
                 "looked at when the patch's brightness varies by at least this standard deviation, levels")
          .field("min_peak", &O::min_peak, inRange(0, 1), "registered when the phase correlation's peak reaches this")
          .field("min_peak_ratio", &O::min_peak_ratio, atLeast(1),
                 "... and this many times the highest value more than clear_m from it")
          .field("clear_m", &O::clear_m, "... the distance from the peak of the values it must beat, m")
          .field("max_residual_m", &O::max_residual_m, above(0),
                 "kept when the residual against the predicted motion is within this, along and across, m")
          .field("max_ground_per_px_m", &O::max_ground_per_px_m, above(0),
                 "looked at only where a pixel spans at most this much ground along the road at the patch's far end, m")
          .field("sigma_m", &O::sigma_m, above(0), "the measured distance's 1-sigma from the registration, m")
          .field("pitch_sigma_deg", &O::pitch_sigma_deg, atLeast(0),
                 "the camera's pitch uncertainty as the vehicle rocks, deg")
          .check("far_m", [](const O& o) { return o.far_m > o.near_m; }, "> near_m")
          .check("cell_m",  // at least 16 cells each way for a peak, at most 1024 for the cost
                 [](const O& o) {
                   const double rows = (o.far_m - o.near_m) / o.cell_m, cols = 2 * o.half_width_m / o.cell_m;
                   return rows >= 16 && rows <= 1024 && cols >= 16 && cols <= 1024;
                 },
                 "giving 16-1024 cells along (far_m - near_m) and across (2 half_width_m)")
          .check("clear_m", [](const O& o) { return o.clear_m >= o.cell_m; }, ">= cell_m");
  return table;
}

void GroundStepOptions::validate() const { groundStepOptionTable().validate(*this); }

namespace {

void requireFrame(const VisionFrame& f, const char* which) {
  if (f.rgb == nullptr || f.camera == nullptr || f.width <= 0 || f.height <= 0) {
    throw InvalidInput(strprintf("measureGroundStep: the %s frame needs its pixels and its camera", which));
  }
}

// Where the patch starts: near_m ahead, or just beyond the nearest ground the camera sees straight
// ahead (its bottom row's middle, and 10 % more) when that is further (a car's camera).
double patchStart(const Camera& camera, const GroundStepOptions& o) {
  const auto nearest = camera.backproject(Vec2(0.5 * (camera.width() - 1), camera.height() - 1));
  return nearest && nearest->x() > 0 ? std::max(o.near_m, 1.1 * nearest->x()) : o.near_m;
}

// The patch's ground points, cell centres in the vehicle frame from `start` ahead, moved by
// `motion` (the current vehicle's pose in the frame the patch is seen from), looked up in the
// frame's pixels: the maps cv::remap reads. False when a cell does not project into the image.
bool patchMaps(const Camera& camera, const GroundStepOptions& o, double start, const Pose2& motion, cv::Mat& map_u,
               cv::Mat& map_v) {
  const int rows = static_cast<int>(std::lround((o.far_m - o.near_m) / o.cell_m));
  const int cols = static_cast<int>(std::lround(2 * o.half_width_m / o.cell_m));
  map_u.create(rows, cols, CV_32F);
  map_v.create(rows, cols, CV_32F);
  const Mat2 rotation = motion.rotation();
  const Vec2 translation = motion.translation();
  for (int i = 0; i < rows; ++i) {  // row i: ahead, the far end first (as the image has it)
    for (int j = 0; j < cols; ++j) {  // column j: from left to right
      const Vec2 p(start + (o.far_m - o.near_m) - (i + 0.5) * o.cell_m, o.half_width_m - (j + 0.5) * o.cell_m);
      const auto px = camera.projectGround(rotation * p + translation);
      if (!px || px->x() < 0 || px->y() < 0 || px->x() > camera.width() - 1 || px->y() > camera.height() - 1) return false;
      map_u.at<float>(i, j) = static_cast<float>(px->x());
      map_v.at<float>(i, j) = static_cast<float>(px->y());
    }
  }
  return true;
}

// patchMaps of `camera` with no motion (the current frame's), kept per thread for the last camera
// and options asked: they depend on nothing else, and the Vision module asks for the same every frame.
bool currentPatchMaps(const Camera& camera, const GroundStepOptions& o, double start, cv::Mat& map_u, cv::Mat& map_v) {
  struct Kept {
    bool valid = false, ok = false;
    LensModel model{};
    CameraIntrinsics intrinsics;
    CameraMount mount;
    double near_m = 0, far_m = 0, half_width_m = 0, cell_m = 0, start = 0;
    cv::Mat u, v;
  };
  thread_local Kept kept;
  const bool same = kept.valid && kept.model == camera.model() && kept.intrinsics == camera.intrinsics() &&
                    kept.mount == camera.mount() && kept.near_m == o.near_m && kept.far_m == o.far_m &&
                    kept.half_width_m == o.half_width_m && kept.cell_m == o.cell_m && kept.start == start;
  if (!same) {
    kept = Kept{true, false, camera.model(), camera.intrinsics(), camera.mount(), o.near_m, o.far_m, o.half_width_m, o.cell_m, start, {}, {}};
    kept.ok = patchMaps(camera, o, start, Pose2(), kept.u, kept.v);
  }
  map_u = kept.u;  // shared, read only
  map_v = kept.v;
  return kept.ok;
}

// The patch as the frame sees it: the sum of the three channels, bilinear (each channel
// interpolated and rounded to its 8 bits, then summed).
cv::Mat patch(const VisionFrame& f, const cv::Mat& map_u, const cv::Mat& map_v) {
  const cv::Mat rgb(f.height, f.width, CV_8UC3, const_cast<std::uint8_t*>(f.rgb));
  cv::Mat sampled;
  cv::remap(rgb, sampled, map_u, map_v, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  cv::Mat grey(sampled.rows, sampled.cols, CV_64F);
  for (int i = 0; i < sampled.rows; ++i) {
    const std::uint8_t* in = sampled.ptr<std::uint8_t>(i);
    double* out = grey.ptr<double>(i);
    for (int j = 0; j < sampled.cols; ++j) out[j] = static_cast<double>(in[3 * j] + in[3 * j + 1] + in[3 * j + 2]);
  }
  return grey;
}

// Phase correlation (Kuglin & Hines 1975): the shift s (cells, x across, y down the patch) with
// b(p) = a(p - s), the correlation surface's peak (1: the same picture moved) and the highest value
// more than `clear` cells from it in either direction — a second candidate, or the peak's own
// ridge where the ground has texture in one direction only (a kerb along the road).
struct Registration {
  cv::Point2d shift;
  double peak = 0, runner_up = 0;
};

Registration phaseCorrelation(const cv::Mat& a, const cv::Mat& b, int clear) {
  thread_local cv::Mat window;  // the same size every frame
  if (window.size() != a.size()) cv::createHanningWindow(window, a.size(), CV_64F);
  cv::Mat fa, fb, cross, surface;
  const int rows = cv::getOptimalDFTSize(a.rows), cols = cv::getOptimalDFTSize(a.cols);
  auto spectrum = [&](const cv::Mat& m, cv::Mat& out) {
    cv::Mat padded;
    cv::copyMakeBorder((m - cv::mean(m)[0]).mul(window), padded, 0, rows - m.rows, 0, cols - m.cols, cv::BORDER_CONSTANT, 0);
    cv::dft(padded, out, cv::DFT_COMPLEX_OUTPUT);
  };
  spectrum(a, fa);
  spectrum(b, fb);
  cv::mulSpectrums(fb, fa, cross, 0, true);
  // The cross power spectrum normalised to unit magnitude, in place (the magnitude as cv::magnitude
  // computes it where it vectorises: one fused multiply-add).
  for (int y = 0; y < cross.rows; ++y) {
    double* c = cross.ptr<double>(y);
    for (int x = 0; x < 2 * cross.cols; x += 2) {
      const double magnitude = std::sqrt(std::fma(c[x], c[x], c[x + 1] * c[x + 1])) + 1e-12;
      c[x] /= magnitude;
      c[x + 1] /= magnitude;
    }
  }
  cv::idft(cross, surface, cv::DFT_REAL_OUTPUT | cv::DFT_SCALE);
  cv::Point at;
  Registration r;
  cv::minMaxLoc(surface, nullptr, &r.peak, nullptr, &at);
  auto value = [&](int y, int x) { return surface.at<double>((y + rows) % rows, (x + cols) % cols); };
  const double sx = at.x + parabolaPeak(value(at.y, at.x - 1), r.peak, value(at.y, at.x + 1));
  const double sy = at.y + parabolaPeak(value(at.y - 1, at.x), r.peak, value(at.y + 1, at.x));
  r.shift = cv::Point2d(sx > cols / 2 ? sx - cols : sx, sy > rows / 2 ? sy - rows : sy);
  // The cyclic distance of each column from the peak's; a row that far from the peak's counts whole.
  std::vector<char> far_column(static_cast<std::size_t>(cols));
  for (int x = 0; x < cols; ++x) far_column[x] = std::min((x - at.x + cols) % cols, (at.x - x + cols) % cols) > clear;
  for (int y = 0; y < rows; ++y) {
    const bool far_row = std::min((y - at.y + rows) % rows, (at.y - y + rows) % rows) > clear;
    const double* row = surface.ptr<double>(y);
    for (int x = 0; x < cols; ++x) {
      if (far_row || far_column[x]) r.runner_up = std::max(r.runner_up, row[x]);
    }
  }
  return r;
}

}  // namespace

MeasuredStep measureGroundStep(const VisionFrame& previous, const VisionFrame& current, const MotionIncrement& predicted,
                               const GroundStepOptions& o) {
  o.validate();
  requireFrame(previous, "previous");
  requireFrame(current, "current");
  if (previous.width != current.width || previous.height != current.height) {
    throw InvalidInput(strprintf("measureGroundStep: the frames differ in size (%dx%d, %dx%d)", previous.width,
                                 previous.height, current.width, current.height));
  }
  MeasuredStep out;
  if (!std::isfinite(predicted.distance_m) || !std::isfinite(predicted.dheading_rad)) {
    out.reason = "no finite predicted motion";
    return out;
  }
  // The current vehicle's pose in the previous vehicle's frame: the step along the mid-step heading.
  const double d = predicted.distance_m;
  const Pose2 motion = stepPose(predicted);
  cv::Mat cu, cv_, pu, pv;
  const double start = patchStart(*current.camera, o), end = start + (o.far_m - o.near_m);
  const Camera& camera = *current.camera;
  const auto far = camera.projectGround(Vec2(end, 0)), beyond = camera.projectGround(Vec2(end + 0.01, 0));
  const double per_px = far && beyond ? 0.01 / std::max(1e-9, (*far - *beyond).norm()) : HUGE_VAL;
  if (!(per_px <= o.max_ground_per_px_m)) {
    out.reason = strprintf("the ground is seen too shallow: a pixel spans %.3f m along the road %.1f m ahead (at most %.3f)",
                           per_px, end, o.max_ground_per_px_m);
    return out;
  }
  if (!currentPatchMaps(*current.camera, o, start, cu, cv_) || !patchMaps(*previous.camera, o, start, motion, pu, pv)) {
    out.reason = "the ground patch is not in view of both frames";
    return out;
  }
  const cv::Mat now = patch(current, cu, cv_), before = patch(previous, pu, pv);
  cv::Scalar mean, spread;
  cv::meanStdDev(now, mean, spread);
  if (!(spread[0] >= o.min_texture)) {
    out.reason = strprintf("the ground has no texture (spread %.1f < %.1f levels)", spread[0], o.min_texture);
    return out;
  }
  // `before` holds the ground the odometry says is at each cell; if the vehicle drove r further,
  // that ground is now r nearer: `before` is `now` moved r ahead (up the patch, rows decreasing).
  const int clear = static_cast<int>(std::ceil(o.clear_m / o.cell_m));
  const Registration r = phaseCorrelation(now, before, clear);
  out.peak = r.peak;
  const double ahead = -r.shift.y * o.cell_m, left = -r.shift.x * o.cell_m;
  if (!(r.peak >= o.min_peak && r.peak >= o.min_peak_ratio * r.runner_up)) {
    out.reason = strprintf("the ground did not register (peak %.3f, next %.3f beyond %.2f m)", r.peak, r.runner_up, o.clear_m);
    return out;
  }
  if (!(std::abs(ahead) <= o.max_residual_m && std::abs(left) <= o.max_residual_m)) {
    out.reason = strprintf("registered %.3f m ahead, %.3f m left of the predicted motion: beyond %.2f m", ahead, left,
                           o.max_residual_m);
    return out;
  }
  out.found = true;
  out.distance_m = d + ahead;
  out.left_m = left;
  // The pitch's share: the patch's middle, seen from the camera's height at depression angle a.
  const Vec3 c = camera.center();
  const double a = std::atan2(c.z(), std::max(1e-6, 0.5 * (start + end) - c.x()));
  const double pitch = std::abs(out.distance_m) * 2 / std::sin(2 * a) * degToRad(o.pitch_sigma_deg);
  out.sigma_m = std::hypot(o.sigma_m, pitch);
  return out;
}

}  // namespace mapnav
