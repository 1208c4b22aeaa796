#include "mapnav/vision/rectify.h"

#include <cmath>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "mapnav/core/error.h"

namespace mapnav {

namespace {
constexpr int kMaxSide = 16384;

int cells(double min, double max, double step) {
  const double n = std::ceil((max - min) / step - 1e-9);
  return static_cast<int>(n);
}
}  // namespace

const OptionTable<RectifyOptions>& rectifyOptionTable() {
  using O = RectifyOptions;
  static const OptionTable<O> table =
      OptionTable<O>("RectifyOptions")
          .field("x_min_m", &O::x_min_m, "the ground rectified: nearest x (ahead), vehicle frame, m")
          .field("x_max_m", &O::x_max_m, "... farthest x, m")
          .field("y_min_m", &O::y_min_m, "... rightmost y (left positive), m")
          .field("y_max_m", &O::y_max_m, "... leftmost y, m")
          .field("metres_per_pixel", &O::metres_per_pixel, above(0), "ground size of one rectified pixel, m")
          .check("x_max_m", [](const O& o) { return o.x_max_m > o.x_min_m; }, "> x_min_m")
          .check("y_max_m", [](const O& o) { return o.y_max_m > o.y_min_m; }, "> y_min_m")
          .check("metres_per_pixel", [](const O& o) { return (o.y_max_m - o.y_min_m) / o.metres_per_pixel <= kMaxSide; },
                 "such that (y_max_m - y_min_m) / metres_per_pixel <= 16384")
          .check("metres_per_pixel", [](const O& o) { return (o.x_max_m - o.x_min_m) / o.metres_per_pixel <= kMaxSide; },
                 "such that (x_max_m - x_min_m) / metres_per_pixel <= 16384");
  return table;
}

void RectifyOptions::validate() const { rectifyOptionTable().validate(*this); }

int RectifyOptions::width() const { return cells(y_min_m, y_max_m, metres_per_pixel); }
int RectifyOptions::height() const { return cells(x_min_m, x_max_m, metres_per_pixel); }

struct Rectifier::Impl {
  RectifyOptions options;
  int camera_width = 0, camera_height = 0;
  cv::Mat map_u, map_v;  // CV_32FC1, rectified size: the source pixel of each grid point (−1 = none)
  long covered = 0;
};

Rectifier::Rectifier(const Camera& camera, RectifyOptions options) : impl_(std::make_unique<Impl>()) {
  options.validate();
  impl_->options = options;
  impl_->camera_width = camera.width();
  impl_->camera_height = camera.height();
  const int w = options.width(), h = options.height();
  impl_->map_u.create(h, w, CV_32FC1);
  impl_->map_v.create(h, w, CV_32FC1);
  long covered = 0;
  for (int r = 0; r < h; ++r) {
    auto* mu = impl_->map_u.ptr<float>(r);
    auto* mv = impl_->map_v.ptr<float>(r);
    for (int c = 0; c < w; ++c) {
      const std::optional<Vec2> px = camera.projectGround(groundAt(c, r));
      if (px && camera.inImage(*px)) {
        mu[c] = static_cast<float>(px->x());
        mv[c] = static_cast<float>(px->y());
        ++covered;
      } else {
        // Far outside any image: remap's constant border gives black.
        mu[c] = -10.0f;
        mv[c] = -10.0f;
      }
    }
  }
  impl_->covered = covered;
}

Rectifier::~Rectifier() = default;
Rectifier::Rectifier(Rectifier&&) noexcept = default;
Rectifier& Rectifier::operator=(Rectifier&&) noexcept = default;

const RectifyOptions& Rectifier::options() const { return impl_->options; }
int Rectifier::width() const { return impl_->map_u.cols; }
int Rectifier::height() const { return impl_->map_u.rows; }

Vec2 Rectifier::groundAt(double col, double row) const {
  const RectifyOptions& o = impl_->options;
  return {o.x_max_m - (row + 0.5) * o.metres_per_pixel, o.y_max_m - (col + 0.5) * o.metres_per_pixel};
}

Vec2 Rectifier::pixelAt(const Vec2& ground) const {
  const RectifyOptions& o = impl_->options;
  return {(o.y_max_m - ground.y()) / o.metres_per_pixel - 0.5, (o.x_max_m - ground.x()) / o.metres_per_pixel - 0.5};
}

double Rectifier::coverage() const {
  const double total = static_cast<double>(width()) * height();
  return total > 0 ? static_cast<double>(impl_->covered) / total : 0.0;
}

namespace {

// A frame that is `width` x `height` with 1 or 3 channels and matching data, or InvalidInput
// saying which.
void checkFrame(const Image& frame, int width, int height, const char* what) {
  if (frame.width != width || frame.height != height) {
    throw InvalidInput(std::string(what) + ": the frame is " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                       ", the camera's image " + std::to_string(width) + "x" + std::to_string(height));
  }
  if (frame.channels != 1 && frame.channels != 3) {
    throw InvalidInput(std::string(what) + ": the frame has " + std::to_string(frame.channels) + " channels (1 or 3 expected)");
  }
  if (frame.data.size() != static_cast<std::size_t>(frame.width) * frame.height * frame.channels) {
    throw InvalidInput(std::string(what) + ": the frame's data does not match its size");
  }
}

// Each output pixel bilinearly sampled at (map_u, map_v) of the frame; black outside it.
Image remapFrame(const Image& frame, const cv::Mat& map_u, const cv::Mat& map_v) {
  const int type = frame.channels == 1 ? CV_8UC1 : CV_8UC3;
  // remap only reads the source.
  const cv::Mat src(frame.height, frame.width, type, const_cast<std::uint8_t*>(frame.data.data()));
  Image out(map_u.cols, map_u.rows, frame.channels);
  cv::Mat dst(out.height, out.width, type, out.data.data());
  cv::remap(src, dst, map_u, map_v, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(0));
  return out;
}

}  // namespace

Image Rectifier::apply(const Image& frame) const {
  checkFrame(frame, impl_->camera_width, impl_->camera_height, "rectify");
  return remapFrame(frame, impl_->map_u, impl_->map_v);
}

Image undistortFrame(const Camera& camera, const Image& frame) {
  checkFrame(frame, camera.width(), camera.height(), "undistort");
  if (camera.model() != LensModel::Pinhole) {
    throw InvalidInput("undistort: only a pinhole camera has an ideal pinhole to undistort to (this one is " +
                       std::string(toString(camera.model())) + ")");
  }
  const CameraIntrinsics& in = camera.intrinsics();
  cv::Mat map_u(in.height, in.width, CV_32FC1), map_v(in.height, in.width, CV_32FC1);
  const Vec3 centre = camera.center();
  for (int r = 0; r < in.height; ++r) {
    auto* mu = map_u.ptr<float>(r);
    auto* mv = map_v.ptr<float>(r);
    for (int c = 0; c < in.width; ++c) {
      // The ideal pinhole's ray through (c, r), imaged by the real lens.
      const Vec3 direction((c - in.cx) / in.fx, (r - in.cy) / in.fy, 1.0);
      const std::optional<Vec2> px = camera.project(centre + camera.rotation() * direction);
      const bool ok = px && camera.inImage(*px);
      mu[c] = ok ? static_cast<float>(px->x()) : -10.0f;
      mv[c] = ok ? static_cast<float>(px->y()) : -10.0f;
    }
  }
  return remapFrame(frame, map_u, map_v);
}

}  // namespace mapnav
