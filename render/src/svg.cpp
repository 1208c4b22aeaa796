// Canvas → a standalone SVG 1.1 document. Plain text, locale-independent numbers (std::to_chars),
// so the same drawing always gives the same bytes.
#include <array>
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <system_error>
#include <variant>

#include "detail.h"
#include "mapnav/render/canvas.h"
#include "mapnav/render/xml.h"

namespace mapnav::render {
namespace {

/// Two decimals, never "-0.00".
void appendNumber(std::string& out, double x) {
  std::array<char, 64> buf{};
  const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), x, std::chars_format::fixed, 2);
  std::string s = ec == std::errc() ? std::string(buf.data(), end) : std::string("0.00");
  if (s == "-0.00") s = "0.00";
  out += s;
}

void appendColor(std::string& out, const Rgb& c) {
  static constexpr char kHex[] = "0123456789abcdef";
  out += '#';
  for (std::uint8_t v : {c.r, c.g, c.b}) {
    out += kHex[v >> 4];
    out += kHex[v & 0x0F];
  }
}

/// `name="number"` with a leading space.
void attr(std::string& out, const char* name, double value) {
  out += ' ';
  out += name;
  out += "=\"";
  appendNumber(out, value);
  out += '"';
}

void attr(std::string& out, const char* name, const Rgb& color) {
  out += ' ';
  out += name;
  out += "=\"";
  appendColor(out, color);
  out += '"';
}

void attr(std::string& out, const char* name, const char* value) {
  out += ' ';
  out += name;
  out += "=\"";
  out += value;
  out += '"';
}

void appendEscaped(std::string& out, const std::string& text) { out += escapeXml(text); }

void appendPoints(std::string& out, const std::vector<Vec2>& pts) {
  out += " points=\"";
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (i > 0) out += ' ';
    appendNumber(out, pts[i].x());
    out += ',';
    appendNumber(out, pts[i].y());
  }
  out += '"';
}

/// fill, stroke, width, joins, dashes, opacity. `polyline` ignores the fill (a polyline is a line).
void appendStyle(std::string& out, const Style& style, bool polyline) {
  if (style.fill && !polyline) {
    attr(out, "fill", *style.fill);
  } else {
    attr(out, "fill", "none");
  }
  if (style.stroke) {
    const double w = detail::sanitizeStrokeWidth(style.stroke_width_px);
    attr(out, "stroke", *style.stroke);
    attr(out, "stroke-width", w);
    attr(out, "stroke-linejoin", "round");
    attr(out, "stroke-linecap", "round");  // OpenCV's thick lines have round ends too
    if (style.dashed) {
      out += " stroke-dasharray=\"";
      appendNumber(out, detail::dashOn(w));
      out += ' ';
      appendNumber(out, detail::dashOff(w));
      out += '"';
    }
  } else {
    attr(out, "stroke", "none");
  }
  const double opacity = detail::sanitizeOpacity(style.opacity);
  if (opacity < 1.0) attr(out, "opacity", opacity);
}

class SvgWriter {
 public:
  SvgWriter(std::string& out, int width, int height) : out_(out), width_(width), height_(height) {}

  void operator()(const Canvas::PolygonCmd& cmd) const {
    const bool fill = cmd.style.fill.has_value(), stroke = cmd.style.stroke.has_value();
    if ((!fill && !stroke) || detail::sanitizeOpacity(cmd.style.opacity) <= 0.0) return;
    const std::vector<Vec2> ring =
        detail::clipRing(cmd.points, detail::clipBoxFor(width_, height_, cmd.style.stroke_width_px));
    if (ring.size() < 2 || (ring.size() < 3 && !stroke)) return;
    out_ += "<polygon";
    appendPoints(out_, ring);
    Style style = cmd.style;
    if (ring.size() < 3) style.fill.reset();  // nothing to fill, only the outline
    appendStyle(out_, style, false);
    out_ += "/>\n";
  }

  void operator()(const Canvas::PolylineCmd& cmd) const {
    if (!cmd.style.stroke || detail::sanitizeOpacity(cmd.style.opacity) <= 0.0) return;
    for (const std::vector<Vec2>& piece :
         detail::clipPolyline(cmd.points, detail::clipBoxFor(width_, height_, cmd.style.stroke_width_px))) {
      out_ += "<polyline";
      appendPoints(out_, piece);
      appendStyle(out_, cmd.style, true);
      out_ += "/>\n";
    }
  }

  void operator()(const Canvas::CircleCmd& cmd) const {
    const bool fill = cmd.style.fill.has_value(), stroke = cmd.style.stroke.has_value();
    if ((!fill && !stroke) || detail::sanitizeOpacity(cmd.style.opacity) <= 0.0) return;
    if (!detail::usablePoint(cmd.center) || !std::isfinite(cmd.radius) || cmd.radius <= 0.0 ||
        cmd.radius > detail::kFarPx) {
      return;
    }
    out_ += "<circle";
    attr(out_, "cx", cmd.center.x());
    attr(out_, "cy", cmd.center.y());
    attr(out_, "r", cmd.radius);
    appendStyle(out_, cmd.style, false);
    out_ += "/>\n";
  }

  void operator()(const Canvas::TextCmd& cmd) const {
    const double size = detail::sanitizeTextSize(cmd.style.size_px);
    if (size <= 0.0 || cmd.text.empty() || !detail::usablePoint(cmd.position)) return;
    out_ += "<text";
    attr(out_, "x", cmd.position.x());
    attr(out_, "y", cmd.position.y());
    attr(out_, "font-family", "sans-serif");
    attr(out_, "font-size", size / detail::kCapHeightPerEm);
    switch (cmd.style.anchor) {
      case Anchor::Start: attr(out_, "text-anchor", "start"); break;
      case Anchor::Middle: attr(out_, "text-anchor", "middle"); break;
      case Anchor::End: attr(out_, "text-anchor", "end"); break;
    }
    if (cmd.style.bold) attr(out_, "font-weight", "bold");
    attr(out_, "fill", cmd.style.color);
    if (cmd.style.halo) {
      // The stroke is centred on the glyph outline: twice the reach, painted under the fill.
      attr(out_, "stroke", *cmd.style.halo);
      attr(out_, "stroke-width", 2.0 * detail::haloReachPx(size));
      attr(out_, "stroke-linejoin", "round");
      attr(out_, "style", "paint-order: stroke");
    }
    out_ += '>';
    appendEscaped(out_, detail::cleanUtf8(cmd.text));
    out_ += "</text>\n";
  }

 private:
  std::string& out_;
  int width_, height_;
};

}  // namespace

std::string escapeXml(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string Canvas::toSvg() const {
  std::string out;
  out.reserve(256 + 96 * commands_.size());
  out += "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n";
  const std::string w = std::to_string(width_), h = std::to_string(height_);
  out += "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" + w + "\" height=\"" + h +
         "\" viewBox=\"0 0 " + w + " " + h + "\">\n";
  out += "<rect x=\"0\" y=\"0\" width=\"" + w + "\" height=\"" + h + "\"";
  attr(out, "fill", background_);
  out += "/>\n";
  const SvgWriter writer(out, width_, height_);
  for (const Command& cmd : commands_) std::visit(writer, cmd);
  out += "</svg>\n";
  return out;
}

}  // namespace mapnav::render
