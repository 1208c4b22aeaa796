#include "mapnav/mission/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/core/json.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/image/png.h"
#include "mapnav/map/geodesy.h"
#include "mapnav/mission/trace.h"
#include "mapnav/render/canvas.h"
#include "report_internal.h"

namespace mapnav {

const OptionTable<ReportOptions>& reportOptionTable() {
  using O = ReportOptions;
  static const OptionTable<O> table =
      OptionTable<O>("ReportOptions")
          .field("max_thumbnails", &O::max_thumbnails, atLeast(2), "thumbnails in the strip at most")
          .field("max_failure_thumbnails", &O::max_failure_thumbnails,
                 "... of them the first frames of vision failures, at most")
          .field("thumbnail_width_px", &O::thumbnail_width_px, inRange(16, 2048),
                 "a thumbnail is the frame shrunk by the whole factor that brings its width nearest to this, px")
          .field("figure_width_px", &O::figure_width_px, inRange(200, 4096),
                 "width of the map picture and of the plots, px")
          .check("max_failure_thumbnails", [](const O& o) { return o.max_failure_thumbnails < o.max_thumbnails; },
                 "< max_thumbnails");
  return table;
}

void ReportOptions::validate() const { reportOptionTable().validate(*this); }

// ---------------------------------------------------------------------------------------------
// The strip's frames

namespace {

// The frame shrunk by a whole factor (box average): the factor that brings the width nearest to
// `width_px`, at least 1.
Image shrink(const Image& rgb, int width_px) {
  const int f = std::max(1, static_cast<int>(std::lround(static_cast<double>(rgb.width) / width_px)));
  if (f == 1) return rgb;
  Image out(rgb.width / f, rgb.height / f, rgb.channels);
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      for (int c = 0; c < rgb.channels; ++c) {
        int sum = 0;
        for (int dy = 0; dy < f; ++dy) {
          for (int dx = 0; dx < f; ++dx) sum += rgb.pixel(x * f + dx, y * f + dy)[c];
        }
        out.pixel(x, y)[c] = static_cast<std::uint8_t>((sum + f * f / 2) / (f * f));
      }
    }
  }
  return out;
}

ReportThumbnail thumbnail(const FrameView& frame, int width_px) {
  ReportThumbnail t;
  t.index = frame.index;
  t.t = frame.t;
  t.width = frame.rgb->width;
  t.height = frame.rgb->height;
  const std::vector<std::uint8_t> png = encodePng(shrink(*frame.rgb, width_px));
  t.png.assign(png.begin(), png.end());
  if (frame.predicted != nullptr) {
    for (const InterestSegment& s : frame.predicted->segments) t.predicted.push_back(s.image);
  }
  if (frame.detected != nullptr) {
    t.vision_ok = frame.detected->status == DetectedObject::Status::Ok;
    t.reason = frame.detected->reason;
    for (const DetectedLine& l : frame.detected->lines) {
      if (!l.frame_edge) t.detected.push_back({l.image, l.label.value_or("")});
    }
  }
  return t;
}

}  // namespace

ReportFrames::ReportFrames(const ReportOptions& options) : options_(options) { options_.validate(); }

void ReportFrames::add(const FrameView& frame) {
  if (frame.rgb == nullptr) return;
  const bool failed = frame.detected != nullptr && frame.detected->status == DetectedObject::Status::Failed;
  const bool onset = failed && !previous_failed_;
  previous_failed_ = failed;
  if (onset && failures_.size() < options_.max_failure_thumbnails) {
    failures_.push_back(thumbnail(frame, options_.thumbnail_width_px));
    return;
  }
  if (frame.index % stride_ != 0) return;
  regular_.push_back(thumbnail(frame, options_.thumbnail_width_px));
  const std::size_t cap = options_.max_thumbnails - options_.max_failure_thumbnails;
  while (regular_.size() > cap) {  // every other one goes: the strip stays evenly spaced
    stride_ *= 2;
    std::erase_if(regular_, [&](const ReportThumbnail& t) { return t.index % stride_ != 0; });
  }
}

std::vector<ReportThumbnail> ReportFrames::thumbnails() const {
  std::vector<ReportThumbnail> all = regular_;
  all.insert(all.end(), failures_.begin(), failures_.end());
  std::sort(all.begin(), all.end(), [](const ReportThumbnail& a, const ReportThumbnail& b) { return a.index < b.index; });
  return all;
}

// ---------------------------------------------------------------------------------------------
// HTML pieces

namespace {

using render::Rgb;
using detail::errorPlots, detail::escape, detail::FailureRun, detail::failureRuns, detail::mapFigure, detail::track;
using detail::kEstimateColor, detail::kFailureColor, detail::kGnssColor, detail::kOdometryColor, detail::kRouteColor,
    detail::kTruthColor;

std::string hex(const Rgb& c) {
  char s[8];
  std::snprintf(s, sizeof s, "#%02x%02x%02x", c.r, c.g, c.b);
  return s;
}

std::string base64(const std::string& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      v = (v << 8) | (k < n ? static_cast<std::uint8_t>(bytes[i + k]) : 0u);
    }
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kAlphabet[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

// ---- the legends

std::string swatch(const Rgb& color, double width, bool dashed, const std::string& text, const std::string& cls) {
  return "<span class=\"key " + cls + "\"><svg width=\"34\" height=\"10\"><line x1=\"2\" y1=\"5\" x2=\"32\" y2=\"5\" stroke=\"" +
         hex(color) + "\" stroke-width=\"" + strprintf("%.1f", width) + "\"" +
         (dashed ? " stroke-dasharray=\"6 4\"" : "") + "/></svg>" + escape(text) + "</span>";
}

// ---- the strip

std::string thumbnailFigure(const ReportThumbnail& t, int width_px) {
  const double scale = static_cast<double>(t.width) / width_px;  // viewBox units per displayed pixel
  const int display_h = static_cast<int>(std::lround(t.height / scale));
  std::string out = "<figure class=\"thumb" + std::string(t.vision_ok ? "" : " failed") + "\" id=\"frame-" +
                    std::to_string(t.index) + "\">";
  out += "<svg class=\"frame\" width=\"" + std::to_string(width_px) + "\" height=\"" + std::to_string(display_h) +
         "\" viewBox=\"0 0 " + std::to_string(t.width) + " " + std::to_string(t.height) + "\">";
  out += "<image x=\"0\" y=\"0\" width=\"" + std::to_string(t.width) + "\" height=\"" + std::to_string(t.height) +
         "\" preserveAspectRatio=\"none\" href=\"data:image/png;base64," + base64(t.png) + "\"/>";
  auto line = [&](const Segment2& s, const char* cls, double px) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "<line class=\"%s\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke-width=\"%.2f\"/>", cls,
                  s.a.x(), s.a.y(), s.b.x(), s.b.y(), px * scale);
    out += text;
  };
  for (const Segment2& s : t.predicted) line(s, "predicted", 1.0);
  std::size_t matched = 0;
  for (const ReportThumbnail::Line& l : t.detected) {
    if (l.label.empty()) line(l.image, "unmatched", 1.0);
  }
  for (const ReportThumbnail::Line& l : t.detected) {
    if (l.label.empty()) continue;
    ++matched;
    line(l.image, "matched", 3.0);
    const Vec2 mid = 0.5 * (l.image.a + l.image.b);
    char text[160];
    std::snprintf(text, sizeof text, "<text class=\"label\" x=\"%.1f\" y=\"%.1f\" font-size=\"%.1f\">", mid.x(), mid.y(),
                  9.0 * scale);
    out += text + escape(l.label) + "</text>";
  }
  out += "</svg><figcaption>frame " + std::to_string(t.index) + ", t " + strprintf("%.1f", t.t) + " s";
  if (t.vision_ok) {
    out += ": " + std::to_string(t.predicted.size()) + " predicted, " + std::to_string(matched) + " of " +
           std::to_string(t.detected.size()) + " lines matched";
  } else {
    out += ": <b>vision failed</b> (" + escape(t.reason) + ")";
  }
  out += "</figcaption></figure>\n";
  return out;
}

// ---- the summary

// "12 frames by intersections, 30 by landmarks, 158 by neither (odometry)".
std::string alongCueText(const MissionRun& run) {
  std::size_t by_lines = 0, by_landmarks = 0;
  for (const FrameRecord& f : run.frames) {
    by_lines += f.along_cue == AlongCue::Intersection ? 1 : 0;
    by_landmarks += f.along_cue == AlongCue::Landmark ? 1 : 0;
  }
  return std::to_string(by_lines) + " frames by intersections, " + std::to_string(by_landmarks) + " by landmarks, " +
         std::to_string(run.frames.size() - by_lines - by_landmarks) + " by neither (odometry)";
}

// The path agreement's row of the summary table (the figures summaryText prints first).
template <typename Row>
void pathAgreementRow(const MissionRun& run, Row&& row) {
  const auto& s = run.metrics.path_agreement;
  if (!s) {
    row("path agreement", "not measured", run.metrics.has_truth ? "" : "no ground truth");
    return;
  }
  const PathAgreementOptions& o = run.path_options;
  auto figure = [](const std::optional<double>& v) { return v ? strprintf("%.3f", *v) : std::string("-"); };
  std::string centre = "no centre line";
  if (s->centre_line_frames > 0)
    centre = "centre line within " + strprintf("%g", o.angle_goal_deg) + " deg in " + std::to_string(s->angle_goal_frames) +
             " of " + std::to_string(s->angle_frames) + ", offset jump <= " + strprintf("%g", o.offset_jump_goal_m) +
             " m in " + std::to_string(s->offset_goal_pairs) + " of " + std::to_string(s->offset_pairs) + " pairs";
  row("path agreement",
      "road found holds >= " + strprintf("%g", 100 * o.inside_goal) + " % of the true future path in " +
          std::to_string(s->inside_goal_frames) + " of " + std::to_string(s->measured) + " measured frames (median " +
          figure(s->median_inside) + ")",
      "covers a median " + figure(s->median_ground_share) + " of the ground in view; " + centre);
}

std::string metricsTable(const MissionRun& run) {
  const MissionMetrics& m = run.metrics;
  std::string out = "<table id=\"metrics-table\">\n";
  auto row = [&](const std::string& name, const std::string& a, const std::string& b = "") {
    out += "<tr><th>" + escape(name) + "</th><td>" + escape(a) + "</td><td>" + escape(b) + "</td></tr>\n";
  };
  out += "<tr><th></th><th>estimate</th><th>odometry only</th></tr>\n";
  if (m.has_truth) {
    auto rmsMax = [&](double rms, double max, const char* unit) {
      return strprintf("%.3f", rms) + " " + unit + " (max " + strprintf("%.3f", max) + ")";
    };
    row("lateral RMS", rmsMax(m.estimate.lateral_rms_m, m.estimate.lateral_max_m, "m"),
        rmsMax(m.odometry_only.lateral_rms_m, m.odometry_only.lateral_max_m, "m"));
    row("along RMS", rmsMax(m.estimate.along_rms_m, m.estimate.along_max_m, "m"),
        rmsMax(m.odometry_only.along_rms_m, m.odometry_only.along_max_m, "m"));
    row("heading RMS", rmsMax(m.estimate.heading_rms_deg, m.estimate.heading_max_deg, "deg"),
        rmsMax(m.odometry_only.heading_rms_deg, m.odometry_only.heading_max_deg, "deg"));
    row("max position error", strprintf("%.3f m", m.estimate.max_error_m), strprintf("%.3f m", m.odometry_only.max_error_m));
    if (m.consistency.frames > 0) {
      const FilterConsistency& c = m.consistency;
      row("true error within 2 sigma", strprintf("along %.1f %%, lateral %.1f %%, heading %.1f %%", 100 * c.within_2sigma_along,
                                                 100 * c.within_2sigma_lateral, 100 * c.within_2sigma_heading) +
                                           (c.nees_frames > 0 ? strprintf("; mean NEES %.2f", c.nees_mean) : std::string()) +
                                           " (a consistent filter: 95.4 %, NEES 3)");
    }
    row("along error 2 m past intersections", strprintf("max %.3f m", m.along_after_intersection_max_m) + " (" +
                                                  std::to_string(m.intersections_checked) + " checked)");
    row("along-road position fixed by", alongCueText(run));
  } else {
    row("errors", "no ground truth", "no ground truth");
  }
  const bool judged_at_arrival = run.mode == "replay" && m.arrived_frame;
  row("reached goal", m.reached_goal ? "yes" : "no",
      judged_at_arrival ? strprintf("%.2f m from it when the Navigator arrived (frame %zu)", m.goal_distance_m, *m.arrived_frame)
                        : strprintf("%.2f m from it at the end", m.goal_distance_m));
  row("estimate at the end", strprintf("%.2f m from the goal", m.estimate_goal_distance_m),
      m.arrived_frame ? "the Navigator arrived at frame " + std::to_string(*m.arrived_frame) : "the Navigator never arrived");
  row("frames", std::to_string(m.frames), strprintf("%.1f s", run.duration_s) + ", " + strprintf("%.1f m driven", run.distance_m));
  row("route", strprintf("%.1f m", run.route.length_m),
      std::to_string(run.route.intersections.size()) + " intersections");
  row("vision failures", std::to_string(m.vision_failures), std::to_string(m.halts) + " halts");
  pathAgreementRow(run, row);
  row("replans", std::to_string(m.replans));
  row("position lost / re-localised", std::to_string(m.lost_frames) + " frames", std::to_string(m.relocalisations) + " times");
  row("integrity: position uncertain / departed from odometry", std::to_string(m.uncertain_frames) + " frames",
      std::to_string(m.departures) + " times");
  if (run.mode == "replay") {
    row("log faults", std::to_string(m.log_faults.total()),
        m.log_faults.total() == 0 ? std::string("none") : escape(logFaultsText(m.log_faults)) + ", skipped or repaired");
  }
  row("loop latency (" + std::to_string(run.image_width) + "x" + std::to_string(run.image_height) + ")",
      strprintf("median %.2f ms", m.latency_ms_median) + strprintf(", p99 %.2f ms", m.latency_ms_p99),
      strprintf("Vision alone: median %.2f ms", m.vision_ms_median));
  row("odometry scale", strprintf("%.4f", run.odometry_scale),
      strprintf("the distance driven measured from the ground on %zu of %zu frames", m.ground_steps_used, m.frames));
  out += "</table>\n";
  return out;
}

// The replayed log's faults, one item each: where (frames.jsonl line, t), what, what was done.
std::string logFaultList(const MissionRun& run) {
  if (run.faults.empty()) return "<p>None: every line of the log was read and used.</p>\n";
  std::string out = "<ul id=\"log-fault-list\">\n";
  for (const LogFault& f : run.faults) {
    out += "<li class=\"" + toString(f.kind) + "\">frames.jsonl line " + std::to_string(f.line) +
           (f.t ? " (t " + strprintf("%.3f", *f.t) + " s)" : std::string()) + ": <b>" + toString(f.kind) + "</b> &mdash; " +
           escape(f.message) + "; " + escape(f.action) + "</li>\n";
  }
  return out + "</ul>\n";
}

std::string failureList(const MissionRun& run) {
  const std::vector<FailureRun> runs = failureRuns(run);
  std::string out;
  if (runs.empty()) {
    out += "<p>None: Vision succeeded on every frame.</p>\n";
  } else {
    out += "<ul id=\"failure-list\">\n";
    for (const FailureRun& f : runs) {
      const FrameRecord &a = run.frames[f.first], &b = run.frames[f.last];
      out += "<li>frame" + std::string(f.first == f.last ? " " : "s ") + std::to_string(a.index) +
             (f.first == f.last ? "" : "&ndash;" + std::to_string(b.index)) + " (t " + strprintf("%.1f", a.t) +
             (f.first == f.last ? "" : "&ndash;" + strprintf("%.1f", b.t)) + " s): " + escape(f.reason) + "</li>\n";
    }
    out += "</ul>\n";
  }
  if (run.ended_by_halt) out += "<p><b>The mission ended in a halt:</b> " + escape(run.outcome) + "</p>\n";
  return out;
}

constexpr const char* kStyle = R"(
body { font-family: sans-serif; margin: 24px auto; max-width: 1000px; color: #222; background: #fff; }
h1 { font-size: 22px; margin-bottom: 4px; }
h2 { font-size: 17px; margin-top: 28px; border-bottom: 1px solid #ccc; }
.outcome { font-size: 15px; }
table { border-collapse: collapse; font-size: 13px; }
th, td { text-align: left; padding: 3px 10px; border-bottom: 1px solid #eee; }
svg.figure { max-width: 100%; height: auto; display: block; margin: 6px 0; border: 1px solid #ddd; }
.legend { font-size: 13px; }
.key { margin-right: 18px; white-space: nowrap; }
.key svg { vertical-align: middle; margin-right: 4px; }
.strip { display: flex; flex-wrap: wrap; gap: 8px; }
figure.thumb { margin: 0; padding: 3px; border: 2px solid #ddd; font-size: 11px; width: min-content; }
figure.thumb.failed { border-color: #dc1e1e; background: #fde8e8; }
figure.thumb svg { display: block; }
line.predicted { stroke: #ffe000; }
line.matched { stroke: #ff2080; }
line.unmatched { stroke: #00e0ff; stroke-dasharray: 6 4; }
text.label { fill: #fff; stroke: #000; stroke-width: 2px; paint-order: stroke; font-family: sans-serif; }
pre#dialogue-text { font-size: 12px; white-space: pre-wrap; max-height: 600px; overflow: auto; background: #f6f6f6; padding: 8px; }
.note { color: #666; }
)";

}  // namespace

std::string reportHtml(const MissionRun& run, const Map& map, const std::vector<ReportThumbnail>& thumbnails,
                       const std::string& dialogue, const ReportOptions& options) {
  options.validate();
  const std::string title = "mapnav " + run.mode + ": " + run.mission;
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" + escape(title) +
                     "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n";
  html += "<h1>" + escape(title) + "</h1>\n";
  html += "<p class=\"outcome\" id=\"outcome\">" + escape(run.outcome) + "</p>\n";
  html += "<p class=\"note\">Pipeline " + escape(run.pipeline) + ", map " + escape(map.name()) +
          (run.log.empty() ? std::string() : ", log " + escape(run.log.string())) + ".</p>\n";

  html += "<section id=\"metrics\">\n<h2>Summary</h2>\n" + metricsTable(run) + "</section>\n";

  html += "<section id=\"map\">\n<h2>Map, planned route and trajectories</h2>\n<p class=\"legend\">";
  html += swatch(kRouteColor, 8, false, "planned route", "route");
  if (run.metrics.has_truth) html += swatch(kTruthColor, 2.5, false, "true", "truth");
  html += swatch(kEstimateColor, 1.5, false, "estimate (Map module)", "estimate");
  html += swatch(kOdometryColor, 2, true, "odometry only", "odometry");
  if (std::any_of(run.frames.begin(), run.frames.end(), [](const FrameRecord& f) { return f.gnss.has_value(); }))
    html += "<span class=\"key\" id=\"key-gnss\"><svg width=\"16\" height=\"16\"><circle cx=\"8\" cy=\"8\" r=\"5\" "
            "fill=\"none\" stroke=\"" + hex(kGnssColor) + "\" stroke-width=\"1.5\"/></svg>GNSS fix (ring: its 1&sigma;)</span>";
  html += "<span class=\"key\"><svg width=\"16\" height=\"16\"><circle cx=\"8\" cy=\"8\" r=\"6\" fill=\"none\" stroke=\"" +
          hex(kFailureColor) + "\" stroke-width=\"2\"/></svg>vision failure</span>";
  html += "</p>\n" + mapFigure(run, map, options) + "</section>\n";

  html += "<section id=\"errors\">\n<h2>Errors over time</h2>\n";
  html += "<p class=\"legend\">Estimate &minus; truth in the road's frame at the true pose (lateral: left positive; "
          "along: forward positive). Red bands: frames where Vision failed; pink: halted. Ticks under the first plot: "
          "frames whose along-road position was fixed by an intersection's lines (grey) or a landmark (orange).</p>\n";
  html += errorPlots(run, options) + "</section>\n";

  html += "<section id=\"failures\">\n<h2>Vision failures and halts</h2>\n" + failureList(run) + "</section>\n";
  if (run.mode == "replay") {
    html += "<section id=\"log-faults\">\n<h2>Faults of the log</h2>\n" + logFaultList(run) + "</section>\n";
  }

  html += "<section id=\"thumbnails\">\n<h2>Frames</h2>\n<p class=\"legend\">" +
          swatch(Rgb{255, 224, 0}, 1, false, "predicted segments", "predicted") +
          swatch(Rgb{255, 32, 128}, 3, false, "detected and matched (label: the predicted segment)", "matched") +
          swatch(Rgb{0, 224, 255}, 1, true, "detected, unmatched", "unmatched") + "</p>\n<div class=\"strip\">\n";
  for (const ReportThumbnail& t : thumbnails) html += thumbnailFigure(t, options.thumbnail_width_px);
  html += "</div>\n</section>\n";

  html += "<section id=\"dialogue\">\n<h2>Dialogue</h2>\n";
  if (dialogue.empty()) {
    html += "<p class=\"note\">No trace was written.</p>\n";
  } else {
    html += "<pre id=\"dialogue-text\">" + escape(dialogue) + "</pre>\n";
  }
  html += "</section>\n</body>\n</html>\n";
  return html;
}

std::string trajectoriesGeoJson(const MissionRun& run, const Map& map) {
  const std::optional<GeoOrigin>& origin = map.data().origin;
  if (!origin) {
    throw InvalidInput("map \"" + map.name() + "\" has no geodetic origin: the trajectories cannot be written as GeoJSON");
  }
  const LocalFrame frame(*origin);
  // As exportGeoJson: [lon, lat], 9 decimals (0.1 mm).
  auto positions = [&](const std::vector<Vec2>& points) {
    Json out = Json::array();
    for (const Vec2& p : points) {
      const LatLon g = frame.toGeodetic(p);
      out.push_back(Json::array({std::round(g.lon * 1e9) / 1e9, std::round(g.lat * 1e9) / 1e9}));
    }
    return out;
  };
  Json features = Json::array();
  auto add = [&](const std::string& name, const std::vector<Vec2>& points) {
    if (points.size() < 2) return;  // a LineString needs two positions
    features.push_back({{"type", "Feature"},
                        {"properties", {{"name", name}, {"mission", run.mission}, {"mode", run.mode}}},
                        {"geometry", {{"type", "LineString"}, {"coordinates", positions(points)}}}});
  };
  add("route", run.route.line.points());
  add("true", track(run, &FrameRecord::truth));
  add("estimate", track(run, &FrameRecord::estimate));
  add("odometry", track(run, &FrameRecord::odometry_only));
  Json fixes = Json::array();
  for (const FrameRecord& f : run.frames)
    if (f.gnss) fixes.push_back(positions({*f.gnss})[0]);
  if (!fixes.empty())
    features.push_back({{"type", "Feature"},
                        {"properties", {{"name", "gnss"}, {"mission", run.mission}, {"mode", run.mode}}},
                        {"geometry", {{"type", "MultiPoint"}, {"coordinates", fixes}}}});
  return dumpJson({{"type", "FeatureCollection"}, {"features", features}});
}

ReportFiles writeReport(const std::filesystem::path& dir, const MissionRun& run, const Map& map,
                        const ReportFrames& frames, const std::string& trace, const std::string& trace_file,
                        const ReportOptions& options) {
  options.validate();
  const std::string dialogue = trace.empty() ? std::string() : traceDialogue(trace, trace_file);
  const std::string html = reportHtml(run, map, frames.thumbnails(), dialogue, options);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw IoError(dir.string() + ": cannot create the report folder: " + ec.message());
  ReportFiles files;
  files.html = dir / "report.html";
  writeFileAtomic(files.html, html);
  if (map.data().origin) {
    files.geojson = dir / "trajectories.geojson";
    writeFileAtomic(*files.geojson, trajectoriesGeoJson(run, map));
  }
  return files;
}

}  // namespace mapnav
