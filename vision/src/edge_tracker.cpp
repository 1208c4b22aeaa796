// The oriented road-edge tracker (Wallace et al. 1985, 3.1-3.2) and the "edge-tracker" pipeline.
#include "mapnav/vision/edge_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include "mapnav/core/error.h"
#include "mapnav/geometry/simplify.h"
#include "mapnav/image/image.h"

namespace mapnav {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
const double kNaN = std::numeric_limits<double>::quiet_NaN();

Vec2 rotateVec(const Vec2& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

/// Perpendicular of an image direction: the direction turned clockwise on screen (up → right).
Vec2 across(const Vec2& d) { return {-d.y(), d.x()}; }

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

/// Distance from p to the polyline, and whether the closest point is interior (not an end point).
double polylineDistance(const std::vector<Vec2>& line, const Vec2& p, bool& interior, Vec2& closest) {
  double best = std::numeric_limits<double>::infinity();
  interior = false;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const Segment2 s{line[i], line[i + 1]};
    const double t = s.closestParameter(p);
    const Vec2 c = s.pointAt(t);
    const double d = (c - p).norm();
    if (d < best) {
      best = d;
      closest = c;
      interior = !((i == 0 && t <= 1e-9) || (i + 2 == line.size() && t >= 1 - 1e-9));
    }
  }
  return best;
}

/// Principal direction of points (unit), through their mean.
Vec2 principalDirection(const std::vector<Vec2>& pts, Vec2& mean) {
  mean = Vec2::Zero();
  for (const Vec2& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  Mat2 c = Mat2::Zero();
  for (const Vec2& p : pts) c += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Mat2> es(c);
  Vec2 d = es.eigenvectors().col(1);
  if (d.x() < 0) d = -d;
  return d;
}

/// Clips segment a→b to the box [lo, hi]; false when nothing is left.
bool clipSegment(Vec2& a, Vec2& b, const Vec2& lo, const Vec2& hi) {
  double t0 = 0, t1 = 1;
  const Vec2 d = b - a;
  for (int k = 0; k < 2; ++k) {
    for (int side = 0; side < 2; ++side) {
      const double p = side == 0 ? -d[k] : d[k];
      const double q = side == 0 ? a[k] - lo[k] : hi[k] - a[k];
      if (std::abs(p) < 1e-12) {
        if (q < 0) return false;
        continue;
      }
      const double r = q / p;
      if (p < 0) t0 = std::max(t0, r);
      else t1 = std::min(t1, r);
    }
  }
  if (t0 > t1) return false;
  const Vec2 a0 = a;
  a = a0 + t0 * d;
  b = a0 + t1 * d;
  return true;
}

}  // namespace

// --- Grey image and the oriented operator ------------------------------------------------------------

double bandLevel(double r, double g, double b, GreyBand band) {
  switch (band) {
    case GreyBand::Blue: return b;
    case GreyBand::Luminance: return 0.299 * r + 0.587 * g + 0.114 * b;
    case GreyBand::NormalizedGreen: return 255.0 * (g + 1) / (r + g + b + 3);
    case GreyBand::NormalizedRed: return 255.0 * (r + 1) / (r + g + b + 3);
  }
  return 0;
}

GreyImage toGrey(const std::uint8_t* rgb, int width, int height, GreyBand band) {
  GreyImage g;
  g.width = width;
  g.height = height;
  const std::size_t n = static_cast<std::size_t>(width) * height;
  g.data.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* p = rgb + 3 * i;
    g.data[i] = static_cast<float>(bandLevel(p[0], p[1], p[2], band));
  }
  return g;
}

EdgeMatch orientedEdge(const GreyImage& image, const Vec2& centre, const Vec2& direction,
                       const OrientedEdgeParams& params, int polarity) {
  EdgeMatch best;
  const int L = std::max(1, params.along_px), W = std::max(4, params.across_px);
  const int h = std::max(1, params.step_half_width_px);
  const Vec2 d0 = direction.normalized();
  const int na = params.angle_step_deg > 0 ? static_cast<int>(std::floor(params.angle_search_deg / params.angle_step_deg))
                                            : 0;
  double best_score = -std::numeric_limits<double>::infinity();
  std::vector<double> prof(W), scores(W);
  for (int ai = -na; ai <= na; ++ai) {
    const Vec2 d = rotateVec(d0, ai * params.angle_step_deg * kDeg);
    const Vec2 n = across(d);
    // The edge profile: the operator's columns (along d) summed over nearest pixels.
    for (int k = 0; k < W; ++k) {
      const double o = k - (W - 1) / 2.0;
      double sum = 0;
      int count = 0;
      for (int j = 0; j < L; ++j) {
        const double t = j - (L - 1) / 2.0;
        const Vec2 p = centre + o * n + t * d;
        const long u = std::lround(p.x()), v = std::lround(p.y());
        if (u < 0 || v < 0 || u >= image.width || v >= image.height) continue;
        sum += image.at(static_cast<int>(u), static_cast<int>(v));
        ++count;
      }
      prof[k] = count * 4 >= L ? sum / count : kNaN;
    }
    // Correlation with the ideal step at each position (step between k-1 and k).
    int kbest = -1;
    double sbest = -std::numeric_limits<double>::infinity();
    for (int k = 0; k < W; ++k) {
      scores[k] = kNaN;
      if (k - h < 0 || k + h > W) continue;
      if (std::abs(k - 0.5 - (W - 1) / 2.0) > params.max_offset_px) continue;
      // An edge point outside the image is no edge seen: there the profile's columns hold only
      // their part inside the image, and where that part ends looks like a step.
      const Vec2 at = centre + (k - 0.5 - (W - 1) / 2.0) * n;
      if (at.x() < 0 || at.y() < 0 || at.x() > image.width - 1 || at.y() > image.height - 1) continue;
      double l = 0, r = 0;
      bool ok = true;
      for (int i = 1; i <= h && ok; ++i) {
        if (std::isnan(prof[k - i]) || std::isnan(prof[k + i - 1])) ok = false;
        else {
          l += prof[k - i];
          r += prof[k + i - 1];
        }
      }
      if (!ok) continue;
      const double c = (r - l) / h;
      const double s = polarity == 0 ? std::abs(c) : polarity * c;
      scores[k] = s;
      if (s > sbest) {
        sbest = s;
        kbest = k;
      }
    }
    if (kbest < 0 || sbest <= best_score) continue;
    best_score = sbest;
    // Sub-pixel position: parabola through the neighbouring scores.
    double frac = 0;
    if (kbest > 0 && kbest + 1 < W && !std::isnan(scores[kbest - 1]) && !std::isnan(scores[kbest + 1])) {
      const double a = scores[kbest - 1], b = scores[kbest], c = scores[kbest + 1];
      const double den = a - 2 * b + c;
      if (den < 0) frac = std::clamp(0.5 * (a - c) / den, -0.5, 0.5);
    }
    const double pos = kbest - 0.5 + frac - (W - 1) / 2.0;
    best.found = true;
    best.point = centre + pos * n;
    best.direction = d;
    double l = 0, r = 0, mean = 0, var = 0, slope = 0;
    for (int i = 1; i <= h; ++i) {
      l += prof[kbest - i];
      r += prof[kbest + i - 1];
    }
    best.contrast = (r - l) / h;
    for (int i = kbest - h; i < kbest + h; ++i) mean += prof[i];
    mean /= 2 * h;
    for (int i = kbest - h; i < kbest + h; ++i) var += (prof[i] - mean) * (prof[i] - mean);
    const double sd = std::sqrt(var / (2 * h));
    best.correlation = sd > 1e-9 ? (best.contrast / 2) / sd : 0;
    for (int i = kbest - h; i + 1 < kbest + h; ++i) slope = std::max(slope, std::abs(prof[i + 1] - prof[i]));
    best.width_px = slope > 1e-9 ? std::abs(best.contrast) / slope : 0;
    best.profile = prof;
  }
  return best;
}

// --- Options -------------------------------------------------------------------------------------------

void EdgeTrackerOptions::validate() const {
  auto bad = [](const std::string& field, double v, const std::string& rule) {
    std::ostringstream s;
    s << "EdgeTrackerOptions::" << field << " = " << v << ": must be " << rule;
    throw InvalidInput(s.str());
  };
  if (!(min_normalised_step >= 0)) bad("min_normalised_step", min_normalised_step, ">= 0");
  if (window_rows < 4) bad("window_rows", window_rows, ">= 4");
  if (window_cols < 8) bad("window_cols", window_cols, ">= 8");
  if (!(step_fraction > 0 && step_fraction <= 4)) bad("step_fraction", step_fraction, "in (0, 4]");
  if (step_half_width_px < 1) bad("step_half_width_px", step_half_width_px, ">= 1");
  if (!(angle_search_deg >= 0 && angle_search_deg <= 45)) bad("angle_search_deg", angle_search_deg, "in [0, 45]");
  if (!(angle_step_deg > 0 && angle_step_deg <= 45)) bad("angle_step_deg", angle_step_deg, "in (0, 45]");
  if (!(min_contrast >= 0)) bad("min_contrast", min_contrast, ">= 0");
  if (!(max_turn_deg > 0 && max_turn_deg <= 180)) bad("max_turn_deg", max_turn_deg, "in (0, 180]");
  if (min_points < 1) bad("min_points", min_points, ">= 1");
  if (max_points < min_points) bad("max_points", max_points, ">= min_points");
  if (!(expected_width_m >= 0)) bad("expected_width_m", expected_width_m, ">= 0");
  if (!(width_tolerance > 0)) bad("width_tolerance", width_tolerance, "> 0");
  if (!(parallel_tolerance_deg > 0)) bad("parallel_tolerance_deg", parallel_tolerance_deg, "> 0");
  if (!(max_width_sd_m > 0)) bad("max_width_sd_m", max_width_sd_m, "> 0");
  if (!(max_range_m > 0)) bad("max_range_m", max_range_m, "> 0");
}

namespace {

struct Spec {
  const char* name;
  const char* def;
  const char* description;
};

const std::vector<Spec>& specs() {
  static const std::vector<Spec> s = {
      {"band", "\"normalized_green\"",
       "grey image: \"luminance\" (0.299 R + 0.587 G + 0.114 B), \"blue\" (the blue band of the Warp runs, 3.6.3) or "
       "\"normalized_green\" (255 G / (R + G + B), the normalised colour of 3.4.3: blind to shadows) or \"normalized_red\""},
      {"band_from_prediction", "true",
       "with a normalised band: trace each edge in whichever of the normalised green and red separates its predicted "
       "side colours more (dirt and gravel have the asphalt's normalised green)"},
      {"min_normalised_step", "12",
       "with band_from_prediction: when neither normalised band separates an edge's predicted side colours by this many "
       "levels, trace it in luminance (gravel against asphalt: 2.8 in green, 6.6 in red, 60 in luminance); 0: never"},
      {"window_rows", "64", "search window length along the edge at 480 rows (scaled with the image height)"},
      {"window_cols", "128", "search window width across the edge at 512 columns (scaled with the image width)"},
      {"step_fraction", "0.5", "the next point is predicted this x window_rows ahead along theta"},
      {"step_half_width_px", "6", "the ideal step edge: this many profile samples each side (at 512 columns)"},
      {"angle_search_deg", "10", "operator orientations tried: theta +- this ..."},
      {"angle_step_deg", "1", "... in steps of this"},
      {"min_contrast", "6", "a weaker step (grey levels) ends the trace"},
      {"max_turn_deg", "30", "a larger change of theta between two steps ends the trace"},
      {"min_points", "3", "fewer edge points: the edge is lost (status failed)"},
      {"max_points", "200", "at most this many points per edge"},
      {"start_left_u", "-1", "without a prediction: left edge start column (-1: 0.25 x width)"},
      {"start_right_u", "-1", "without a prediction: right edge start column (-1: 0.75 x width)"},
      {"start_v", "-1", "without a prediction: start row (-1: half a window above the bottom)"},
      {"start_left_angle_deg", "20", "without a prediction: left edge direction, degrees from up, + leaning right"},
      {"start_right_angle_deg", "-20", "without a prediction: right edge direction"},
      {"expected_width_m", "0", "expected road width; 0: the prediction's parallel relation separation_m"},
      {"width_tolerance", "0.15", "ground width must be within this fraction of the expected width"},
      {"parallel_tolerance_deg", "10", "the two edges' ground lines must be within this angle"},
      {"max_width_sd_m", "0.4", "the spread of the width along the edges must be within this"},
      {"max_range_m", "15", "an edge ends at its first point farther than this on the ground (or above the horizon), m"},
      {"gate_search", "false",
       "after the first point search only offsets reachable within max_turn_deg (step x tan); off: the whole window"},
      {"gate_luminance", "true",
       "gate_search for the edges min_normalised_step sends to luminance alone (there tree shadows on a bright shoulder "
       "step more than the material)"},
      {"use_carried_edges", "true", "start from advance()'d previous edges when the prediction has no segments"},
      {"single_edge", "true",
       "when one edge is lost and the other (labelled) is tracked, report that edge alone instead of failing"},
  };
  return s;
}

}  // namespace

EdgeTrackerOptions edgeTrackerOptionsFromJson(const std::string& text, const EdgeTrackerOptions& base) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text.empty() ? std::string("{}") : text);
  } catch (const nlohmann::json::exception& e) {
    throw InvalidInput(std::string("pipeline \"edge-tracker\": options are not JSON: ") + e.what());
  }
  if (!j.is_object()) throw InvalidInput("pipeline \"edge-tracker\": options must be a JSON object");
  EdgeTrackerOptions o = base;
  for (const auto& [key, value] : j.items()) {
    const std::string bad = "pipeline \"edge-tracker\": option " + key + " = " + value.dump();
    auto num = [&]() {
      if (!value.is_number() || !std::isfinite(value.get<double>())) throw InvalidInput(bad + ": must be a number");
      return value.get<double>();
    };
    auto integer = [&]() {
      const double v = num();
      if (v != std::floor(v) || std::abs(v) > 1e9) throw InvalidInput(bad + ": must be an integer");
      return static_cast<int>(v);
    };
    if (key == "band") {
      if (value == "blue") o.band = GreyBand::Blue;
      else if (value == "luminance") o.band = GreyBand::Luminance;
      else if (value == "normalized_green") o.band = GreyBand::NormalizedGreen;
      else if (value == "normalized_red") o.band = GreyBand::NormalizedRed;
      else throw InvalidInput(bad + ": must be \"blue\", \"luminance\", \"normalized_green\" or \"normalized_red\"");
    } else if (key == "min_normalised_step") o.min_normalised_step = num();
    else if (key == "window_rows") o.window_rows = integer();
    else if (key == "window_cols") o.window_cols = integer();
    else if (key == "step_fraction") o.step_fraction = num();
    else if (key == "step_half_width_px") o.step_half_width_px = integer();
    else if (key == "angle_search_deg") o.angle_search_deg = num();
    else if (key == "angle_step_deg") o.angle_step_deg = num();
    else if (key == "min_contrast") o.min_contrast = num();
    else if (key == "max_turn_deg") o.max_turn_deg = num();
    else if (key == "min_points") o.min_points = integer();
    else if (key == "max_points") o.max_points = integer();
    else if (key == "start_left_u") o.start_left_u = num();
    else if (key == "start_right_u") o.start_right_u = num();
    else if (key == "start_v") o.start_v = num();
    else if (key == "start_left_angle_deg") o.start_left_angle_deg = num();
    else if (key == "start_right_angle_deg") o.start_right_angle_deg = num();
    else if (key == "expected_width_m") o.expected_width_m = num();
    else if (key == "width_tolerance") o.width_tolerance = num();
    else if (key == "parallel_tolerance_deg") o.parallel_tolerance_deg = num();
    else if (key == "max_width_sd_m") o.max_width_sd_m = num();
    else if (key == "max_range_m") o.max_range_m = num();
    else if (key == "gate_search") {
      if (!value.is_boolean()) throw InvalidInput(bad + ": must be true or false");
      o.gate_search = value.get<bool>();
    } else if (key == "gate_luminance") {
      if (!value.is_boolean()) throw InvalidInput(bad + ": must be true or false");
      o.gate_luminance = value.get<bool>();
    } else if (key == "band_from_prediction") {
      if (!value.is_boolean()) throw InvalidInput(bad + ": must be true or false");
      o.band_from_prediction = value.get<bool>();
    } else if (key == "single_edge") {
      if (!value.is_boolean()) throw InvalidInput(bad + ": must be true or false");
      o.single_edge = value.get<bool>();
    } else if (key == "use_carried_edges") {
      if (!value.is_boolean()) throw InvalidInput(bad + ": must be true or false");
      o.use_carried_edges = value.get<bool>();
    } else
      throw InvalidInput("pipeline \"edge-tracker\": unknown option \"" + key + "\"");
  }
  try {
    o.validate();
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string("pipeline \"edge-tracker\": ") + e.what());
  }
  return o;
}

std::vector<OptionInfo> edgeTrackerOptionInfos() {
  std::vector<OptionInfo> out;
  for (const Spec& s : specs()) out.push_back({s.name, s.def, s.description});
  return out;
}

// --- The tracker ---------------------------------------------------------------------------------------

EdgeTracker::EdgeTracker(EdgeTrackerOptions options) : options_(std::move(options)) { options_.validate(); }

void EdgeTracker::setOptions(const EdgeTrackerOptions& options) {
  options.validate();
  options_ = options;
}

namespace {

OrientedEdgeParams paramsFor(const EdgeTrackerOptions& o, int width, int height) {
  OrientedEdgeParams p;
  p.along_px = std::max(4, static_cast<int>(std::lround(o.window_rows * height / 480.0)));
  p.across_px = std::max(8, static_cast<int>(std::lround(o.window_cols * width / 512.0)));
  p.step_half_width_px = std::max(1, static_cast<int>(std::lround(o.step_half_width_px * width / 512.0)));
  p.angle_search_deg = o.angle_search_deg;
  p.angle_step_deg = o.angle_step_deg;
  return p;
}

void evaluate(TrackedEdge& e, double max_turn_deg) {
  EdgeEvaluation& ev = e.eval;
  const std::size_t n = e.matches.size();
  if (n == 0) return;
  std::vector<double> c;
  for (const EdgeMatch& m : e.matches) {
    c.push_back(std::abs(m.contrast));
    ev.contrast += std::abs(m.contrast);
    ev.width_px += m.width_px;
  }
  ev.contrast /= static_cast<double>(n);
  ev.width_px /= static_cast<double>(n);
  double ss = 0;
  int cnt = 0;
  for (std::size_t i = 1; i + 1 < e.image.size(); ++i) {
    const Segment2 chord{e.image[i - 1], e.image[i + 1]};
    const double d = chord.distanceTo(e.image[i]);
    ss += d * d;
    ++cnt;
  }
  ev.smoothness = cnt > 0 ? std::sqrt(ss / cnt) : 0;
  const double med = median(c);
  int good = 0;
  for (std::size_t i = 0; i < n; ++i) {
    bool ok = c[i] >= 0.5 * med && c[i] <= 2 * med;
    if (i >= 2) {
      const Vec2 a = (e.image[i - 1] - e.image[i - 2]).normalized(), b = (e.image[i] - e.image[i - 1]).normalized();
      const double turn = std::acos(std::clamp(a.dot(b), -1.0, 1.0)) / kDeg;
      ok = ok && turn <= max_turn_deg / 2;
    }
    if (ok) ++good;
  }
  ev.consistency = static_cast<double>(good) / static_cast<double>(n);
  // Score: contrast saturating at 20 grey levels, times consistency, less for a rough trace.
  ev.score = std::clamp(ev.contrast / 20.0, 0.0, 1.0) * ev.consistency * std::exp(-ev.smoothness / 4.0);
}

}  // namespace

TrackedEdge EdgeTracker::trace(const GreyImage& image, const Vec2& start, const Vec2& direction,
                               int expected_polarity, bool gate) const {
  TrackedEdge e;
  e.start = start;
  e.start_direction = direction.normalized();
  OrientedEdgeParams p = paramsFor(options_, image.width, image.height);
  const double step = options_.step_fraction * p.along_px;
  auto inside = [&](const Vec2& q) {
    return q.x() >= -0.5 && q.y() >= -0.5 && q.x() <= image.width - 0.5 && q.y() <= image.height - 0.5;
  };
  Vec2 dir = e.start_direction;
  if (dir.y() > 0) dir = -dir;  // trace up the image
  // The start point and, when no step is found there, the next few predicted points along the
  // start direction: a start clipped into an image corner has most of its window outside.
  EdgeMatch m;
  for (int k = 0; k < 4; ++k) {
    const Vec2 at = start + k * step * dir;
    if (!inside(at)) break;
    m = orientedEdge(image, at, dir, p, expected_polarity);
    if (m.found && std::abs(m.contrast) >= options_.min_contrast) break;
  }
  if (!m.found || std::abs(m.contrast) < options_.min_contrast) {
    e.stop_reason = "no step edge at the start point";
    return e;
  }
  const int polarity = m.contrast > 0 ? 1 : -1;
  // gate_search: after the first point, only steps the trace can reach without turning more than
  // max_turn_deg. Off by default: under heavy shadow it turns "edge lost" into a wrong trace.
  if (options_.gate_search || gate) p.max_offset_px = step * std::tan(std::min(options_.max_turn_deg, 80.0) * kDeg);
  m.profile.clear();
  e.image.push_back(m.point);
  e.matches.push_back(m);
  while (static_cast<int>(e.image.size()) < options_.max_points) {
    const Vec2 predicted = e.image.back() + step * dir;
    if (!inside(predicted)) {
      e.reached_top = true;
      e.stop_reason = "the search window left the image";
      break;
    }
    EdgeMatch next = orientedEdge(image, predicted, dir, p, polarity);
    if (!next.found || std::abs(next.contrast) < options_.min_contrast) {
      e.stop_reason = "edge contrast lost";
      break;
    }
    const Vec2 moved = next.point - e.image.back();
    if (moved.norm() < 0.25 * step) {
      e.stop_reason = "edge did not advance";
      break;
    }
    const Vec2 nd = moved.normalized();
    const double turn = std::acos(std::clamp(nd.dot(dir), -1.0, 1.0)) / kDeg;
    if (turn > options_.max_turn_deg) {
      e.stop_reason = "edge turned too sharply";
      break;
    }
    next.profile.clear();
    e.image.push_back(next.point);
    e.matches.push_back(next);
    dir = nd;  // theta = atan2(c_i - c_{i-1}, r_i - r_{i-1})
  }
  if (e.stop_reason.empty()) e.stop_reason = "max_points reached";
  evaluate(e, options_.max_turn_deg);
  return e;
}

void EdgeTracker::advance(const Pose2& motion) {
  auto carry = [&](const std::optional<Carried>& last) -> std::optional<Carried> {
    if (!last) return std::nullopt;
    Carried c;
    c.label = last->label;
    for (const Vec2& g : last->ground) c.ground.push_back(motion.inverseTransform(g));
    return c;
  };
  carried_left_ = carry(last_left_);
  carried_right_ = carry(last_right_);
}

void EdgeTracker::reset() {
  carried_left_.reset();
  carried_right_.reset();
  last_left_.reset();
  last_right_.reset();
  report_ = {};
}

namespace {

struct Start {
  Vec2 point = Vec2::Zero(), direction = Vec2(0, -1);
  std::optional<std::string> label;
  int polarity = 0;
  GreyBand band = GreyBand::NormalizedGreen;
};

bool normalised(GreyBand b) { return b == GreyBand::NormalizedGreen || b == GreyBand::NormalizedRed; }


/// The near end of an image segment clipped to the image, directed up the image.
/// The start is kept `margin` px from the image's sides, so that the step model fits in the image.
/// The edge's band: o.band, or with o.band_from_prediction the one its predicted side colours choose
/// (see EdgeTrackerOptions::band_from_prediction); their difference in it gives the expected contrast sign.
std::optional<Start> startFromSegment(const InterestSegment& s, const Camera& cam, int w, int h,
                                      const EdgeTrackerOptions& o, double margin = 16) {
  Vec2 a = s.image.a, b = s.image.b;
  // Recompute from the ground so that a clipped image segment is not an issue for curved lenses.
  const auto pa = cam.projectGround(s.vehicle.a), pb = cam.projectGround(s.vehicle.b);
  if (pa && pb) {
    a = *pa;
    b = *pb;
  }
  if (!clipSegment(a, b, Vec2(margin, 1), Vec2(w - 1.0 - margin, h - 2.0))) return std::nullopt;
  if ((b - a).norm() < 4) return std::nullopt;
  Start st;
  // Walking a → b on the ground is walking up the image when a is the lower end; then the image's
  // right of the edge is the segment's right side.
  const bool forward = a.y() >= b.y();
  if (forward) {
    st.point = a;
    st.direction = (b - a).normalized();
  } else {
    st.point = b;
    st.direction = (a - b).normalized();
  }
  st.label = s.id;
  const bool colours = s.left_rgb.norm() > 0 || s.right_rgb.norm() > 0;
  auto sideStep = [&](GreyBand b) {  // right side − left side, in band b
    return bandLevel(s.right_rgb.x(), s.right_rgb.y(), s.right_rgb.z(), b) -
           bandLevel(s.left_rgb.x(), s.left_rgb.y(), s.left_rgb.z(), b);
  };
  GreyBand band = o.band;
  if (colours && o.band_from_prediction && normalised(band)) {
    const double green = std::abs(sideStep(GreyBand::NormalizedGreen)), red = std::abs(sideStep(GreyBand::NormalizedRed));
    band = red > green ? GreyBand::NormalizedRed : GreyBand::NormalizedGreen;
    // Gravel against asphalt differs in brightness only: no normalised band separates them.
    if (std::max(green, red) < o.min_normalised_step && std::abs(sideStep(GreyBand::Luminance)) > std::max(green, red))
      band = GreyBand::Luminance;
  }
  st.band = band;
  const double diff = sideStep(band) * (forward ? 1 : -1);
  if (colours && std::abs(diff) >= 3) st.polarity = diff > 0 ? 1 : -1;
  return st;
}

/// Start points from the prediction: the road whose edge comes nearest the vehicle, its segments on
/// each side, nearest first (the lowest near end in the image), as {vehicle-left, vehicle-right};
/// false when neither is in the image. On a tight curve a narrow lens sees one edge only: the other
/// is then left empty.
bool startsFromPrediction(const PredictedObject& pred, const Camera& cam, int w, int h, const EdgeTrackerOptions& o,
                          std::vector<Start>& left, std::vector<Start>& right) {
  const InterestSegment* nearest = nullptr;
  double best = std::numeric_limits<double>::infinity();
  for (const InterestSegment& s : pred.segments) {
    if (s.side != "left" && s.side != "right") continue;
    const double d = s.vehicle.distanceTo(Vec2::Zero());
    if (d < best && startFromSegment(s, cam, w, h, o)) {
      best = d;
      nearest = &s;
    }
  }
  if (nearest == nullptr) return false;
  std::vector<std::pair<const InterestSegment*, Start>> side[2];  // road's left, right
  for (const InterestSegment& s : pred.segments) {
    if (s.owner != nearest->owner || (s.side != "left" && s.side != "right")) continue;
    if (auto st = startFromSegment(s, cam, w, h, o)) side[s.side == "left" ? 0 : 1].emplace_back(&s, std::move(*st));
  }
  for (auto& v : side)
    std::stable_sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.second.point.y() > b.second.point.y(); });
  // Which is the vehicle's left: with both, the larger y at the nearest segments' midpoints; with
  // one, the road's left is the vehicle's when the road runs forward (its segments point a → b).
  bool road_left_is_vehicle_left = true;
  if (!side[0].empty() && !side[1].empty()) {
    road_left_is_vehicle_left =
        side[0].front().first->vehicle.pointAt(0.5).y() >= side[1].front().first->vehicle.pointAt(0.5).y();
  } else {
    const InterestSegment* one = !side[0].empty() ? side[0].front().first : side[1].front().first;
    road_left_is_vehicle_left = (one->vehicle.b - one->vehicle.a).x() >= 0;
  }
  for (int k = 0; k < 2; ++k) {
    const bool vehicle_left = (k == 0) == road_left_is_vehicle_left;
    for (auto& [segment, st] : side[k]) (vehicle_left ? left : right).push_back(std::move(st));
  }
  return true;
}

std::optional<Start> startFromCarried(const std::vector<Vec2>& ground, const std::optional<std::string>& label,
                                      const Camera& cam, int w, int h) {
  std::vector<Vec2> px;
  for (const Vec2& g : ground) {
    const auto p = cam.projectGround(g);
    if (p && p->x() >= 1 && p->y() >= 1 && p->x() <= w - 2 && p->y() <= h - 2) px.push_back(*p);
  }
  if (px.size() < 2) return std::nullopt;
  std::sort(px.begin(), px.end(), [](const Vec2& a, const Vec2& b) { return a.y() > b.y(); });
  Start st;
  st.point = px[0];
  st.direction = (px[std::min<std::size_t>(px.size() - 1, 2)] - px[0]).normalized();
  st.label = label;
  return st;
}

}  // namespace

DetectedObject EdgeTracker::detect(const VisionFrame& frame, const PredictedObject& prediction) {
  if (frame.camera == nullptr) throw InvalidInput("pipeline \"edge-tracker\": the frame has no camera");
  if (frame.rgb == nullptr || frame.width <= 0 || frame.height <= 0)
    throw InvalidInput("pipeline \"edge-tracker\": the frame has no pixels");
  const Camera& cam = *frame.camera;
  const int w = frame.width, h = frame.height;
  report_ = {};
  last_left_.reset();
  last_right_.reset();
  auto fail = [&](const std::string& why) {
    DetectedObject d = DetectedObject::failed(why);
    d.timestamp = frame.timestamp;
    return d;
  };

  Start ls, rs;
  ls.band = rs.band = options_.band;
  std::vector<Start> pl, pr;  // from the prediction: each edge's segments, nearest first
  bool trace_left = true, trace_right = true;
  if (startsFromPrediction(prediction, cam, w, h, options_, pl, pr)) {
    report_.start_source = "prediction";
    trace_left = !pl.empty();
    trace_right = !pr.empty();
    if (trace_left) ls = pl.front();
    if (trace_right) rs = pr.front();
  } else if (options_.use_carried_edges && carried_left_ && carried_right_ &&
             startFromCarried(carried_left_->ground, carried_left_->label, cam, w, h) &&
             startFromCarried(carried_right_->ground, carried_right_->label, cam, w, h)) {
    ls = *startFromCarried(carried_left_->ground, carried_left_->label, cam, w, h);
    rs = *startFromCarried(carried_right_->ground, carried_right_->label, cam, w, h);
    ls.band = rs.band = options_.band;
    report_.start_source = "carried";
  } else {
    const double sv = options_.start_v >= 0 ? options_.start_v
                                            : h - 1 - 0.5 * paramsFor(options_, w, h).along_px;
    ls.point = Vec2(options_.start_left_u >= 0 ? options_.start_left_u : 0.25 * w, sv);
    rs.point = Vec2(options_.start_right_u >= 0 ? options_.start_right_u : 0.75 * w, sv);
    ls.direction = Vec2(std::sin(options_.start_left_angle_deg * kDeg), -std::cos(options_.start_left_angle_deg * kDeg));
    rs.direction =
        Vec2(std::sin(options_.start_right_angle_deg * kDeg), -std::cos(options_.start_right_angle_deg * kDeg));
    report_.start_source = "options";
  }
  carried_left_.reset();
  carried_right_.reset();

  // The grey image in each band an edge needs (most frames: one). A grey camera's frame (R = G = B)
  // has no normalised colour (every pixel 85): there the edge is traced in the grey level.
  const bool colourless = isGreyFrame(frame.rgb, w, h);
  std::vector<std::pair<GreyBand, GreyImage>> greys;
  greys.reserve(4);  // one per GreyBand: references handed out stay valid
  auto traced = [&](GreyBand band) { return colourless && normalised(band) ? GreyBand::Luminance : band; };
  auto grey = [&](GreyBand band) -> const GreyImage& {
    for (const auto& [b, g] : greys)
      if (b == band) return g;
    greys.emplace_back(band, toGrey(frame.rgb, w, h, band));
    return greys.back().second;
  };
  auto traceIf = [&](bool predicted, const Start& st) {
    if (predicted) {
      const GreyBand band = traced(st.band);  // the band the edge is really traced in, as reported
      const bool gate = options_.gate_luminance && st.band == GreyBand::Luminance && normalised(options_.band);
      TrackedEdge e = trace(grey(band), st.point, st.direction, st.polarity, gate);
      e.band = band;
      return e;
    }
    TrackedEdge none;
    none.stop_reason = "not predicted in the image";
    return none;
  };
  // An edge lost within min_points of its start starts again from the next predicted segment up
  // the image: on a curve the edge enters at the image's side, where the window is half outside
  // and a shadow's edge on the shoulder can take the second point (park_loop frame 421, R4's gravel
  // edge); its next segment's near end lies a few pixels from the true edge.
  auto traceSide = [&](bool predicted, Start& st, const std::vector<Start>& next) {
    TrackedEdge e = traceIf(predicted, st);
    for (std::size_t i = 1; i < next.size() && static_cast<int>(e.image.size()) < options_.min_points; ++i) {
      TrackedEdge again = traceIf(true, next[i]);
      if (again.image.size() <= e.image.size()) continue;
      e = std::move(again);
      st = next[i];
    }
    e.label = st.label;
    return e;
  };
  report_.left = traceSide(trace_left, ls, pl);
  report_.right = traceSide(trace_right, rs, pr);
  // The predicted segments the edges started from, for the expected width (prediction's relations).
  const bool predicted = report_.start_source == "prediction";
  const std::string lid = predicted && trace_left ? ls.label.value_or("") : "";
  const std::string rid = predicted && trace_right ? rs.label.value_or("") : "";
  // Every edge point to the ground; the trace ends at the first one above the horizon or beyond
  // max_range_m (near the horizon a pixel spans metres of ground, and a wide lens sees the trace
  // run on into the far distance, where it would swing the fitted ground lines).
  for (TrackedEdge* e : {&report_.left, &report_.right}) {
    for (std::size_t i = 0; i < e->image.size(); ++i) {
      const auto g = cam.backproject(e->image[i]);
      if (!g || g->norm() > options_.max_range_m) {
        e->image.resize(i);
        e->matches.resize(i);
        e->stop_reason = "beyond max_range_m";
        e->reached_top = false;
        break;
      }
      e->ground.push_back(*g);
    }
  }

  // The edges' lines for the DetectedObject, labelled with the predicted segment each started from.
  auto addLines = [&](DetectedObject& d, const TrackedEdge& e) {
    const std::vector<Vec2> poly = e.image.size() > 2 ? simplifyPolyline(e.image, 1.5) : e.image;
    for (std::size_t i = 0; i + 1 < poly.size(); ++i) {
      DetectedLine l;
      l.label = e.label;
      l.score = e.label ? e.eval.score : 0;
      l.image = {poly[i], poly[i + 1]};
      const auto ga = cam.backproject(poly[i]), gb = cam.backproject(poly[i + 1]);
      if (ga && gb) l.vehicle = {*ga, *gb};
      d.lines.push_back(l);
    }
  };
  auto tracked = [&](const TrackedEdge& e) {
    return static_cast<int>(e.image.size()) >= options_.min_points && e.ground.size() >= 2;
  };
  const bool left_ok = tracked(report_.left), right_ok = tracked(report_.right);
  if (!left_ok && !right_ok) {
    return fail("both edges lost: left: " + report_.left.stop_reason + "; right: " + report_.right.stop_reason);
  }
  if (!left_ok || !right_ok) {
    const std::string lost = !left_ok ? "left edge lost: " + report_.left.stop_reason
                                      : "right edge lost: " + report_.right.stop_reason;
    const TrackedEdge& good = left_ok ? report_.left : report_.right;
    if (!options_.single_edge || !good.label) return fail(lost);
    // One edge: lateral position and heading for the Map (its gate against the prediction is the
    // only check left), no centre line, half the confidence.
    (left_ok ? last_left_ : last_right_) = Carried{good.ground, good.label};
    DetectedObject d;
    d.timestamp = frame.timestamp;
    addLines(d, good);
    d.confidence = std::clamp(0.5 * good.eval.score, 0.0, 1.0);
    d.reason = lost + "; the other edge alone";
    return d;
  }

  // Ground check: width samples from each edge to the other, parallelism of the fitted lines.
  EdgePairCheck& pc = report_.pair;
  std::vector<double> widths;
  std::vector<Vec2> mids;
  for (int side = 0; side < 2; ++side) {
    const std::vector<Vec2>& a = side == 0 ? report_.left.ground : report_.right.ground;
    const std::vector<Vec2>& b = side == 0 ? report_.right.ground : report_.left.ground;
    for (const Vec2& p : a) {
      bool interior = false;
      Vec2 c;
      const double d = polylineDistance(b, p, interior, c);
      if (!interior) continue;
      widths.push_back(d);
      mids.push_back(0.5 * (p + c));
    }
  }
  if (widths.size() < 2) return fail("edges inconsistent: they do not overlap on the ground");
  pc.width_m = median(widths);
  double var = 0;
  for (double x : widths) var += (x - pc.width_m) * (x - pc.width_m);
  pc.width_sd_m = std::sqrt(var / static_cast<double>(widths.size()));
  Vec2 ml, mr;
  const Vec2 dl = principalDirection(report_.left.ground, ml), dr = principalDirection(report_.right.ground, mr);
  pc.angle_deg = std::acos(std::clamp(std::abs(dl.dot(dr)), 0.0, 1.0)) / kDeg;
  pc.parallel_ok = pc.angle_deg <= options_.parallel_tolerance_deg && pc.width_sd_m <= options_.max_width_sd_m;
  pc.expected_width_m = options_.expected_width_m;
  if (pc.expected_width_m <= 0) {
    for (const SegmentRelation& r : prediction.relations) {
      if (r.type != SegmentRelation::Type::Parallel) continue;
      if ((r.a == lid && r.b == rid) || (r.a == rid && r.b == lid)) {
        pc.expected_width_m = r.separation_m;
        break;
      }
    }
    // Else a parallel relation of one of them with a segment on the road's other side (a relation
    // with a segment of its own side is a few centimetres: two pieces of the same edge).
    auto sideOf = [&](const std::string& id) -> std::string {
      for (const InterestSegment& s : prediction.segments)
        if (s.id == id) return s.side;
      return "";
    };
    if (pc.expected_width_m <= 0)
      for (const SegmentRelation& r : prediction.relations)
        if (r.type == SegmentRelation::Type::Parallel && (r.a == lid || r.b == lid || r.a == rid || r.b == rid) &&
            sideOf(r.a) != sideOf(r.b)) {
          pc.expected_width_m = r.separation_m;
          break;
        }
  }
  pc.width_ok = pc.expected_width_m <= 0 ||
                std::abs(pc.width_m - pc.expected_width_m) <= options_.width_tolerance * pc.expected_width_m;

  last_left_ = Carried{report_.left.ground, report_.left.label};
  last_right_ = Carried{report_.right.ground, report_.right.label};

  if (!pc.parallel_ok) {
    std::ostringstream s;
    s << "edges not parallel: " << pc.angle_deg << " deg apart, width spread " << pc.width_sd_m << " m";
    return fail(s.str());
  }
  if (!pc.width_ok) {
    std::ostringstream s;
    s << "edges inconsistent: width " << pc.width_m << " m, expected " << pc.expected_width_m << " m";
    return fail(s.str());
  }

  DetectedObject d;
  d.timestamp = frame.timestamp;
  for (const TrackedEdge* e : {&report_.left, &report_.right}) addLines(d, *e);
  // Region between the edges: left bottom → top, then right top → bottom.
  for (const Vec2& p : report_.left.image) d.region_image.push_back(p);
  for (auto it = report_.right.image.rbegin(); it != report_.right.image.rend(); ++it) d.region_image.push_back(*it);
  for (const Vec2& p : d.region_image)
    if (const auto g = cam.backproject(p)) d.region_vehicle.push_back(*g);
  // Centre line: the mid-points fitted with a line, from the nearest to the farthest.
  {
    Vec2 mean;
    const Vec2 dir = principalDirection(mids, mean);
    double tmin = std::numeric_limits<double>::infinity(), tmax = -tmin;
    for (const Vec2& m : mids) {
      const double t = (m - mean).dot(dir);
      tmin = std::min(tmin, t);
      tmax = std::max(tmax, t);
    }
    d.centerline_vehicle = Segment2{mean + tmin * dir, mean + tmax * dir};
  }
  const double width_fit =
      pc.expected_width_m > 0 ? 1 - std::abs(pc.width_m - pc.expected_width_m) / pc.expected_width_m : 1.0;
  d.confidence = std::clamp(0.5 * (report_.left.eval.score + report_.right.eval.score) * width_fit, 0.0, 1.0);
  return d;
}

// --- The pipeline ----------------------------------------------------------------------------------------

namespace {

class EdgeTrackerPipeline : public VisionPipeline {
 public:
  std::string name() const override { return "edge-tracker"; }
  void configure(const std::string& options_json) override {
    tracker_.setOptions(edgeTrackerOptionsFromJson(options_json, tracker_.options()));
  }
  DetectedObject detect(const VisionFrame& frame, const PredictedObject& prediction) override {
    return tracker_.detect(frame, prediction);
  }
  void reset() override { tracker_.reset(); }

 private:
  EdgeTracker tracker_;
};

}  // namespace

std::unique_ptr<VisionPipeline> createEdgeTrackerPipeline() { return std::make_unique<EdgeTrackerPipeline>(); }

}  // namespace mapnav
