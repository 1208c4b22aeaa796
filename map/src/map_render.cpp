#include "mapnav/map/map_render.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace mapnav {

using render::Anchor;
using render::Rgb;
using render::Style;
using render::TextStyle;

const OptionTable<MapRenderOptions>& mapRenderOptionTable() {
  using O = MapRenderOptions;
  static const OptionTable<O> table =
      OptionTable<O>("MapRenderOptions")
          .field("width_px", &O::width_px, inRange(64, 20000), "picture width; the height follows from the map's aspect")
          .field("margin_px", &O::margin_px, atLeast(0), "free border around the map")
          .field("labels", &O::labels, "draw road and intersection ids")
          .field("title", &O::title, "draw the map's name at the top")
          .check("margin_px", [](const O& o) { return o.margin_px * 2 < o.width_px; }, "< width_px / 2");
  return table;
}

void MapRenderOptions::validate() const { mapRenderOptionTable().validate(*this); }

namespace {

Rgb toRgb(const Vec3& c) {
  auto byte = [](double v) { return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L)); };
  return {byte(c.x()), byte(c.y()), byte(c.z())};
}

Rgb shade(Rgb c, double factor) {
  auto f = [&](std::uint8_t v) { return static_cast<std::uint8_t>(std::clamp(v * factor, 0.0, 255.0)); };
  return {f(c.r), f(c.g), f(c.b)};
}

std::vector<Vec2> toPixels(const render::View& view, const std::vector<Vec2>& world) {
  std::vector<Vec2> out;
  out.reserve(world.size());
  for (const Vec2& p : world) out.push_back(view.toPixel(p));
  return out;
}

// The shoulder colour most roads have, lightened: the picture's ground.
Rgb lightGround(const Map& map) {
  std::map<std::string, std::size_t> votes;
  for (const Road& r : map.roads()) {
    ++votes[r.left];
    ++votes[r.right];
  }
  const auto best = std::max_element(votes.begin(), votes.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  if (best != votes.end()) {
    if (const Appearance* a = map.findSurface(best->first)) {
      // Lighter than the real thing, so that roads and labels stand out.
      const Rgb c = toRgb(a->rgb);
      auto lighten = [](std::uint8_t v) { return static_cast<std::uint8_t>(v + (255 - v) * 0.55); };
      return {lighten(c.r), lighten(c.g), lighten(c.b)};
    }
  }
  return {236, 240, 228};
}

}  // namespace

void drawMapLayers(render::Canvas& canvas, const render::View& view, const Map& map,
                   const std::vector<const Road*>& roads, const std::vector<const Intersection*>& intersections,
                   bool labels) {
  const double ppm = view.pixelsPerMetre();
  // Lower layers first, so that a bridge is drawn over what it crosses (stable: map order within).
  std::vector<const Road*> by_layer = roads;
  std::stable_sort(by_layer.begin(), by_layer.end(), [](const Road* a, const Road* b) { return a->layer < b->layer; });
  // Shoulders: a band of each shoulder's colour along each side, so that a dirt or brick edge shows
  // (none along a tunnel: its sides are underground).
  for (const Road* road : by_layer) {
    if (road->structure == RoadStructure::Tunnel) continue;
    for (const bool left : {true, false}) {
      const Appearance* a = map.findSurface(left ? road->left : road->right);
      if (a == nullptr) continue;
      const Polyline2 outer = road->centerline.offset((left ? 1 : -1) * (road->width / 2 + 1.0));
      const Polyline2& inner = left ? map.leftEdge(*road) : map.rightEdge(*road);
      std::vector<Vec2> ring = inner.points();
      ring.insert(ring.end(), outer.points().rbegin(), outer.points().rend());
      Style style;
      style.fill = toRgb(a->rgb);
      style.opacity = 0.55;
      canvas.polygon(toPixels(view, ring), style);
    }
  }
  // Paved areas in their surface colours with a dark outline: tunnels faint with a dashed outline,
  // then the ground's roads, the intersections, and bridges last on a dark casing.
  auto pave = [&](const Road& road) {
    const Appearance* a = map.findSurface(road.surface);
    Style style;
    style.fill = a ? toRgb(a->rgb) : Rgb{180, 180, 180};
    style.stroke = shade(*style.fill, 0.45);
    style.stroke_width_px = 1.2;
    if (road.structure == RoadStructure::Tunnel) {
      style.opacity = 0.4;
      style.stroke = Rgb{40, 40, 40};
      style.stroke_width_px = 1.6;
      style.dashed = true;
    }
    if (road.structure == RoadStructure::Bridge) {
      Style casing;
      casing.fill = Rgb{45, 45, 50};
      const double outer = road.width / 2 + std::max(0.6, 2.5 / ppm);  // at least 2.5 px of casing
      std::vector<Vec2> ring = road.centerline.offset(outer).points();
      const std::vector<Vec2> right = road.centerline.offset(-outer).points();
      ring.insert(ring.end(), right.rbegin(), right.rend());
      canvas.polygon(toPixels(view, ring), casing);
    }
    canvas.polygon(toPixels(view, map.roadPolygon(road)), style);
  };
  for (const Road* road : by_layer) {
    if (road->structure == RoadStructure::Tunnel) pave(*road);
  }
  for (const Road* road : by_layer) {
    if (road->structure == RoadStructure::None) pave(*road);
  }
  for (const Intersection* x : intersections) {
    const auto ends = map.roadsAt(x->id);
    const Appearance* a = ends.empty() ? nullptr : map.findSurface(ends.front().road->surface);
    Style style;
    style.fill = a ? toRgb(a->rgb) : Rgb{180, 180, 180};
    if (x->shape) {
      style.stroke = shade(*style.fill, 0.45);
      style.stroke_width_px = 1.2;
    }
    canvas.polygon(toPixels(view, map.intersectionShape(*x)), style);
  }
  for (const Road* road : by_layer) {
    if (road->structure == RoadStructure::Bridge) pave(*road);
  }
  // Centre lines, dashed, so that direction and curvature read at a glance.
  for (const Road* road : roads) {
    Style style;
    style.stroke = Rgb{255, 255, 255};
    style.stroke_width_px = 1.0;
    style.dashed = true;
    canvas.polyline(toPixels(view, road->centerline.points()), style);
  }
  if (!labels) return;
  // Ids, placed greedily without overlap (intersections first, then roads, each in map order): on a
  // dense map (an OSM import of hundreds of roads) a label that would cover another is left out
  // rather than drawn illegibly. The box is the text's extent in the PNG font (about 1 em a character).
  const double size = std::clamp(ppm * 1.6, 10.0, 15.0);
  std::vector<Box2> placed;
  auto place = [&](const Vec2& at, const std::string& label, Anchor anchor) {
    const double width = 1.0 * size * static_cast<double>(label.size());
    const double x0 = anchor == Anchor::Start ? at.x() : at.x() - width / 2;
    const Box2 box(Vec2(x0 - 2, at.y() - size), Vec2(x0 + width + 2, at.y() + 0.3 * size));
    for (const Box2& other : placed) {
      if (other.intersects(box)) return false;
    }
    placed.push_back(box);
    return true;
  };
  for (const Intersection* x : intersections) {
    Style dot;
    dot.fill = Rgb{200, 30, 30};
    canvas.circle(view.toPixel(x->position), 3.0, dot);
    const Vec2 at = view.toPixel(x->position) + Vec2(6, -6);
    const std::string label = x->id + " " + std::string(toString(x->kind));
    if (!place(at, label, Anchor::Start)) continue;
    TextStyle text;
    text.size_px = size;
    text.color = Rgb{150, 20, 20};
    text.bold = true;
    text.halo = Rgb{255, 255, 255};
    text.anchor = Anchor::Start;
    canvas.text(at, label, text);
  }
  for (const Road* road : roads) {
    const Vec2 at = view.toPixel(road->centerline.pointAt(road->centerline.length() / 2));
    if (!place(at, road->id, Anchor::Middle)) continue;
    TextStyle text;
    text.size_px = size;
    text.color = Rgb{20, 40, 120};
    text.halo = Rgb{255, 255, 255};
    canvas.text(at, road->id, text);
  }
}

namespace {

// A rectangle `half_length` px either side of `center` along the unit `direction` and `half_width`
// px across it (pixel coordinates).
std::vector<Vec2> bar(const Vec2& center, const Vec2& direction, double half_length, double half_width) {
  const Vec2 along = direction * half_length, across = Vec2(-direction.y(), direction.x()) * half_width;
  return {center - along - across, center + along - across, center + along + across, center - along + across};
}

// The direction (pixels, unit) of the road a landmark stands beside, at its nearest point; east
// when the map has no road.
Vec2 roadDirectionPx(const render::View& view, const Map& map, const Landmark& landmark) {
  const Road* road = map.roadBeside(landmark);
  if (road == nullptr) return Vec2(1, 0);
  const Vec2 tangent = road->centerline.tangentAt(road->centerline.project(landmark.position).arc_length);
  const Vec2 px = view.toPixel(landmark.position + tangent) - view.toPixel(landmark.position);
  return px.norm() > 0 ? Vec2(px / px.norm()) : Vec2(1, 0);
}

void drawLandmark(render::Canvas& canvas, const render::View& view, const Map& map, const Landmark& l) {
  const double ppm = view.pixelsPerMetre();
  const Vec2 at = view.toPixel(l.position);
  const double r = l.radius * ppm;
  Style style;
  switch (l.kind) {
    case LandmarkKind::Tree: {
      style.fill = kTreeCrown;
      style.stroke = shade(kTreeCrown, 0.6);
      canvas.circle(at, std::max(std::clamp(l.height / 3, 1.0, 4.0) * ppm, 4.0), style);
      Style trunk;
      trunk.fill = kTreeTrunk;
      canvas.circle(at, std::max(r, 1.5), trunk);
      break;
    }
    case LandmarkKind::Pole:
      style.fill = kPole;
      canvas.circle(at, std::max(r, 2.5), style);
      break;
    case LandmarkKind::Bollard:
      style.fill = kBollard;
      style.stroke = shade(kBollard, 0.55);
      canvas.polygon(bar(at, Vec2(1, 0), std::max(r, 2.5), std::max(r, 2.5)), style);
      break;
    case LandmarkKind::Bench:
      style.fill = kBench;
      canvas.polygon(bar(at, roadDirectionPx(view, map, l), std::max(r, 4.0), std::max(0.25 * ppm, 1.5)), style);
      break;
    case LandmarkKind::Manhole:
      style.fill = kManhole;
      style.stroke = shade(kManhole, 0.5);
      style.stroke_width_px = 1.2;
      canvas.circle(at, std::max(r, 3.0), style);
      break;
  }
}

}  // namespace

void drawLandmarks(render::Canvas& canvas, const render::View& view, const Map& map,
                   const std::vector<const Landmark*>& landmarks) {
  // Flat covers first, so that an upright landmark is never hidden under one.
  for (const bool upright : {false, true}) {
    for (const Landmark* l : landmarks) {
      if (isUpright(l->kind) == upright) drawLandmark(canvas, view, map, *l);
    }
  }
}

render::Rgb groundColor(const Map& map) { return lightGround(map); }

MapPicture renderMap(const Map& map, const MapRenderOptions& options) {
  options.validate();
  Box2 world = map.bounds();
  for (const Landmark& l : map.landmarks()) world.extend(l.position);  // one kept far from every road too
  if (world.isEmpty()) world = Box2(Vec2(-10, -10), Vec2(10, 10));
  const double top_band = options.title ? 40.0 : 0.0;
  render::View fit = render::View::fitWidth(world, options.width_px, options.margin_px);
  render::View view(world, options.width_px, fit.height() + static_cast<int>(top_band), options.margin_px + top_band / 2);
  render::Canvas canvas(view.width(), view.height(), groundColor(map));
  std::vector<const Road*> roads;
  for (const Road& r : map.roads()) roads.push_back(&r);
  std::vector<const Intersection*> intersections;
  for (const Intersection& x : map.intersections()) intersections.push_back(&x);
  drawMapLayers(canvas, view, map, roads, intersections, options.labels);
  std::vector<const Landmark*> landmarks;
  for (const Landmark& l : map.landmarks()) landmarks.push_back(&l);
  drawLandmarks(canvas, view, map, landmarks);
  if (options.title) {
    TextStyle title;
    title.size_px = 18;
    title.bold = true;
    title.anchor = Anchor::Start;
    canvas.text(Vec2(options.margin_px, 30), map.name(), title);
  }
  render::drawScaleBarAndNorthArrow(canvas, view);
  return MapPicture{std::move(canvas), view};
}

}  // namespace mapnav
