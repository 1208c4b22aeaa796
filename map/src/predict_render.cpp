#include "mapnav/map/predict_render.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "mapnav/geometry/clip.h"
#include "mapnav/map/map_render.h"

namespace mapnav {

using render::Anchor;
using render::Rgb;
using render::Style;
using render::TextStyle;

const OptionTable<PredictionPictureOptions>& predictionPictureOptionTable() {
  using O = PredictionPictureOptions;
  static const OptionTable<O> table =
      OptionTable<O>("PredictionPictureOptions")
          .field("panel_px", &O::panel_px, inRange(100, 4000),
                 "height of both panels; the image panel keeps the camera's aspect")
          .field("map_margin_m", &O::map_margin_m, atLeast(0), "map shown around the footprint and the vehicle, m");
  return table;
}

void PredictionPictureOptions::validate() const { predictionPictureOptionTable().validate(*this); }

namespace {

constexpr Rgb kSegmentColour{255, 140, 0};
constexpr Rgb kFootprintColour{250, 220, 40};

Rgb rgbOf(const Vec3& c) {
  auto byte = [](double v) { return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L)); };
  return {byte(c.x()), byte(c.y()), byte(c.z())};
}

// Points every `step` metres along a ring's edges (closed) or a segment, so that a fish-eye's
// curved images of straight ground lines come out curved.
std::vector<Vec2> densify(const std::vector<Vec2>& points, bool closed, double step) {
  std::vector<Vec2> out;
  const std::size_t n = points.size();
  const std::size_t edges = closed ? n : (n == 0 ? 0 : n - 1);
  for (std::size_t i = 0; i < edges; ++i) {
    const Vec2 a = points[i], b = points[(i + 1) % n];
    const int pieces = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
    for (int k = 0; k < pieces; ++k) out.push_back(a + (b - a) * (k / double(pieces)));
  }
  if (!closed && n > 0) out.push_back(points.back());
  return out;
}

// The image panel: camera pixels scaled by `scale` and shifted right by `x0`.
struct ImagePanel {
  const Camera& camera;
  double scale;
  double x0;
  Polygon2 frame;  // the image's area, in camera pixels

  std::optional<Vec2> toPanel(const Vec2& ground_vehicle) const {
    const auto px = camera.projectGround(ground_vehicle);
    if (!px) return std::nullopt;
    return Vec2(x0 + (px->x() + 0.5) * scale, (px->y() + 0.5) * scale);
  }
  Vec2 pixelToPanel(const Vec2& px) const { return Vec2(x0 + (px.x() + 0.5) * scale, (px.y() + 0.5) * scale); }
};

// The landmarks in view: what stands as a bar from its base to its top, one diameter wide (at
// least 3 px), a flat mark as a ring; a dot at the base, the id beside it.
void drawLandmarks(render::Canvas& canvas, const ImagePanel& panel, const PredictedObject& view) {
  using render::Rgb;
  for (const PredictedLandmark& l : view.landmarks) {
    const Vec2 base = panel.pixelToPanel(l.image_base), top = panel.pixelToPanel(l.image_top);
    const double width = std::max(3.0, l.width_px * panel.scale);
    const Rgb colour = l.kind == "tree" ? Rgb{60, 110, 30} : Rgb{30, 30, 110};
    if (l.height_m > 0) {
      canvas.polyline({base, top}, render::Style{std::nullopt, colour, width, 0.85, false});
    } else {
      canvas.circle(base, std::max(3.0, width / 2), render::Style{std::nullopt, colour, 2.0, 1.0, false});
    }
    canvas.circle(base, 2.5, render::Style{Rgb{255, 255, 255}, colour, 1.0, 1.0, false});
    render::TextStyle text;
    text.size_px = 11;
    text.color = colour;
    text.halo = Rgb{255, 255, 255};
    text.anchor = render::Anchor::Start;
    canvas.text(base + Vec2(width / 2 + 3, -3), l.id, text);
  }
}

std::vector<Vec2> projectAll(const ImagePanel& panel, const std::vector<Vec2>& ground) {
  std::vector<Vec2> out;
  for (const Vec2& g : ground) {
    if (const auto p = panel.toPanel(g)) out.push_back(*p);
  }
  return out;
}

}  // namespace

render::Canvas renderPrediction(const Map& map, const Prediction& prediction, const Camera& camera,
                                const PredictionPictureOptions& options) {
  options.validate();
  const int height = options.panel_px;
  const double scale = height / static_cast<double>(camera.height());
  const int image_w = static_cast<int>(std::lround(camera.width() * scale));
  const int map_w = height;
  const int gap = 16;
  render::Canvas canvas(map_w + gap + image_w, height + 36, Rgb{255, 255, 255});

  // ---- left: the map around the vehicle, the footprint, the segments in the world -------------
  Box2 window;
  window.extend(prediction.pose.translation());
  for (const Vec2& p : prediction.footprint_world) window.extend(p);
  window.min().array() -= options.map_margin_m;
  window.max().array() += options.map_margin_m;
  const render::View view(window, map_w, height, 0.0);
  canvas.polygon({{0, 0}, {double(map_w), 0}, {double(map_w), double(height)}, {0, double(height)}},
                 Style{groundColor(map), std::nullopt, 1.0, 1.0, false});
  const Polygon2 window_ring{window.min(), {window.max().x(), window.min().y()}, window.max(), {window.min().x(), window.max().y()}};
  drawMapLayers(canvas, view, map, map.roadsMeeting(window_ring), map.intersectionsMeeting(window_ring), true);
  std::vector<Vec2> footprint_px;
  for (const Vec2& p : prediction.footprint_world) footprint_px.push_back(view.toPixel(p));
  canvas.polygon(footprint_px, Style{kFootprintColour, Rgb{160, 120, 0}, 1.5, 0.35, false});
  for (const Segment2& s : prediction.segments_world) {
    canvas.polyline({view.toPixel(s.a), view.toPixel(s.b)}, Style{std::nullopt, kSegmentColour, 3.0, 1.0, false});
  }
  // The vehicle: an arrow at the pose.
  const Pose2& pose = prediction.pose;
  const double body = std::max(0.8, 12.0 / view.pixelsPerMetre());
  canvas.polygon({view.toPixel(pose.transform(Vec2(body, 0))), view.toPixel(pose.transform(Vec2(-body * 0.6, body * 0.6))),
                  view.toPixel(pose.transform(Vec2(-body * 0.3, 0))), view.toPixel(pose.transform(Vec2(-body * 0.6, -body * 0.6)))},
                 Style{Rgb{200, 20, 20}, Rgb{255, 255, 255}, 1.5, 1.0, false});

  // ---- right: the camera's image plane ------------------------------------------------------
  const double x0 = map_w + gap;
  const ImagePanel panel{camera, scale, x0,
                         {{-0.5, -0.5}, {camera.width() - 0.5, -0.5}, {camera.width() - 0.5, camera.height() - 0.5}, {-0.5, camera.height() - 0.5}}};
  std::vector<Vec2> frame_px;
  for (const Vec2& p : panel.frame) frame_px.push_back(panel.pixelToPanel(p));
  // Ground everywhere, then the sky above the horizon (the images of far-away ground points).
  canvas.polygon(frame_px, Style{groundColor(map), std::nullopt, 1.0, 1.0, false});
  std::vector<Vec2> horizon;
  for (int deg = -179; deg <= 179; ++deg) {
    const double a = degToRad(deg);
    const auto px = camera.project(Vec3(1e5 * std::cos(a), 1e5 * std::sin(a), 0.0));
    if (px) horizon.push_back(*px);
  }
  std::sort(horizon.begin(), horizon.end(), [](const Vec2& a, const Vec2& b) { return a.x() < b.x(); });
  if (horizon.size() >= 2) {
    Polygon2 sky = horizon;
    sky.push_back(Vec2(horizon.back().x(), -1e4));
    sky.push_back(Vec2(horizon.front().x(), -1e4));
    for (const Polygon2& piece : intersectPolygons(sky, panel.frame)) {
      std::vector<Vec2> px;
      for (const Vec2& p : piece) px.push_back(panel.pixelToPanel(p));
      canvas.polygon(px, Style{Rgb{170, 205, 240}, std::nullopt, 1.0, 1.0, false});
    }
  }
  // Road regions, clipped to the image.
  for (const PredictedRegion& region : prediction.view.regions) {
    for (const Polygon2& ring : region.vehicle) {
      std::vector<Vec2> image;
      for (const Vec2& g : densify(ring, true, 0.25)) {
        if (const auto px = camera.projectGround(g)) image.push_back(*px);
      }
      if (image.size() < 3) continue;
      for (const Polygon2& piece : intersectPolygons(image, panel.frame)) {
        std::vector<Vec2> px;
        for (const Vec2& p : piece) px.push_back(panel.pixelToPanel(p));
        canvas.polygon(px, Style{rgbOf(region.rgb), Rgb{90, 90, 90}, 1.0, 1.0, false});
      }
    }
  }
  // Interest segments, bold and labelled.
  for (const InterestSegment& s : prediction.view.segments) {
    const std::vector<Vec2> line = projectAll(panel, densify({s.vehicle.a, s.vehicle.b}, false, 0.25));
    canvas.polyline(line, Style{std::nullopt, kSegmentColour, 3.5, 1.0, false});
    const auto mid = panel.toPanel(s.vehicle.pointAt(0.5));
    if (mid) {
      TextStyle text;
      text.size_px = 11;
      text.color = Rgb{120, 40, 0};
      text.halo = Rgb{255, 255, 255};
      canvas.text(*mid + Vec2(0, -6), s.id, text);
    }
  }
  drawLandmarks(canvas, panel, prediction.view);
  // The image panel's frame hides whatever spilled past the image.
  canvas.polygon({{x0 - gap, 0}, {x0, 0}, {x0, double(height)}, {x0 - gap, double(height)}},
                 Style{Rgb{255, 255, 255}, std::nullopt, 1.0, 1.0, false});
  canvas.polygon(frame_px, Style{std::nullopt, Rgb{40, 40, 40}, 1.5, 1.0, false});

  // ---- captions, below both panels; the map may have spilled there --------------------------
  canvas.polygon({{0, double(height)}, {double(canvas.width()), double(height)}, {double(canvas.width()), double(canvas.height())},
                  {0, double(canvas.height())}},
                 Style{Rgb{255, 255, 255}, std::nullopt, 1.0, 1.0, false});
  render::drawScaleBarAndNorthArrow(canvas, view, 100.0, Box2(Vec2(0, 0), Vec2(map_w, height)));
  TextStyle caption;
  caption.size_px = 13;
  caption.anchor = Anchor::Start;
  char text[200];
  std::snprintf(text, sizeof text, "map: pose (%.1f, %.1f), heading %.0f deg; footprint yellow", pose.x(), pose.y(),
                radToDeg(pose.heading()));
  canvas.text(Vec2(4, height + 24), text, caption);
  const std::size_t objects = prediction.view.regions.size(), segments = prediction.view.segments.size();
  std::snprintf(text, sizeof text, "view: %s %dx%d, %zu object%s, %zu segment%s", std::string(toString(camera.model())).c_str(),
                camera.width(), camera.height(), objects, objects == 1 ? "" : "s", segments, segments == 1 ? "" : "s");
  canvas.text(Vec2(x0, height + 24), text, caption);
  return canvas;
}

}  // namespace mapnav
