#pragma once
// Internal to render/: what the SVG and PNG writers share, so that both draw the same thing
// (sanitised styles, clipping, dash pattern, text metrics that must agree).
#include <string>
#include <vector>

#include "mapnav/render/canvas.h"

namespace mapnav::render::detail {

/// Beyond this many pixels from the origin a point (text, circle centre) is not drawn; line and
/// polygon geometry is clipped to a box well inside it. Keeps every pixel coordinate far from int
/// overflow in OpenCV's fixed-point (shift = 4) arithmetic.
inline constexpr double kFarPx = 1.0e6;

struct ClipBox {
  double u0, v0, u1, v1;
};

/// The canvas grown by a generous margin (larger than any stroke), so that clipping never changes
/// what is visible.
ClipBox clipBoxFor(int width, int height, double stroke_width_px);

/// Opacity clamped to 0..1 (NaN → 1).
double sanitizeOpacity(double opacity);
/// A usable stroke width: non-finite or ≤ 0 → 1, at most 1000.
double sanitizeStrokeWidth(double width);
/// The pixel thickness OpenCV draws a stroke with: round(width), at least 1.
int strokeThickness(double width);

/// Finite and within kFarPx of the origin.
bool usablePoint(const Vec2& p);

/// The ring without non-finite vertices, clipped to `box` (Sutherland–Hodgman). A ring already
/// inside the box comes back unchanged. Fewer than 3 points when nothing is left to fill.
std::vector<Vec2> clipRing(const std::vector<Vec2>& ring, const ClipBox& box);

/// The polyline broken at non-finite points and where it leaves `box`; every piece has ≥ 2 points.
std::vector<std::vector<Vec2>> clipPolyline(const std::vector<Vec2>& points, const ClipBox& box);

/// The dash pattern of a dashed stroke of this width: `dashOn` px drawn, then `dashOff` px gap.
double dashOn(double stroke_width);
double dashOff(double stroke_width);

/// Text: a usable size (0 when the text is not to be drawn), the halo's reach beyond the glyphs,
/// and SVG's font-size for the cap height `size_px` (sans-serif caps are about 0.7 em).
double sanitizeTextSize(double size_px);
double haloReachPx(double size_px);
inline constexpr double kCapHeightPerEm = 0.7;

/// Valid UTF-8 with control characters turned into spaces and invalid bytes into U+FFFD.
std::string cleanUtf8(const std::string& text);
/// ASCII only, for OpenCV's Hershey fonts: control characters → ' ', every non-ASCII code point
/// (or invalid byte) → '?'.
std::string toAsciiForRaster(const std::string& text);

}  // namespace mapnav::render::detail
