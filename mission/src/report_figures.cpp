// The report's figures, which reportHtml (report.cpp) places in the page: the map with the planned
// route, the true, estimated and odometry-only trajectories, the GNSS fixes and where Vision failed;
// and the plots of the errors over time, with the frames where Vision failed or the mission halted
// shaded and ticks where the along-road position was fixed. Each is drawn on a render::Canvas and
// inlined as an <svg> element.
#include "report_internal.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "mapnav/core/strprintf.h"
#include "mapnav/map/map_render.h"

namespace mapnav {

namespace {

using render::Rgb;
using detail::escape, detail::kFailureColor, detail::kHaltColor;

// A Canvas as an inline <svg> element: no XML prologue, scaled to the page's width, with an id.
std::string inlineSvg(const render::Canvas& canvas, const std::string& id, const std::string& title) {
  std::string svg = canvas.toSvg();
  const std::size_t at = svg.find("<svg ");
  svg = svg.substr(at == std::string::npos ? 0 : at);
  svg.insert(5, "id=\"" + id + "\" class=\"figure\" role=\"img\" aria-label=\"" + escape(title) + "\" ");
  return svg;
}

double framePeriod(const MissionRun& run) {
  if (run.frames.size() < 2) return 0.5;
  return (run.frames.back().t - run.frames.front().t) / static_cast<double>(run.frames.size() - 1);
}

// ---- the plots

struct Series {
  std::string name;
  Rgb color;
  std::vector<double> values;  // one per frame; NaN: none
};

// A time plot of `series` over the run's frames, with failed frames shaded red and halted ones pink.
// A tick under a plot at one frame's time: what the Map module's along-road position came from.
struct FrameMark {
  double t;
  Rgb color;
};

std::string plot(const MissionRun& run, const std::string& id, const std::string& title, const std::string& unit,
                 const std::vector<Series>& series, int width, const std::vector<FrameMark>& marks = {}) {
  const int height = 210;
  const double left = 64, right = width - 16.0, top = 28, bottom = height - 34.0;
  render::Canvas canvas(width, height, Rgb{255, 255, 255});
  double t0 = run.frames.empty() ? 0.0 : run.frames.front().t;
  double t1 = run.frames.empty() ? 1.0 : run.frames.back().t;
  if (t1 <= t0) t1 = t0 + 1.0;
  double lo = 0, hi = 0;
  for (const Series& s : series) {
    for (double v : s.values) {
      if (std::isfinite(v)) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    }
  }
  if (hi - lo < 1e-9) hi = lo + 1.0;
  const double step_y = render::niceScaleLength((hi - lo) / 4.0);
  lo = std::floor(lo / step_y) * step_y;
  hi = std::ceil(hi / step_y) * step_y;
  auto px = [&](double t, double v) {
    return Vec2(left + (t - t0) / (t1 - t0) * (right - left), bottom - (v - lo) / (hi - lo) * (bottom - top));
  };
  // Failures and halts under everything.
  const double period = framePeriod(run);
  for (const FrameRecord& f : run.frames) {
    if (f.vision_ok && !f.halted) continue;
    render::Style band;
    band.fill = f.vision_ok ? kHaltColor : kFailureColor;
    band.opacity = f.vision_ok ? 0.5 : 0.35;
    const double a = std::max(t0, f.t - period / 2), b = std::min(t1, f.t + period / 2);
    canvas.polygon({px(a, lo), px(b, lo), px(b, hi), px(a, hi)}, band);
  }
  render::Style grid;
  grid.stroke = Rgb{225, 225, 225};
  render::TextStyle tick;
  tick.size_px = 8;
  tick.color = Rgb{80, 80, 80};
  tick.anchor = render::Anchor::End;
  for (double v = lo; v <= hi + step_y / 2; v += step_y) {
    canvas.polyline({px(t0, v), px(t1, v)}, grid);
    canvas.text(px(t0, v) + Vec2(-6, 4), strprintf(step_y < 0.01 ? "%.3f" : step_y < 0.1 ? "%.2f" : "%.1f", v), tick);
  }
  const double step_t = render::niceScaleLength((t1 - t0) / 8.0);
  tick.anchor = render::Anchor::Middle;
  for (double t = std::ceil(t0 / step_t) * step_t; t <= t1 + 1e-9; t += step_t) {
    canvas.polyline({px(t, lo), px(t, hi)}, grid);
    canvas.text(px(t, lo) + Vec2(0, 14), strprintf("%g", t), tick);
  }
  render::Style zero;
  zero.stroke = Rgb{120, 120, 120};
  if (lo < 0 && hi > 0) canvas.polyline({px(t0, 0), px(t1, 0)}, zero);
  render::Style frame;
  frame.stroke = Rgb{60, 60, 60};
  canvas.polygon({px(t0, lo), px(t1, lo), px(t1, hi), px(t0, hi)}, frame);
  for (const FrameMark& m : marks) {
    render::Style tick_style;
    tick_style.stroke = m.color;
    tick_style.stroke_width_px = 2.0;
    canvas.polyline({px(m.t, lo), px(m.t, lo) + Vec2(0, -7)}, tick_style);
  }
  for (const Series& s : series) {
    std::vector<Vec2> points;
    render::Style line;
    line.stroke = s.color;
    line.stroke_width_px = 1.5;
    for (std::size_t i = 0; i < run.frames.size() && i < s.values.size(); ++i) {
      if (std::isfinite(s.values[i])) {
        points.push_back(px(run.frames[i].t, s.values[i]));
      } else if (!points.empty()) {
        canvas.polyline(points, line);
        points.clear();
      }
    }
    canvas.polyline(points, line);
  }
  render::TextStyle heading;
  heading.size_px = 10;
  heading.bold = true;
  heading.anchor = render::Anchor::Start;
  canvas.text(Vec2(left, 16), title + " [" + unit + "]", heading);
  render::TextStyle key = heading;
  key.bold = false;
  key.size_px = 9;
  double x = right;
  key.anchor = render::Anchor::End;
  for (auto it = series.rbegin(); it != series.rend(); ++it) {
    key.color = it->color;
    canvas.text(Vec2(x, 16), it->name, key);
    x -= 9.0 * it->name.size() + 24;  // about the text's width and a gap
  }
  tick.anchor = render::Anchor::Middle;
  canvas.text(Vec2((left + right) / 2, height - 4.0), "mission time [s]", tick);
  return inlineSvg(canvas, id, title);
}

}  // namespace

// ---- the map

std::string detail::mapFigure(const MissionRun& run, const Map& map, const ReportOptions& options) {
  const std::vector<Vec2> truth = track(run, &FrameRecord::truth);
  const std::vector<Vec2> estimate = track(run, &FrameRecord::estimate);
  const std::vector<Vec2> odometry = track(run, &FrameRecord::odometry_only);
  Box2 box;
  std::vector<std::pair<Vec2, double>> gnss;  // the fixes and their sigma
  for (const FrameRecord& f : run.frames)
    if (f.gnss) gnss.emplace_back(*f.gnss, f.gnss_sigma_m);
  for (const auto* line : {&run.route.line.points(), &truth, &estimate, &odometry}) {
    for (const Vec2& p : *line) box.extend(p);
  }
  for (const auto& [p, sigma] : gnss) box.extend(p);
  box.extend(run.start.translation());
  box.extend(run.goal.translation());
  const Vec2 pad(15.0, 15.0);  // the roads around the route
  box = Box2(box.min() - pad, box.max() + pad);
  // The figure's height follows the route's shape within 300..640 px (a long north-south route would
  // fill the page); the view centres the route and shows more map around it.
  const double aspect = box.sizes().y() / std::max(box.sizes().x(), 1.0);
  const int height = static_cast<int>(std::clamp(options.figure_width_px * aspect, 300.0, 640.0));
  const render::View view(box, options.figure_width_px, height, 24.0);
  render::Canvas canvas(view.width(), view.height(), groundColor(map));
  std::vector<const Road*> roads;
  std::vector<const Intersection*> intersections;
  for (const Road& r : map.roads()) roads.push_back(&r);
  for (const Intersection& x : map.intersections()) intersections.push_back(&x);
  drawMapLayers(canvas, view, map, roads, intersections, true);

  auto pixels = [&](const std::vector<Vec2>& world) {
    std::vector<Vec2> px;
    px.reserve(world.size());
    for (const Vec2& p : world) px.push_back(view.toPixel(p));
    return px;
  };
  render::Style route;
  route.stroke = kRouteColor;
  route.stroke_width_px = 10;
  route.opacity = 0.6;
  canvas.polyline(pixels(run.route.line.points()), route);
  render::Style odo;
  odo.stroke = kOdometryColor;
  odo.stroke_width_px = 2;
  odo.dashed = true;
  canvas.polyline(pixels(odometry), odo);
  render::Style tru;
  tru.stroke = kTruthColor;
  tru.stroke_width_px = 2.5;
  canvas.polyline(pixels(truth), tru);
  render::Style est;
  est.stroke = kEstimateColor;
  est.stroke_width_px = 1.5;
  canvas.polyline(pixels(estimate), est);
  // GNSS fixes: a ring of radius 1 sigma (at least 3 px) about each.
  render::Style fix;
  fix.stroke = kGnssColor;
  fix.stroke_width_px = 1.5;
  for (const auto& [p, sigma] : gnss) canvas.circle(view.toPixel(p), std::max(3.0, sigma * view.pixelsPerMetre()), fix);
  // Where Vision failed: on the truth when known, else on the estimate.
  render::Style fail;
  fail.stroke = kFailureColor;
  fail.stroke_width_px = 2;
  for (const FailureRun& f : failureRuns(run)) {
    const FrameRecord& r = run.frames[f.first];
    canvas.circle(view.toPixel(r.truth ? r.truth->translation() : r.estimate.translation()), 7, fail);
  }
  render::Style start;
  start.fill = Rgb{0, 170, 0};
  start.stroke = Rgb{255, 255, 255};
  start.stroke_width_px = 2;
  canvas.circle(view.toPixel(run.start.translation()), 7, start);
  render::Style goal = start;
  goal.fill = Rgb{200, 0, 160};
  canvas.circle(view.toPixel(run.goal.translation()), 7, goal);
  render::TextStyle label;
  label.size_px = 11;
  label.bold = true;
  label.halo = Rgb{255, 255, 255};
  label.anchor = render::Anchor::Start;
  canvas.text(view.toPixel(run.start.translation()) + Vec2(10, -8), "start", label);
  canvas.text(view.toPixel(run.goal.translation()) + Vec2(10, -8), "goal", label);
  render::drawScaleBarAndNorthArrow(canvas, view);
  return inlineSvg(canvas, "map-svg", "the map with the planned route and the trajectories");
}

// ---- the errors over time

std::string detail::errorPlots(const MissionRun& run, const ReportOptions& options) {
  if (!run.metrics.has_truth) {
    return "<p class=\"note\">The log has no ground truth: the errors were not measured.</p>\n";
  }
  auto values = [&](auto get) {
    std::vector<double> v;
    for (const FrameRecord& f : run.frames) v.push_back(f.truth ? get(f) : std::numeric_limits<double>::quiet_NaN());
    return v;
  };
  constexpr double kDeg = 180.0 / 3.14159265358979323846;
  const int w = options.figure_width_px;
  std::string out;
  std::vector<FrameMark> cues;  // what fixed the along-road position, frame by frame
  for (const FrameRecord& f : run.frames) {
    if (f.along_cue != AlongCue::None) {
      cues.push_back({f.t, f.along_cue == AlongCue::Landmark ? kLandmarkCueColor : kIntersectionCueColor});
    }
  }
  out += plot(run, "plot-position", "Estimate error across and along the road", "m",
              {{"lateral", kEstimateColor, values([](const FrameRecord& f) { return f.error.lateral_m; })},
               {"along", kAlongColor, values([](const FrameRecord& f) { return f.error.along_m; })}},
              w, cues);
  out += plot(run, "plot-heading", "Estimate heading error", "deg",
              {{"heading", kEstimateColor, values([&](const FrameRecord& f) { return f.error.heading_rad * kDeg; })}}, w);
  out += plot(run, "plot-distance", "Position error: estimate and odometry alone", "m",
              {{"estimate", kEstimateColor, values([](const FrameRecord& f) { return f.error.distance_m; })},
               {"odometry only", kOdometryColor, values([](const FrameRecord& f) { return f.odometry_error.distance_m; })}},
              w);
  return out;
}

}  // namespace mapnav
