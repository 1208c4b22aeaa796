#include "mapnav/vision/overlay.h"

#include <opencv2/imgproc.hpp>

#include "cv_view.h"
#include "mapnav/core/error.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>

namespace mapnav {

namespace {

cv::Point fixed(const Vec2& p) {  // 4 fractional bits, pixel centres at integers
  return {static_cast<int>(std::lround(p.x() * 16)), static_cast<int>(std::lround(p.y() * 16))};
}

std::vector<cv::Point> ring(const Polygon2& polygon) {
  std::vector<cv::Point> out;
  for (const Vec2& p : polygon) {
    if (p.allFinite() && std::abs(p.x()) < 1e5 && std::abs(p.y()) < 1e5) out.push_back(fixed(p));
  }
  return out;
}

}  // namespace

Image regionMask(const DetectedObject& detection, int width, int height) {
  const Image& m = detection.road_mask;
  if (!m.empty() && m.width == width && m.height == height && m.channels == 1) return m;
  return regionMask(detection.region_image, width, height);
}

Image regionMask(const Polygon2& region_image, int width, int height) {
  Image out(width, height, 1);
  const std::vector<cv::Point> points = ring(region_image);
  if (points.size() >= 3) {
    const cv::Point* pts = points.data();
    const int n = static_cast<int>(points.size());
    cv::Mat mask = cvview::view(out);
    cv::fillPoly(mask, &pts, &n, 1, cv::Scalar(255), cv::LINE_8, 4);
  }
  return out;
}

Image groundMask(const Camera& camera) {
  Image out(camera.width(), camera.height(), 1);
  for (int v = 0; v < out.height; ++v)
    for (int u = 0; u < out.width; ++u)
      if (camera.backproject(Vec2(u, v))) out.pixel(u, v)[0] = 255;
  return out;
}

Image drawDetection(const Image& frame, const PredictedObject& prediction, const DetectedObject& detection) {
  cv::Mat rgb(frame.height, frame.width, CV_8UC3);
  if (frame.channels == 3) {
    std::memcpy(rgb.data, frame.data.data(), frame.data.size());
  } else {
    cv::Mat grey(frame.height, frame.width, CV_8UC1, const_cast<std::uint8_t*>(frame.data.data()));
    cv::cvtColor(grey, rgb, cv::COLOR_GRAY2RGB);
  }
  const std::vector<cv::Point> region = ring(detection.region_image);
  if (region.size() >= 3) cv::polylines(rgb, std::vector<std::vector<cv::Point>>{region}, true, cv::Scalar(255, 220, 0), 1, cv::LINE_AA, 4);
  for (const InterestSegment& s : prediction.segments) {
    cv::line(rgb, fixed(s.image.a), fixed(s.image.b), cv::Scalar(255, 255, 255), 1, cv::LINE_AA, 4);
  }
  for (const DetectedLine& line : detection.lines) {
    const cv::Scalar colour = line.frame_edge ? cv::Scalar(150, 150, 150)
                              : line.label    ? cv::Scalar(40, 220, 40)
                                              : cv::Scalar(230, 40, 40);
    cv::line(rgb, fixed(line.image.a), fixed(line.image.b), colour, 3, cv::LINE_AA, 4);
    if (line.label) {
      const Vec2 mid = line.image.pointAt(0.5);
      cv::putText(rgb, *line.label, cv::Point(static_cast<int>(mid.x()) + 4, static_cast<int>(mid.y()) - 4),
                  cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(255, 255, 255), 2, cv::LINE_AA);
      cv::putText(rgb, *line.label, cv::Point(static_cast<int>(mid.x()) + 4, static_cast<int>(mid.y()) - 4),
                  cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 100, 0), 1, cv::LINE_AA);
    }
  }
  const std::string status = detection.status == DetectedObject::Status::Ok ? "ok" : "failed: " + detection.reason;
  cv::putText(rgb, status, cv::Point(6, 16), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
  cv::putText(rgb, status, cv::Point(6, 16), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  Image out(frame.width, frame.height, 3);
  std::memcpy(out.data.data(), rgb.data, out.data.size());
  return out;
}

Image drawDetection(const Image& frame, const PredictedObject& prediction, const DetectedObject& detection,
                    const Camera& camera) {
  Image out = drawDetection(frame, prediction, detection);
  if (!detection.centerline_vehicle) return out;
  const auto a = camera.projectGround(detection.centerline_vehicle->a);
  const auto b = camera.projectGround(detection.centerline_vehicle->b);
  if (!a || !b) return out;
  cv::Mat rgb = cvview::view(out);
  cv::line(rgb, fixed(*a), fixed(*b), cv::Scalar(255, 0, 255), 3, cv::LINE_AA, 4);
  return out;
}

void drawGroundPath(Image& overlay, const std::vector<Vec2>& path_vehicle, const Camera& camera) {
  if (overlay.channels != 3) throw InvalidInput("drawGroundPath: the overlay must be RGB");
  const cv::Scalar cyan(0, 255, 255);
  cv::Mat rgb = cvview::view(overlay);
  std::optional<Vec2> last;
  for (const Vec2& g : path_vehicle) {
    auto px = camera.projectGround(g);
    if (px && !(std::abs(px->x()) < 1e5 && std::abs(px->y()) < 1e5)) px.reset();  // as ring(): fixed() stays in int
    if (px && last) cv::line(rgb, fixed(*last), fixed(*px), cyan, 2, cv::LINE_AA, 4);
    if (px && camera.inImage(*px)) cv::circle(rgb, fixed(*px), 2 * 16, cyan, cv::FILLED, cv::LINE_AA, 4);
    last = px;
  }
}

Image contactSheet(const std::vector<Image>& tiles, const std::vector<std::string>& captions, int columns,
                   double scale) {
  if (tiles.empty()) throw InvalidInput("contactSheet: no tiles");
  if (captions.size() != tiles.size()) throw InvalidInput("contactSheet: one caption per tile");
  if (columns < 1 || !(scale > 0)) throw InvalidInput("contactSheet: columns must be >= 1 and scale > 0");
  constexpr int kGap = 4;
  std::vector<cv::Mat> scaled;
  int cell_w = 1, cell_h = 1;
  for (const Image& t : tiles) {
    cv::Mat m(t.height, t.width, t.channels == 1 ? CV_8UC1 : CV_8UC3, const_cast<std::uint8_t*>(t.data.data()));
    cv::Mat rgb;
    if (t.channels == 1) {
      cv::cvtColor(m, rgb, cv::COLOR_GRAY2RGB);
    } else {
      rgb = m;
    }
    cv::Mat small;
    cv::resize(rgb, small, cv::Size(), scale, scale, cv::INTER_AREA);
    cell_w = std::max(cell_w, small.cols);
    cell_h = std::max(cell_h, small.rows);
    scaled.push_back(small);
  }
  const int n = static_cast<int>(tiles.size());
  const int cols = std::min(columns, n), rows = (n + columns - 1) / columns;
  cv::Mat sheet(rows * cell_h + (rows - 1) * kGap, cols * cell_w + (cols - 1) * kGap, CV_8UC3, cv::Scalar(0, 0, 0));
  for (int i = 0; i < n; ++i) {
    const cv::Rect cell((i % columns) * (cell_w + kGap), (i / columns) * (cell_h + kGap), scaled[i].cols, scaled[i].rows);
    scaled[i].copyTo(sheet(cell));
    const cv::Point at(cell.x + 6, cell.y + scaled[i].rows - 8);
    cv::putText(sheet, captions[i], at, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
    cv::putText(sheet, captions[i], at, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 0), 1, cv::LINE_AA);
  }
  Image out(sheet.cols, sheet.rows, 3);
  std::memcpy(out.data.data(), sheet.data, out.data.size());
  return out;
}

}  // namespace mapnav
