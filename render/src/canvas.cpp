#include "mapnav/render/canvas.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include "detail.h"
#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/core/strprintf.h"

namespace mapnav::render {

// ---- View ---------------------------------------------------------------------------------------

namespace {

void checkCanvasSide(int px, const char* what) {
  if (px < 1 || px > kMaxCanvasSidePx) {
    throw InvalidInput(std::string("render: canvas ") + what + " " + std::to_string(px) +
                       " px is outside 1.." + std::to_string(kMaxCanvasSidePx));
  }
}

void checkMargin(double margin_px) {
  if (!std::isfinite(margin_px) || margin_px < 0.0) {
    throw InvalidInput("render: margin " + std::to_string(margin_px) + " px must be finite and >= 0");
  }
}

/// The box as centre and extent, padded so that both extents are at least 1 m.
struct FittedBox {
  Vec2 center;
  Vec2 extent;
};

FittedBox fitted(const Box2& world) {
  const bool finite = world.min().allFinite() && world.max().allFinite();
  if (!finite || world.isEmpty()) return {Vec2::Zero(), Vec2(1.0, 1.0)};
  const Vec2 center = 0.5 * (world.min() + world.max());
  const Vec2 size = world.max() - world.min();
  // A box so large that its size overflows is treated like a bad one.
  if (!center.allFinite() || !size.allFinite()) return {Vec2::Zero(), Vec2(1.0, 1.0)};
  return {center, Vec2(std::max(size.x(), 1.0), std::max(size.y(), 1.0))};
}

}  // namespace

View::View(const Box2& world, int width_px, int height_px, double margin_px) {
  checkCanvasSide(width_px, "width");
  checkCanvasSide(height_px, "height");
  checkMargin(margin_px);
  const FittedBox box = fitted(world);
  const double avail_w = std::max(width_px - 2.0 * margin_px, 1.0);
  const double avail_h = std::max(height_px - 2.0 * margin_px, 1.0);
  scale_ = std::min(avail_w / box.extent.x(), avail_h / box.extent.y());
  world_center_ = box.center;
  width_ = width_px;
  height_ = height_px;
}

View View::fitWidth(const Box2& world, int width_px, double margin_px) {
  checkCanvasSide(width_px, "width");
  checkMargin(margin_px);
  const FittedBox box = fitted(world);
  const double avail_w = std::max(width_px - 2.0 * margin_px, 1.0);
  const double scale = avail_w / box.extent.x();
  // Ceil (less a hair, against round-off) so that the width, not the height, sets the scale.
  const double h = std::ceil(box.extent.y() * scale + 2.0 * margin_px - 1e-9);
  const int height_px = static_cast<int>(std::clamp(h, 1.0, static_cast<double>(kMaxCanvasSidePx)));
  return View(world, width_px, height_px, margin_px);
}

Vec2 View::toPixel(const Vec2& world) const {
  return {0.5 * width_ + (world.x() - world_center_.x()) * scale_,
          0.5 * height_ - (world.y() - world_center_.y()) * scale_};
}

// ---- Canvas: recording and saving ---------------------------------------------------------------

Canvas::Canvas(int width_px, int height_px, Rgb background)
    : width_(width_px), height_(height_px), background_(background) {
  checkCanvasSide(width_px, "width");
  checkCanvasSide(height_px, "height");
}

void Canvas::polygon(const std::vector<Vec2>& ring, const Style& style) {
  commands_.emplace_back(PolygonCmd{ring, style});
}

void Canvas::polyline(const std::vector<Vec2>& points, const Style& style) {
  commands_.emplace_back(PolylineCmd{points, style});
}

void Canvas::circle(const Vec2& center, double radius_px, const Style& style) {
  commands_.emplace_back(CircleCmd{center, radius_px, style});
}

void Canvas::text(const Vec2& position, const std::string& text, const TextStyle& style) {
  commands_.emplace_back(TextCmd{position, text, style});
}

void Canvas::save(const std::filesystem::path& path) const {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  std::string bytes;
  if (ext == ".svg") {
    bytes = toSvg();
  } else if (ext == ".png") {
    bytes = toPng();
  } else {
    throw InvalidInput(path.string() + ": cannot save a picture as '" + path.extension().string() +
                       "'; use .svg or .png");
  }
  writeFileAtomic(path, bytes);
}

// ---- scale bar and north arrow ------------------------------------------------------------------

namespace {

/// 10^k, exact for the k that matter (|k| ≤ 22), and divided rather than multiplied for k < 0 so
/// that 5 × 10^-2 is the double nearest to 0.05.
double niceValue(double mantissa, int k) {
  double p = 1.0;
  for (int i = 0; i < std::abs(k); ++i) p *= 10.0;
  return k >= 0 ? mantissa * p : mantissa / p;
}

}  // namespace

double niceScaleLength(double metres) {
  if (!std::isfinite(metres) || metres <= 0.0) {
    throw InvalidInput("render: scale length " + std::to_string(metres) + " m must be positive and finite");
  }
  const int k = static_cast<int>(std::floor(std::log10(metres)));
  double best = 0.0, best_diff = 0.0;
  bool have = false;
  // Candidates around the decade of `metres`, ascending, so that a tie keeps the shorter length.
  for (int kk = k - 1; kk <= k + 1; ++kk) {
    for (double m : {1.0, 2.0, 5.0}) {
      const double c = niceValue(m, kk);
      const double diff = std::abs(c - metres);
      if (c > 0.0 && std::isfinite(c) && (!have || diff < best_diff)) {
        best = c;
        best_diff = diff;
        have = true;
      }
    }
  }
  return best;
}

std::string scaleLengthLabel(double metres) {
  if (metres >= 1000.0) return numberText(metres / 1000.0) + " km";
  return numberText(metres) + " m";
}

void drawScaleBarAndNorthArrow(Canvas& canvas, const View& view, double target_px, const std::optional<Box2>& panel) {
  if (!std::isfinite(target_px) || target_px <= 0.0) {
    throw InvalidInput("render: scale bar length " + std::to_string(target_px) + " px must be positive and finite");
  }
  const Box2 area = panel.value_or(Box2(Vec2(0, 0), Vec2(canvas.width(), canvas.height())));
  const double w = area.sizes().x(), h = area.sizes().y();
  const double left = area.min().x(), top_edge = area.min().y();
  const double ppm = view.pixelsPerMetre();
  const Rgb black{0, 0, 0}, white{255, 255, 255};

  // Scale bar, bottom-left: a black and a white half in a black frame, the length above it.
  const double margin = 12.0;
  const double avail = std::max(w - 2.0 * margin, 1.0);
  double length = niceScaleLength(target_px / ppm);
  for (int i = 0; i < 64 && length * ppm > avail; ++i) length = niceScaleLength(0.45 * length);
  const double bar_px = length * ppm;
  const double bar_h = 6.0;
  // On half pixels, so that the 1 px frame falls on whole pixels and looks crisp.
  const double x0 = left + margin + 0.5, x1 = x0 + bar_px, xm = 0.5 * (x0 + x1);
  const double y1 = top_edge + h - margin - 0.5, y0 = y1 - bar_h;
  Style black_fill{black, std::nullopt, 1.0, 1.0, false};
  Style white_fill{white, std::nullopt, 1.0, 1.0, false};
  Style frame{std::nullopt, black, 1.0, 1.0, false};
  canvas.polygon({{x0, y0}, {xm, y0}, {xm, y1}, {x0, y1}}, black_fill);
  canvas.polygon({{xm, y0}, {x1, y0}, {x1, y1}, {xm, y1}}, white_fill);
  canvas.polygon({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, frame);
  TextStyle label;
  label.size_px = 10.0;
  label.color = black;
  label.anchor = Anchor::Start;
  label.halo = white;
  canvas.text({x0, y0 - 5.0}, scaleLengthLabel(length), label);

  // North arrow, top-right: a black triangle pointing up, "N" under it.
  const double cx = left + w - 22.0, top = top_edge + 10.0, half = 8.0, tri_h = 20.0;
  canvas.polygon({{cx, top}, {cx + half, top + tri_h}, {cx - half, top + tri_h}},
                 Style{black, white, 1.5, 1.0, false});
  TextStyle n;
  n.size_px = 11.0;
  n.color = black;
  n.anchor = Anchor::Middle;
  n.bold = true;
  n.halo = white;
  canvas.text({cx, top + tri_h + 16.0}, "N", n);
}

// ---- shared by the SVG and PNG writers ----------------------------------------------------------

namespace detail {

ClipBox clipBoxFor(int width, int height, double stroke_width_px) {
  const double pad = std::max({static_cast<double>(width), static_cast<double>(height), 256.0}) +
                     4.0 * sanitizeStrokeWidth(stroke_width_px);
  return {-pad, -pad, width + pad, height + pad};
}

double sanitizeOpacity(double opacity) {
  if (std::isnan(opacity)) return 1.0;
  return std::clamp(opacity, 0.0, 1.0);
}

double sanitizeStrokeWidth(double width) {
  if (!std::isfinite(width) || width <= 0.0) return 1.0;
  return std::min(width, 1000.0);
}

int strokeThickness(double width) {
  return std::max(1, static_cast<int>(std::lround(sanitizeStrokeWidth(width))));
}

bool usablePoint(const Vec2& p) {
  return p.allFinite() && std::abs(p.x()) <= kFarPx && std::abs(p.y()) <= kFarPx;
}

namespace {

/// One edge of the clip box as a half-plane: inside when coord(p) * sign <= limit * sign.
struct HalfPlane {
  int axis;      // 0: u, 1: v
  double limit;
  bool keep_below;  // inside when p[axis] <= limit (else when >= limit)
  bool inside(const Vec2& p) const { return keep_below ? p[axis] <= limit : p[axis] >= limit; }
  /// Where a-b crosses the edge (a and b on either side): exactly on it along `axis`.
  Vec2 cut(const Vec2& a, const Vec2& b) const {
    const double t = (limit - a[axis]) / (b[axis] - a[axis]);
    Vec2 r = a + t * (b - a);
    r[axis] = limit;
    return r;
  }
};

std::array<HalfPlane, 4> halfPlanes(const ClipBox& box) {
  return {HalfPlane{0, box.u0, false}, HalfPlane{0, box.u1, true}, HalfPlane{1, box.v0, false},
          HalfPlane{1, box.v1, true}};
}

Vec2 clampInto(Vec2 p, const ClipBox& box) {
  p.x() = std::clamp(p.x(), box.u0, box.u1);
  p.y() = std::clamp(p.y(), box.v0, box.v1);
  return p;
}

/// Liang–Barsky: the part of segment a-b inside the box, if any. Endpoints inside come back exactly;
/// a cut point lies exactly on the box edge it was cut at (computing it as a + t (b - a) alone
/// would lose all precision for far-away endpoints).
bool clipSegment(const Vec2& a, const Vec2& b, const ClipBox& box, Vec2& ca, Vec2& cb) {
  const Vec2 d = b - a;
  if (!d.allFinite()) return false;
  double t0 = 0.0, t1 = 1.0;
  int edge0 = -1, edge1 = -1;
  const std::array<HalfPlane, 4> planes = halfPlanes(box);
  const std::array<std::pair<double, double>, 4> pq = {
      std::pair{-d.x(), a.x() - box.u0}, std::pair{d.x(), box.u1 - a.x()},
      std::pair{-d.y(), a.y() - box.v0}, std::pair{d.y(), box.v1 - a.y()}};
  for (int i = 0; i < 4; ++i) {
    const auto [p, q] = pq[static_cast<std::size_t>(i)];
    if (p == 0.0) {
      if (q < 0.0) return false;
    } else {
      const double r = q / p;
      if (p < 0.0) {
        if (r > t1) return false;
        if (r > t0) t0 = r, edge0 = i;
      } else {
        if (r < t0) return false;
        if (r < t1) t1 = r, edge1 = i;
      }
    }
  }
  const auto cutAt = [&](double t, int edge) {
    Vec2 r = a + t * d;
    const HalfPlane& hp = planes[static_cast<std::size_t>(edge)];
    r[hp.axis] = hp.limit;
    return clampInto(r, box);
  };
  ca = edge0 >= 0 ? cutAt(t0, edge0) : a;
  cb = edge1 >= 0 ? cutAt(t1, edge1) : b;
  return ca.allFinite() && cb.allFinite();
}

}  // namespace

std::vector<Vec2> clipRing(const std::vector<Vec2>& ring, const ClipBox& box) {
  std::vector<Vec2> pts;
  pts.reserve(ring.size());
  for (const Vec2& p : ring) {
    if (p.allFinite()) pts.push_back(p);
  }
  for (const HalfPlane& hp : halfPlanes(box)) {
    if (pts.empty()) break;
    std::vector<Vec2> out;
    out.reserve(pts.size() + 4);
    Vec2 prev = pts.back();
    bool prev_in = hp.inside(prev);
    for (const Vec2& cur : pts) {
      const bool cur_in = hp.inside(cur);
      if (cur_in != prev_in) out.push_back(hp.cut(prev, cur));
      if (cur_in) out.push_back(cur);
      prev = cur;
      prev_in = cur_in;
    }
    pts = std::move(out);
  }
  // Far-away input can round a cut point a hair outside, or overflow (b - a) to infinity.
  std::vector<Vec2> result;
  result.reserve(pts.size());
  for (const Vec2& p : pts) {
    if (p.allFinite()) result.push_back(clampInto(p, box));
  }
  return result;
}

std::vector<std::vector<Vec2>> clipPolyline(const std::vector<Vec2>& points, const ClipBox& box) {
  std::vector<std::vector<Vec2>> pieces;
  std::vector<Vec2> piece;
  auto flush = [&] {
    if (piece.size() >= 2) pieces.push_back(std::move(piece));
    piece.clear();
  };
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const Vec2& a = points[i];
    const Vec2& b = points[i + 1];
    if (!a.allFinite() || !b.allFinite()) {
      flush();
      continue;
    }
    Vec2 ca, cb;
    if (!clipSegment(a, b, box, ca, cb)) {
      flush();
      continue;
    }
    if (piece.empty() || ca != a) {
      flush();
      piece.push_back(ca);
    }
    piece.push_back(cb);
    if (cb != b) flush();
  }
  flush();
  return pieces;
}

double dashOn(double stroke_width) { return std::max(4.0, 3.0 * sanitizeStrokeWidth(stroke_width)); }
double dashOff(double stroke_width) { return std::max(4.0, 3.0 * sanitizeStrokeWidth(stroke_width)); }

double sanitizeTextSize(double size_px) {
  if (!std::isfinite(size_px) || size_px <= 0.0) return 0.0;
  return std::min(size_px, 2000.0);
}

double haloReachPx(double size_px) { return std::max(1.5, 0.15 * size_px); }

namespace {

/// The next code point of `s` from `i` (advancing `i`), or -1 for an invalid byte (advancing by 1).
long nextCodePoint(const std::string& s, std::size_t& i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = byte(i);
  if (c < 0x80) {
    ++i;
    return c;
  }
  int len = 0;
  long cp = 0, min = 0;
  if ((c & 0xE0) == 0xC0) {
    len = 2, cp = c & 0x1F, min = 0x80;
  } else if ((c & 0xF0) == 0xE0) {
    len = 3, cp = c & 0x0F, min = 0x800;
  } else if ((c & 0xF8) == 0xF0) {
    len = 4, cp = c & 0x07, min = 0x10000;
  } else {
    ++i;
    return -1;
  }
  if (i + static_cast<std::size_t>(len) > s.size()) {
    ++i;
    return -1;
  }
  for (int k = 1; k < len; ++k) {
    const unsigned char cc = byte(i + static_cast<std::size_t>(k));
    if ((cc & 0xC0) != 0x80) {
      ++i;
      return -1;
    }
    cp = (cp << 6) | (cc & 0x3F);
  }
  if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) {
    ++i;
    return -1;
  }
  i += static_cast<std::size_t>(len);
  return cp;
}

void appendUtf8(std::string& out, long cp) {
  if (cp < 0x80) {
    out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    out += static_cast<char>(0xC0 | (cp >> 6));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += static_cast<char>(0xE0 | (cp >> 12));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (cp >> 18));
    out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  }
}

}  // namespace

std::string cleanUtf8(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    long cp = nextCodePoint(text, i);
    if (cp < 0 || cp == 0xFFFE || cp == 0xFFFF) cp = 0xFFFD;  // not allowed in XML
    if (cp < 0x20 || cp == 0x7F) cp = ' ';
    appendUtf8(out, cp);
  }
  return out;
}

std::string toAsciiForRaster(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const long cp = nextCodePoint(text, i);
    if (cp < 0 || cp > 0x7F) {
      out += '?';
    } else if (cp < 0x20 || cp == 0x7F) {
      out += ' ';
    } else {
      out += static_cast<char>(cp);
    }
  }
  return out;
}

}  // namespace detail

}  // namespace mapnav::render
