#pragma once
// A Canvas records drawing commands in pixel coordinates (u right, v down) and writes them as SVG
// or PNG; the same drawing gives both. A `View` maps world metres (x east, y north) to pixels with
// north up and equal scale on both axes.
//
// Pixel (i, j) covers [i, i+1) x [j, j+1), as in SVG, so a square from (10, 10) to (20, 20) covers
// pixels 10..19 in both outputs (in PNG, OpenCV's anti-aliasing softens edges over about one more
// pixel). Both outputs skip what cannot be drawn instead of failing:
// non-finite coordinates (a polygon drops such vertices, a polyline breaks there, a circle or a text
// at such a point is left out), non-positive radii and text sizes, empty text. Geometry far off the
// canvas is clipped. Opacity is clamped to 0..1; a non-finite or non-positive stroke width counts
// as 1 px.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "mapnav/geometry/types.h"

namespace mapnav::render {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb&) const = default;
};

struct Style {
  std::optional<Rgb> fill;    ///< no fill when empty
  std::optional<Rgb> stroke;  ///< no outline when empty
  double stroke_width_px = 1.0;
  double opacity = 1.0;       ///< 0..1, for fill and stroke
  bool dashed = false;
};

enum class Anchor { Start, Middle, End };

/// Text is placed with its baseline at the given position; `anchor` puts the start, the middle or
/// the end of the text there. Only ASCII is drawn in PNG (other characters show as '?'); SVG keeps
/// UTF-8.
struct TextStyle {
  double size_px = 12.0;  ///< cap height roughly, in pixels
  Rgb color{0, 0, 0};
  Anchor anchor = Anchor::Middle;
  bool bold = false;
  std::optional<Rgb> halo;  ///< a thin outline in this colour so text reads on any background
};

/// The largest canvas side, in pixels, that View and Canvas accept.
inline constexpr int kMaxCanvasSidePx = 16384;

/// World metres → pixels: north up, `pixels_per_metre` on both axes.
/// An empty or non-finite box counts as 1 m x 1 m around the origin, and a box thinner than 1 m is
/// widened to 1 m about its centre. The world box is centred in the canvas. Throws InvalidInput for
/// a size outside 1..kMaxCanvasSidePx or a negative or non-finite margin.
class View {
 public:
  /// Fits `world` into width × height pixels with `margin_px` on every side, keeping the aspect.
  View(const Box2& world, int width_px, int height_px, double margin_px);
  /// Fits `world` into a canvas `width_px` wide whose height follows from the aspect ratio (at
  /// least 1 px; at most kMaxCanvasSidePx, in which case the world is scaled down to fit).
  static View fitWidth(const Box2& world, int width_px, double margin_px);

  Vec2 toPixel(const Vec2& world) const;
  double pixelsPerMetre() const { return scale_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  double scale_ = 1.0;
  Vec2 world_center_ = Vec2::Zero();
  int width_ = 0, height_ = 0;
};

class Canvas {
 public:
  /// Throws InvalidInput for a size outside 1..kMaxCanvasSidePx.
  Canvas(int width_px, int height_px, Rgb background);

  int width() const { return width_; }
  int height() const { return height_; }

  // All coordinates in pixels.
  void polygon(const std::vector<Vec2>& ring, const Style& style);
  void polyline(const std::vector<Vec2>& points, const Style& style);
  void circle(const Vec2& center, double radius_px, const Style& style);
  void text(const Vec2& position, const std::string& text, const TextStyle& style);

  std::string toSvg() const;
  /// The PNG file's bytes (8-bit RGB), anti-aliased.
  std::string toPng() const;
  /// Writes SVG or PNG by the extension (.svg / .png, case-insensitive), atomically. Throws
  /// InvalidInput for another extension, IoError when it cannot write.
  void save(const std::filesystem::path& path) const;

  struct PolygonCmd { std::vector<Vec2> points; Style style; };
  struct PolylineCmd { std::vector<Vec2> points; Style style; };
  struct CircleCmd { Vec2 center; double radius; Style style; };
  struct TextCmd { Vec2 position; std::string text; TextStyle style; };
  using Command = std::variant<PolygonCmd, PolylineCmd, CircleCmd, TextCmd>;
  const std::vector<Command>& commands() const { return commands_; }

 private:
  int width_, height_;
  Rgb background_;
  std::vector<Command> commands_;
};

/// A scale bar of a round length (1, 2, 5 × 10^k m) about `target_px` long, bottom-left, and a
/// north arrow, top-right. Every map picture carries both.
/// The bar is shortened (to the next smaller round length) when it would not fit the canvas.
/// Throws InvalidInput when `target_px` is not positive and finite.
/// `panel` (pixels) confines both to one panel of a picture made of several; default: the canvas.
void drawScaleBarAndNorthArrow(Canvas& canvas, const View& view, double target_px = 120.0,
                               const std::optional<Box2>& panel = std::nullopt);

/// The round length (1, 2 or 5 x 10^k m) nearest to `metres` (by absolute difference; on a tie the
/// shorter one): 50 for 50, 100 for 120, 50 for 75, 2 for 3.4. Throws InvalidInput when `metres` is
/// not positive and finite.
double niceScaleLength(double metres);

/// The scale bar's label: "20 m", "0.5 m", "1 km" and "2.5 km" (kilometres from 1000 m on).
std::string scaleLengthLabel(double metres);

}  // namespace mapnav::render
