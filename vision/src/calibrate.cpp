#include "mapnav/vision/calibrate.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "cv_view.h"
#include "mapnav/core/error.h"

namespace mapnav {

namespace {

bool finite(const Vec2& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

void requireSegment(const Segment2& s, const char* what) {
  if (!finite(s.a) || !finite(s.b) || (s.b - s.a).norm() < 1e-9) {
    throw InvalidInput(std::string("calibration: ") + what + " is degenerate (zero length or not finite)");
  }
}

// Removes pin-hole distortion from pixels (back to pixels of the ideal pin-hole).
std::vector<Vec2> undistortPixels(const CameraIntrinsics& in, const std::vector<Vec2>& pixels) {
  bool any = std::any_of(in.distortion.begin(), in.distortion.end(), [](double k) { return k != 0.0; });
  if (!any) return pixels;
  const cv::Matx33d k(in.fx, 0, in.cx, 0, in.fy, in.cy, 0, 0, 1);
  std::vector<cv::Point2d> src, dst;
  for (const Vec2& p : pixels) src.emplace_back(p.x(), p.y());
  cv::undistortPoints(src, dst, k, in.distortion, cv::noArray(), k);
  std::vector<Vec2> out;
  for (const cv::Point2d& p : dst) out.emplace_back(p.x, p.y);
  return out;
}

using cvview::view;

cv::Mat toGrey(const Image& image) {
  if (image.empty() || image.width <= 0 || image.height <= 0 ||
      image.data.size() != static_cast<std::size_t>(image.width) * image.height * image.channels ||
      (image.channels != 1 && image.channels != 3)) {
    throw InvalidInput("calibration: an image is empty or not 8-bit grey or RGB");
  }
  cv::Mat grey;
  if (image.channels == 1) {
    grey = view(image).clone();
  } else {
    cv::cvtColor(view(image), grey, cv::COLOR_RGB2GRAY);
  }
  return grey;
}

void requireBoard(int cols, int rows) {
  if (cols < 2 || rows < 2) {
    throw InvalidInput("calibration: the chessboard needs at least 2 x 2 inner corners (got " + std::to_string(cols) +
                       " x " + std::to_string(rows) + ")");
  }
}

std::optional<std::vector<cv::Point2f>> detect(const cv::Mat& grey, int cols, int rows) {
  std::vector<cv::Point2f> corners;
  const bool found = cv::findChessboardCorners(grey, cv::Size(cols, rows), corners,
                                               cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE);
  if (!found) return std::nullopt;
  // The refinement window: as large as OpenCV's usual 11 x 11 half-size, but never reaching the
  // neighbouring corners on a small board image.
  double spacing = 1e9;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const cv::Point2f& p = corners[static_cast<std::size_t>(r * cols + c)];
      if (c + 1 < cols) spacing = std::min(spacing, static_cast<double>(cv::norm(corners[static_cast<std::size_t>(r * cols + c + 1)] - p)));
      if (r + 1 < rows) spacing = std::min(spacing, static_cast<double>(cv::norm(corners[static_cast<std::size_t>((r + 1) * cols + c)] - p)));
    }
  }
  const int half = std::clamp(static_cast<int>(spacing * 0.4), 2, 11);
  cv::cornerSubPix(grey, corners, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
  return corners;
}

}  // namespace

std::optional<Vec2> vanishingPoint(const CameraIntrinsics& intrinsics, const Segment2& line_a, const Segment2& line_b) {
  requireSegment(line_a, "the first line");
  requireSegment(line_b, "the second line");
  const std::vector<Vec2> p = undistortPixels(intrinsics, {line_a.a, line_a.b, line_b.a, line_b.b});
  const Vec3 la = Vec3(p[0].x(), p[0].y(), 1.0).cross(Vec3(p[1].x(), p[1].y(), 1.0));
  const Vec3 lb = Vec3(p[2].x(), p[2].y(), 1.0).cross(Vec3(p[3].x(), p[3].y(), 1.0));
  const Vec3 v = la.cross(lb);
  // Parallel when the lines' directions are parallel: |w| small against the point's coordinates.
  const Vec2 da = (p[1] - p[0]).normalized(), db = (p[3] - p[2]).normalized();
  if (std::abs(cross2(da, db)) < 1e-9 || v.z() == 0.0) return std::nullopt;
  return Vec2(v.x() / v.z(), v.y() / v.z());
}

double tiltFromParallelLines(const CameraIntrinsics& intrinsics, const Segment2& line_a, const Segment2& line_b) {
  if (!(intrinsics.fy > 0) || !std::isfinite(intrinsics.fy) || !std::isfinite(intrinsics.cy)) {
    throw InvalidInput("tiltFromParallelLines: the focal length fy must be finite and > 0");
  }
  const std::optional<Vec2> vp = vanishingPoint(intrinsics, line_a, line_b);
  if (!vp) {
    throw InvalidInput(
        "tiltFromParallelLines: the two lines are parallel in the image, so their vanishing point (and the horizon) "
        "cannot be found");
  }
  return std::atan((intrinsics.cy - vp->y()) / intrinsics.fy);
}

ScaleFactors scaleFromSticks(const Segment2& x_stick_px, double x_stick_length_m, const Segment2& y_stick_px,
                             double y_stick_length_m) {
  requireSegment(x_stick_px, "the x stick");
  requireSegment(y_stick_px, "the y stick");
  if (!(x_stick_length_m > 0) || !std::isfinite(x_stick_length_m) || !(y_stick_length_m > 0) ||
      !std::isfinite(y_stick_length_m)) {
    throw InvalidInput("scaleFromSticks: the sticks' lengths must be finite and > 0");
  }
  // Unknowns a = x_m_per_px², b = y_m_per_px²: L² = Δr²·a + Δc²·b for each stick.
  const Vec2 dx = x_stick_px.vector(), dy = y_stick_px.vector();
  Mat2 m;
  m << dx.y() * dx.y(), dx.x() * dx.x(), dy.y() * dy.y(), dy.x() * dy.x();
  const Vec2 rhs(x_stick_length_m * x_stick_length_m, y_stick_length_m * y_stick_length_m);
  const double det = m.determinant();
  const double scale = m.cwiseAbs().maxCoeff();
  if (std::abs(det) < 1e-6 * scale * scale) {
    throw InvalidInput("scaleFromSticks: the two sticks are (nearly) parallel in the image");
  }
  const Vec2 ab = m.inverse() * rhs;
  if (!(ab.x() > 0) || !(ab.y() > 0)) {
    throw InvalidInput(
        "scaleFromSticks: no positive scale fits the sticks (is the x stick along the rows and the y stick along the "
        "columns?)");
  }
  return {std::sqrt(ab.x()), std::sqrt(ab.y())};
}

std::optional<std::vector<Vec2>> findChessboard(const Image& image, int cols, int rows) {
  requireBoard(cols, rows);
  const auto corners = detect(toGrey(image), cols, rows);
  if (!corners) return std::nullopt;
  std::vector<Vec2> out;
  out.reserve(corners->size());
  for (const cv::Point2f& p : *corners) out.emplace_back(p.x, p.y);
  return out;
}

Image drawChessboardCorners(const Image& image, int cols, int rows, const std::vector<Vec2>& corners, bool found) {
  requireBoard(cols, rows);
  const cv::Mat grey = toGrey(image);  // validates the image
  (void)grey;
  cv::Mat rgb;
  if (image.channels == 1) {
    cv::cvtColor(view(image), rgb, cv::COLOR_GRAY2RGB);
  } else {
    rgb = view(image).clone();
  }
  std::vector<cv::Point2f> pts;
  for (const Vec2& p : corners) pts.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  const bool complete = found && pts.size() == static_cast<std::size_t>(cols) * static_cast<std::size_t>(rows);
  if (!pts.empty()) cv::drawChessboardCorners(rgb, cv::Size(cols, rows), pts, complete);
  Image out(image.width, image.height, 3);
  std::copy(rgb.data, rgb.data + out.data.size(), out.data.begin());
  return out;
}

ChessboardResult calibrateChessboard(const std::vector<Image>& images, int cols, int rows, double square_m,
                                     const std::vector<std::string>& names, int size_tolerance_px) {
  requireBoard(cols, rows);
  if (!(square_m > 0) || !std::isfinite(square_m)) {
    throw InvalidInput("calibrateChessboard: square_m = " + std::to_string(square_m) + ": must be finite and > 0");
  }
  if (size_tolerance_px < 0) {
    throw InvalidInput("calibrateChessboard: size_tolerance_px = " + std::to_string(size_tolerance_px) + ": must be >= 0");
  }
  if (!names.empty() && names.size() != images.size()) {
    throw InvalidInput("calibrateChessboard: " + std::to_string(names.size()) + " names for " +
                       std::to_string(images.size()) + " images");
  }
  std::vector<cv::Point3f> board;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      board.emplace_back(static_cast<float>(c * square_m), static_cast<float>(r * square_m), 0.0f);
    }
  }
  ChessboardResult result;
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  std::vector<ImageSize> sizes;
  for (const Image& image : images) sizes.push_back({image.width, image.height});
  const ImageSize common = mostCommonSize(sizes);
  const auto text = [](const ImageSize& z) { return std::to_string(z.width) + "x" + std::to_string(z.height); };
  for (std::size_t i = 0; i < images.size(); ++i) {
    const std::string name = names.empty() ? "image " + std::to_string(i) : names[i];
    const ImageSize& z = sizes[i];
    if (std::abs(z.width - common.width) > size_tolerance_px || std::abs(z.height - common.height) > size_tolerance_px) {
      result.rejected.push_back(name + ": " + text(z) + ", not the common " + text(common) + " (size tolerance " +
                                std::to_string(size_tolerance_px) + " px)");
      continue;
    }
    Image fitted;
    if (z != common) {
      const bool larger = z.width >= common.width && z.height >= common.height;
      const bool smaller = z.width <= common.width && z.height <= common.height;
      result.fitted.push_back(name + ": " + text(z) + (larger ? " cut" : smaller ? " padded" : " cut and padded") +
                              " at the right and bottom to " + text(common));
      fitted = fitToSize(images[i], common);
    }
    const auto corners = detect(toGrey(z != common ? fitted : images[i]), cols, rows);
    if (!corners) {
      result.rejected.push_back(name + ": no " + std::to_string(cols) + "x" + std::to_string(rows) +
                                " chessboard found");
      continue;
    }
    image_points.push_back(*corners);
    object_points.push_back(board);
  }
  const cv::Size size(common.width, common.height);
  if (image_points.size() < 3) {
    throw InvalidInput("calibrateChessboard: the chessboard was found in " + std::to_string(image_points.size()) +
                       " image(s); at least 3 are needed");
  }
  cv::Mat k = cv::Mat::eye(3, 3, CV_64F);
  cv::Mat dist = cv::Mat::zeros(5, 1, CV_64F);
  std::vector<cv::Mat> rvecs, tvecs;
  const double rms = cv::calibrateCamera(object_points, image_points, size, k, dist, rvecs, tvecs, 0,
                                         cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12));
  result.rms_reprojection_px = rms;
  result.images_used = static_cast<int>(image_points.size());
  CameraIntrinsics& in = result.intrinsics;
  in.width = size.width;
  in.height = size.height;
  in.fx = k.at<double>(0, 0);
  in.fy = k.at<double>(1, 1);
  in.cx = k.at<double>(0, 2);
  in.cy = k.at<double>(1, 2);
  in.distortion.assign(dist.begin<double>(), dist.begin<double>() + 5);
  return result;
}

}  // namespace mapnav
