// Canvas → PNG bytes: drawn with OpenCV (the only file of mapnav that uses OpenCV for drawing),
// anti-aliased (cv::LINE_AA) with sub-pixel coordinates (shift = 4, i.e. 1/16 px), into an Image
// that mapnav::image encodes.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "detail.h"
#include "mapnav/core/error.h"
#include "mapnav/image/png.h"
#include "mapnav/render/canvas.h"

namespace mapnav::render {
namespace {

constexpr int kShift = 4;
constexpr double kOne = 1 << kShift;
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

/// A colour in the channel order of the image drawn into (RGB, mapnav::Image's). OpenCV's drawing
/// treats the channels alike, so the order is only the colours'.
cv::Scalar rgb(const Rgb& c) { return {static_cast<double>(c.r), static_cast<double>(c.g), static_cast<double>(c.b)}; }

/// Canvas pixel coordinates (pixel i covers [i, i+1)) → OpenCV fixed point (pixel i centred on i),
/// relative to `origin` (the top-left of the image being drawn into).
cv::Point fixedPoint(const Vec2& p, const cv::Point& origin) {
  return {static_cast<int>(std::lround((p.x() - 0.5 - origin.x) * kOne)),
          static_cast<int>(std::lround((p.y() - 0.5 - origin.y) * kOne))};
}

std::vector<cv::Point> fixedPoints(const std::vector<Vec2>& pts, const cv::Point& origin) {
  std::vector<cv::Point> out;
  out.reserve(pts.size());
  for (const Vec2& p : pts) out.push_back(fixedPoint(p, origin));
  return out;
}

/// The pixels that points spread by `reach` px can touch (may lie partly off the image).
cv::Rect boundsOf(const std::vector<Vec2>& pts, double reach) {
  double u0 = pts.front().x(), u1 = u0, v0 = pts.front().y(), v1 = v0;
  for (const Vec2& p : pts) {
    u0 = std::min(u0, p.x()), u1 = std::max(u1, p.x());
    v0 = std::min(v0, p.y()), v1 = std::max(v1, p.y());
  }
  const int x0 = static_cast<int>(std::floor(u0 - reach)) - 2, y0 = static_cast<int>(std::floor(v0 - reach)) - 2;
  const int x1 = static_cast<int>(std::ceil(u1 + reach)) + 2, y1 = static_cast<int>(std::ceil(v1 + reach)) + 2;
  return {x0, y0, x1 - x0, y1 - y0};
}

/// Runs `draw(target, origin)` straight onto the image, or, with opacity below 1, onto a copy of
/// the part of the image within `bounds` which is then blended back (cv::addWeighted).
template <class Draw>
void drawBlended(cv::Mat& img, const cv::Rect& bounds, double opacity, const Draw& draw) {
  if (opacity <= 0.0) return;
  if (opacity >= 1.0) {
    draw(img, cv::Point(0, 0));
    return;
  }
  const cv::Rect r = bounds & cv::Rect(0, 0, img.cols, img.rows);
  if (r.empty()) return;
  cv::Mat roi = img(r);
  cv::Mat overlay = roi.clone();
  draw(overlay, r.tl());
  cv::addWeighted(overlay, opacity, roi, 1.0 - opacity, 0.0, roi);
}

/// `path` cut into the drawn pieces of the dash pattern (`on` px drawn, `off` px skipped, starting
/// with a drawn piece at the first point, as SVG's stroke-dasharray).
std::vector<std::vector<Vec2>> dashPieces(const std::vector<Vec2>& path, double on, double off) {
  std::vector<std::vector<Vec2>> pieces;
  if (path.size() < 2) return pieces;
  std::vector<Vec2> current{path.front()};
  bool drawing = true;
  double left = on;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const Vec2 a = path[i], d = path[i + 1] - path[i];
    const double len = d.norm();
    double t = 0.0;
    while (len - t > left) {
      t += left;
      const Vec2 p = a + d * (t / len);
      if (drawing) {
        current.push_back(p);
        pieces.push_back(std::move(current));
        current.clear();
      } else {
        current = {p};
      }
      drawing = !drawing;
      left = drawing ? on : off;
    }
    left -= len - t;
    if (drawing) current.push_back(path[i + 1]);
  }
  if (drawing && current.size() >= 2) pieces.push_back(std::move(current));
  return pieces;
}

/// Strokes `path` (closed: back to the first point), solid or dashed.
void strokePath(cv::Mat& img, const cv::Point& origin, std::vector<Vec2> path, bool closed, const Style& style) {
  const double w = detail::sanitizeStrokeWidth(style.stroke_width_px);
  const int thickness = detail::strokeThickness(w);
  const cv::Scalar color = rgb(*style.stroke);
  if (!style.dashed) {
    const std::vector<std::vector<cv::Point>> contour{fixedPoints(path, origin)};
    cv::polylines(img, contour, closed, color, thickness, cv::LINE_AA, kShift);
    return;
  }
  if (closed) path.push_back(path.front());
  std::vector<std::vector<cv::Point>> dashes;
  for (const std::vector<Vec2>& piece : dashPieces(path, detail::dashOn(w), detail::dashOff(w))) {
    dashes.push_back(fixedPoints(piece, origin));
  }
  if (!dashes.empty()) cv::polylines(img, dashes, false, color, thickness, cv::LINE_AA, kShift);
}

/// Cap height of FONT_HERSHEY_SIMPLEX at font scale 1, in pixels.
double capHeightAtScale1() {
  static const double cap = [] {
    int baseline = 0;
    const cv::Size size = cv::getTextSize("H", kFont, 100.0, 1, &baseline);
    return std::max(1.0, (size.height - 1.0) / 100.0);
  }();
  return cap;
}

class PngPainter {
 public:
  PngPainter(cv::Mat& img) : img_(img) {}

  void operator()(const Canvas::PolygonCmd& cmd) const {
    const Style& style = cmd.style;
    if (!style.fill && !style.stroke) return;
    const std::vector<Vec2> ring =
        detail::clipRing(cmd.points, detail::clipBoxFor(img_.cols, img_.rows, style.stroke_width_px));
    if (ring.size() < 2 || (ring.size() < 3 && !style.stroke)) return;
    const double reach = style.stroke ? detail::strokeThickness(style.stroke_width_px) : 0.0;
    drawBlended(img_, boundsOf(ring, reach), detail::sanitizeOpacity(style.opacity),
                [&](cv::Mat& target, const cv::Point& origin) {
                  if (style.fill && ring.size() >= 3) {
                    const std::vector<std::vector<cv::Point>> contour{fixedPoints(ring, origin)};
                    cv::fillPoly(target, contour, rgb(*style.fill), cv::LINE_AA, kShift);
                  }
                  if (style.stroke) strokePath(target, origin, ring, true, style);
                });
  }

  void operator()(const Canvas::PolylineCmd& cmd) const {
    const Style& style = cmd.style;
    if (!style.stroke) return;
    const double reach = detail::strokeThickness(style.stroke_width_px);
    for (const std::vector<Vec2>& piece :
         detail::clipPolyline(cmd.points, detail::clipBoxFor(img_.cols, img_.rows, style.stroke_width_px))) {
      drawBlended(img_, boundsOf(piece, reach), detail::sanitizeOpacity(style.opacity),
                  [&](cv::Mat& target, const cv::Point& origin) { strokePath(target, origin, piece, false, style); });
    }
  }

  void operator()(const Canvas::CircleCmd& cmd) const {
    const Style& style = cmd.style;
    if (!style.fill && !style.stroke) return;
    if (!detail::usablePoint(cmd.center) || !std::isfinite(cmd.radius) || cmd.radius <= 0.0 ||
        cmd.radius > detail::kFarPx) {
      return;
    }
    const int thickness = detail::strokeThickness(style.stroke_width_px);
    const double reach = cmd.radius + (style.stroke ? thickness : 0.0);
    const cv::Rect bounds = boundsOf({cmd.center}, reach);
    drawBlended(img_, bounds, detail::sanitizeOpacity(style.opacity), [&](cv::Mat& target, const cv::Point& origin) {
      const cv::Point c = fixedPoint(cmd.center, origin);
      const int r = static_cast<int>(std::lround(cmd.radius * kOne));
      if (style.fill) cv::circle(target, c, r, rgb(*style.fill), cv::FILLED, cv::LINE_AA, kShift);
      if (style.stroke) cv::circle(target, c, r, rgb(*style.stroke), thickness, cv::LINE_AA, kShift);
    });
  }

  void operator()(const Canvas::TextCmd& cmd) const {
    const double size = detail::sanitizeTextSize(cmd.style.size_px);
    if (size <= 0.0 || cmd.text.empty() || !detail::usablePoint(cmd.position)) return;
    std::string text = detail::toAsciiForRaster(cmd.text);
    // Keep OpenCV's integer text metrics far from overflow; such text is absurdly long anyway.
    const auto max_chars = static_cast<std::size_t>(std::max(1.0, 2.0e7 / size));
    if (text.size() > max_chars) text.resize(max_chars);
    const double scale = size / capHeightAtScale1();
    const int thickness = cmd.style.bold ? std::max(2, static_cast<int>(std::lround(size / 6.0)))
                                         : std::max(1, static_cast<int>(std::lround(size / 11.0)));
    int baseline = 0;
    const cv::Size extent = cv::getTextSize(text, kFont, scale, thickness, &baseline);
    double u = cmd.position.x() - 0.5;
    if (cmd.style.anchor == Anchor::Middle) u -= 0.5 * extent.width;
    if (cmd.style.anchor == Anchor::End) u -= extent.width;
    const cv::Point org(static_cast<int>(std::lround(u)), static_cast<int>(std::lround(cmd.position.y() - 0.5)));
    if (cmd.style.halo) {
      const int halo = thickness + 2 * static_cast<int>(std::lround(detail::haloReachPx(size)));
      cv::putText(img_, text, org, kFont, scale, rgb(*cmd.style.halo), halo, cv::LINE_AA);
    }
    cv::putText(img_, text, org, kFont, scale, rgb(cmd.style.color), thickness, cv::LINE_AA);
  }

 private:
  cv::Mat& img_;
};

}  // namespace

std::string Canvas::toPng() const {
  try {
    Image image(width_, height_, 3);
    cv::Mat img(height_, width_, CV_8UC3, image.data.data());  // a view: drawing fills `image`
    img.setTo(rgb(background_));
    const PngPainter painter(img);
    for (const Command& cmd : commands_) std::visit(painter, cmd);
    const std::vector<std::uint8_t> bytes = encodePng(image, PngCompression::Balanced);
    return std::string(bytes.begin(), bytes.end());
  } catch (const cv::Exception& e) {
    // OpenCV's exception types stay inside this file.
    throw Error(std::string("render: drawing the PNG failed: ") + e.what());
  }
}

}  // namespace mapnav::render
