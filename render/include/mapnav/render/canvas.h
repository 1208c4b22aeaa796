#pragma once
// A Canvas records drawing commands in pixel coordinates (u right, v down) and writes them as SVG
// or PNG; the same drawing gives both. A `View` maps world metres (x east, y north) to pixels with
// north up and equal scale on both axes.
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

struct TextStyle {
  double size_px = 12.0;  ///< cap height roughly, in pixels
  Rgb color{0, 0, 0};
  Anchor anchor = Anchor::Middle;
  bool bold = false;
  std::optional<Rgb> halo;  ///< a thin outline in this colour so text reads on any background
};

/// World metres → pixels: north up, `pixels_per_metre` on both axes.
class View {
 public:
  /// Fits `world` into width × height pixels with `margin_px` on every side, keeping the aspect.
  View(const Box2& world, int width_px, int height_px, double margin_px);
  /// Fits `world` into a canvas `width_px` wide whose height follows from the aspect ratio.
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
void drawScaleBarAndNorthArrow(Canvas& canvas, const View& view, double target_px = 120.0);

}  // namespace mapnav::render
