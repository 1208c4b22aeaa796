#include "mapnav/render/canvas.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <variant>
#include <vector>

#include <gtest/gtest.h>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/image/png.h"
#include "mapnav/testing/support.h"

namespace mapnav::render {
namespace {

namespace fs = std::filesystem;

const Rgb kWhite{255, 255, 255};
const Rgb kBlack{0, 0, 0};
const Rgb kRed{255, 0, 0};
const Rgb kBlue{0, 0, 255};
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Style fillOnly(Rgb c, double opacity = 1.0) { return Style{c, std::nullopt, 1.0, opacity, false}; }
Style strokeOnly(Rgb c, double width, bool dashed = false) { return Style{std::nullopt, c, width, 1.0, dashed}; }

std::vector<Vec2> square(double u0, double v0, double u1, double v1) {
  return {{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}};
}

Image decode(const std::string& png) {
  return decodePng(std::span(reinterpret_cast<const std::uint8_t*>(png.data()), png.size()), "canvas");
}

/// The pixel at column u, row v as RGB.
Rgb at(const Image& img, int u, int v) {
  const std::uint8_t* p = img.pixel(u, v);
  return {p[0], p[1], p[2]};
}

::testing::AssertionResult rgbNear(const Rgb& actual, const Rgb& expected, int tolerance) {
  const int dr = std::abs(actual.r - expected.r), dg = std::abs(actual.g - expected.g),
            db = std::abs(actual.b - expected.b);
  if (dr <= tolerance && dg <= tolerance && db <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "rgb(" << int(actual.r) << "," << int(actual.g) << "," << int(actual.b)
                                       << ") vs expected rgb(" << int(expected.r) << "," << int(expected.g) << ","
                                       << int(expected.b) << "), tolerance " << tolerance;
}
#define EXPECT_RGB(img, u, v, expected, tol) EXPECT_TRUE(rgbNear(at((img), (u), (v)), (expected), (tol))) \
    << "at pixel (" << (u) << ", " << (v) << ")"

bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

// ---- View ---------------------------------------------------------------------------------------

TEST(View, MapsWorldPointsToPixelsNorthUp) {
  // 100 m x 50 m into 220 x 120 px with 10 px margins: 200 / 100 = 2 = 100 / 50 px per metre.
  const View view(Box2(Vec2(0, 0), Vec2(100, 50)), 220, 120, 10);
  EXPECT_DOUBLE_EQ(view.pixelsPerMetre(), 2.0);
  EXPECT_EQ(view.width(), 220);
  EXPECT_EQ(view.height(), 120);
  EXPECT_VEC2_NEAR(view.toPixel({0, 0}), Vec2(10, 110), 1e-9);    // south-west corner: bottom-left
  EXPECT_VEC2_NEAR(view.toPixel({100, 50}), Vec2(210, 10), 1e-9);  // north-east corner: top-right
  EXPECT_VEC2_NEAR(view.toPixel({50, 25}), Vec2(110, 60), 1e-9);   // centre
  EXPECT_VEC2_NEAR(view.toPixel({0, 50}), Vec2(10, 10), 1e-9);
  // North up: going north (larger y) goes up the picture (smaller v), east goes right.
  EXPECT_LT(view.toPixel({30, 40}).y(), view.toPixel({30, 10}).y());
  EXPECT_GT(view.toPixel({40, 30}).x(), view.toPixel({10, 30}).x());
}

TEST(View, KeepsAspectAndCentresTheWorld) {
  // 300 px wide leaves 280 px for 100 m (2.8 px/m) but 100 px for 50 m (2 px/m): the height rules.
  const View view(Box2(Vec2(0, 0), Vec2(100, 50)), 300, 120, 10);
  EXPECT_DOUBLE_EQ(view.pixelsPerMetre(), 2.0);
  EXPECT_VEC2_NEAR(view.toPixel({0, 0}), Vec2(50, 110), 1e-9);  // 200 px of world centred in 300
  EXPECT_VEC2_NEAR(view.toPixel({100, 50}), Vec2(250, 10), 1e-9);
  // Equal scale: 10 m east and 10 m north are both 20 px.
  const Vec2 o = view.toPixel({20, 20});
  EXPECT_VEC2_NEAR(view.toPixel({30, 20}) - o, Vec2(20, 0), 1e-9);
  EXPECT_VEC2_NEAR(view.toPixel({20, 30}) - o, Vec2(0, -20), 1e-9);
}

TEST(View, FitWidthComputesTheHeightFromTheAspect) {
  const View view = View::fitWidth(Box2(Vec2(-50, 100), Vec2(50, 150)), 220, 10);
  EXPECT_EQ(view.width(), 220);
  EXPECT_EQ(view.height(), 120);  // 50 m * 2 px/m + 2 * 10 px
  EXPECT_DOUBLE_EQ(view.pixelsPerMetre(), 2.0);
  EXPECT_VEC2_NEAR(view.toPixel({-50, 150}), Vec2(10, 10), 1e-9);
  EXPECT_VEC2_NEAR(view.toPixel({50, 100}), Vec2(210, 110), 1e-9);
}

TEST(View, PadsDegenerateAndEmptyBoxesToOneMetre) {
  // A single point: 1 m x 1 m around it.
  const View point = View::fitWidth(Box2(Vec2(5, 7), Vec2(5, 7)), 102, 1);
  EXPECT_DOUBLE_EQ(point.pixelsPerMetre(), 100.0);
  EXPECT_EQ(point.height(), 102);
  EXPECT_VEC2_NEAR(point.toPixel({5, 7}), Vec2(51, 51), 1e-9);
  // A horizontal segment: 100 m x 1 m.
  const View line = View::fitWidth(Box2(Vec2(0, 0), Vec2(100, 0)), 220, 10);
  EXPECT_DOUBLE_EQ(line.pixelsPerMetre(), 2.0);
  EXPECT_EQ(line.height(), 22);  // 1 m * 2 px/m + 20 px
  EXPECT_VEC2_NEAR(line.toPixel({0, 0}), Vec2(10, 11), 1e-9);
  // An empty box (Eigen's default) and a non-finite one: 1 m x 1 m around the origin.
  for (const Box2& bad : {Box2(), Box2(Vec2(0, 0), Vec2(kNaN, 1)), Box2(Vec2(-kInf, 0), Vec2(1, 1))}) {
    const View v = View::fitWidth(bad, 50, 0);
    EXPECT_GE(v.height(), 1);
    EXPECT_DOUBLE_EQ(v.pixelsPerMetre(), 50.0);
    EXPECT_VEC2_NEAR(v.toPixel({0, 0}), Vec2(25, 25), 1e-9);
  }
}

TEST(View, FitWidthCapsTheHeightAndStillFits) {
  // 1 m wide, 100 km tall: the height is capped and the scale shrinks so that all of it fits.
  const View view = View::fitWidth(Box2(Vec2(0, 0), Vec2(1, 100000)), 500, 0);
  EXPECT_EQ(view.height(), kMaxCanvasSidePx);
  EXPECT_GE(view.toPixel({0, 0}).y(), view.height() - 1e-6);
  EXPECT_GE(view.toPixel({0, 100000}).y(), -1e-6);
  EXPECT_LE(view.toPixel({0, 0}).y(), view.height() + 1e-6);
}

TEST(View, RejectsBadSizesAndMargins) {
  const Box2 box(Vec2(0, 0), Vec2(10, 10));
  EXPECT_THROW(View(box, 0, 100, 0), InvalidInput);
  EXPECT_THROW(View(box, 100, -1, 0), InvalidInput);
  EXPECT_THROW(View(box, kMaxCanvasSidePx + 1, 100, 0), InvalidInput);
  EXPECT_THROW(View(box, 100, 100, -1), InvalidInput);
  EXPECT_THROW(View(box, 100, 100, kNaN), InvalidInput);
  EXPECT_THROW(View::fitWidth(box, 0, 0), InvalidInput);
  // A margin that leaves no room still gives a usable view.
  const View tight(box, 10, 10, 20);
  EXPECT_TRUE(std::isfinite(tight.pixelsPerMetre()));
  EXPECT_GT(tight.pixelsPerMetre(), 0.0);
}

TEST(Canvas, RejectsBadSizes) {
  EXPECT_THROW(Canvas(0, 10, kWhite), InvalidInput);
  EXPECT_THROW(Canvas(10, 0, kWhite), InvalidInput);
  EXPECT_THROW(Canvas(kMaxCanvasSidePx + 1, 10, kWhite), InvalidInput);
  EXPECT_NO_THROW(Canvas(1, 1, kWhite));
}

TEST(Canvas, RecordsCommands) {
  Canvas canvas(10, 10, kWhite);
  canvas.polygon(square(1, 1, 2, 2), fillOnly(kRed));
  canvas.polyline({{0, 0}, {5, 5}}, strokeOnly(kBlack, 1));
  canvas.circle({5, 5}, 2, fillOnly(kBlue));
  canvas.text({5, 5}, "x", TextStyle{});
  ASSERT_EQ(canvas.commands().size(), 4u);
  EXPECT_TRUE(std::holds_alternative<Canvas::PolygonCmd>(canvas.commands()[0]));
  EXPECT_TRUE(std::holds_alternative<Canvas::PolylineCmd>(canvas.commands()[1]));
  EXPECT_TRUE(std::holds_alternative<Canvas::CircleCmd>(canvas.commands()[2]));
  EXPECT_EQ(std::get<Canvas::TextCmd>(canvas.commands()[3]).text, "x");
}

// ---- PNG ----------------------------------------------------------------------------------------

TEST(Png, FilledSquareIsRedInsideAndBackgroundOutside) {
  Canvas canvas(40, 30, kWhite);
  canvas.polygon(square(10, 10, 20, 20), fillOnly(kRed));
  const Image img = decode(canvas.toPng());
  ASSERT_EQ(img.width, 40);
  ASSERT_EQ(img.height, 30);
  ASSERT_EQ(img.channels, 3);  // 8-bit RGB, no alpha
  // Inside, including the first and last pixel rows/columns of the square (pixel i covers [i, i+1)).
  for (int v = 10; v < 20; ++v) {
    for (int u = 10; u < 20; ++u) EXPECT_RGB(img, u, v, kRed, 0);
  }
  // Outside: everything two pixels or more away from the square (OpenCV's anti-aliasing blurs the
  // edge over about one pixel outside).
  for (int v = 0; v < 30; ++v) {
    for (int u = 0; u < 40; ++u) {
      if (u >= 8 && u <= 21 && v >= 8 && v <= 21) continue;
      EXPECT_RGB(img, u, v, kWhite, 0);
    }
  }
  // The edge pixels just outside are a blend of red and white, never another colour.
  for (const auto& [u, v] : std::vector<std::pair<int, int>>{{9, 15}, {20, 15}, {15, 9}, {15, 20}}) {
    const Rgb p = at(img, u, v);
    EXPECT_EQ(p.r, 255);
    EXPECT_EQ(p.g, p.b);
  }
}

TEST(Png, OpacityBlendsWithWhatIsUnder) {
  Canvas canvas(40, 30, kWhite);
  canvas.polygon(square(0, 0, 20, 30), fillOnly(kBlue));  // left half blue
  canvas.polygon(square(5, 5, 35, 25), fillOnly(kRed, 0.5));
  const Image img = decode(canvas.toPng());
  // 0.5 red over white: (255, 127.5, 127.5); over blue: (127.5, 0, 127.5).
  EXPECT_RGB(img, 28, 15, (Rgb{255, 128, 128}), 2);
  EXPECT_RGB(img, 10, 15, (Rgb{128, 0, 128}), 2);
  EXPECT_RGB(img, 38, 15, kWhite, 0);  // outside the translucent square: untouched
  EXPECT_RGB(img, 2, 15, kBlue, 0);

  Canvas quarter(20, 20, kBlack);
  quarter.polygon(square(0, 0, 20, 20), fillOnly(kWhite, 0.25));
  EXPECT_RGB(decode(quarter.toPng()), 10, 10, (Rgb{64, 64, 64}), 2);  // 0.25 * 255 = 63.75
}

TEST(Png, StrokesSolidAndDashedLines) {
  Canvas canvas(60, 30, kWhite);
  canvas.polyline({{5, 10.5}, {55, 10.5}}, strokeOnly(kBlack, 3));
  canvas.polyline({{5, 20.5}, {55, 20.5}}, strokeOnly(kBlack, 1, true));
  const Image img = decode(canvas.toPng());
  int solid_dark = 0, dashed_dark = 0, dashed_light = 0;
  for (int u = 8; u < 52; ++u) {
    if (at(img, u, 10).r < 60) ++solid_dark;
    if (at(img, u, 20).r < 100) ++dashed_dark;
    if (at(img, u, 20).r > 200) ++dashed_light;
  }
  EXPECT_EQ(solid_dark, 44);  // solid all along
  EXPECT_GT(dashed_dark, 10);  // dashed: pieces ...
  EXPECT_GT(dashed_light, 10);  // ... with gaps
  EXPECT_RGB(img, 30, 9, kBlack, 60);  // 3 px thick: rows 9..11
  EXPECT_RGB(img, 30, 11, kBlack, 60);
  EXPECT_RGB(img, 30, 14, kWhite, 0);
  EXPECT_RGB(img, 30, 2, kWhite, 0);
}

TEST(Png, DrawsCirclesAndPolygonOutlines) {
  Canvas canvas(40, 40, kWhite);
  // Centres on .5: 1 px lines then fall on whole pixels (pixel i covers [i, i+1)).
  canvas.circle({20.5, 20.5}, 8, Style{Rgb{0, 200, 0}, kBlack, 1, 1.0, false});
  canvas.polygon(square(2.5, 2.5, 37.5, 37.5), strokeOnly(kBlue, 1));
  const Image img = decode(canvas.toPng());
  EXPECT_RGB(img, 20, 20, (Rgb{0, 200, 0}), 0);
  EXPECT_RGB(img, 20, 20 + 8, kBlack, 90);  // the outline at the radius
  EXPECT_RGB(img, 6, 6, kWhite, 0);         // between circle and frame
  EXPECT_RGB(img, 20, 2, kBlue, 90);        // the frame
  EXPECT_RGB(img, 20, 0, kWhite, 0);        // outside the frame
}

/// Columns of dark pixels in rows v0..v1.
std::pair<int, int> inkColumns(const Image& img, int v0, int v1) {
  int lo = img.width, hi = -1;
  for (int v = v0; v <= v1; ++v) {
    for (int u = 0; u < img.width; ++u) {
      if (at(img, u, v).r < 128) lo = std::min(lo, u), hi = std::max(hi, u);
    }
  }
  return {lo, hi};
}

TEST(Png, TextIsAnchoredAndAboutSizePxTall) {
  TextStyle style;
  style.size_px = 20;
  for (Anchor anchor : {Anchor::Start, Anchor::Middle, Anchor::End}) {
    style.anchor = anchor;
    Canvas canvas(200, 60, kWhite);
    canvas.text({100, 40}, "HHHH", style);
    const Image img = decode(canvas.toPng());
    const auto [lo, hi] = inkColumns(img, 0, 59);
    ASSERT_LT(lo, hi) << "no text drawn";
    if (anchor == Anchor::Start) {
      EXPECT_NEAR(lo, 100, 4);
      EXPECT_GT(hi, 140);
    } else if (anchor == Anchor::Middle) {
      EXPECT_NEAR(0.5 * (lo + hi), 100, 4);
    } else {
      EXPECT_NEAR(hi, 100, 6);  // the advance width includes the last glyph's side bearing
      EXPECT_LT(lo, 60);
    }
    // Cap height ≈ size_px, standing on the baseline v = 40.
    int top = 60, bottom = -1;
    for (int v = 0; v < 60; ++v) {
      for (int u = 0; u < 200; ++u) {
        if (at(img, u, v).r < 128) top = std::min(top, v), bottom = std::max(bottom, v);
      }
    }
    EXPECT_NEAR(bottom - top + 1, 20, 3);
    EXPECT_NEAR(bottom, 39, 2);
  }
}

TEST(Png, HaloOutlinesTheText) {
  TextStyle style;
  style.size_px = 16;
  style.color = kWhite;
  style.bold = true;
  Canvas plain(120, 40, kWhite);
  plain.text({60, 30}, "MAP", style);
  style.halo = kBlack;
  Canvas haloed(120, 40, kWhite);
  haloed.text({60, 30}, "MAP", style);
  auto dark = [](const Image& img) {
    int n = 0;
    for (int v = 0; v < img.height; ++v) {
      for (int u = 0; u < img.width; ++u) n += at(img, u, v).r < 100;
    }
    return n;
  };
  EXPECT_EQ(dark(decode(plain.toPng())), 0);  // white on white: invisible
  EXPECT_GT(dark(decode(haloed.toPng())), 50);  // the black halo makes it readable
}

TEST(Png, SkipsNonFiniteAndClipsFarCoordinates) {
  Canvas canvas(40, 30, kWhite);
  // A huge square (vertices 1e12 px away) covers the whole canvas once clipped.
  canvas.polygon(square(-1e12, -1e12, 1e12, 1e12), fillOnly(kBlue));
  // A NaN vertex is dropped: the rest is still a square.
  canvas.polygon({{10, 10}, {20, 10}, {kNaN, 5}, {20, 20}, {10, 20}}, fillOnly(kRed));
  canvas.polyline({{0, 0}, {kInf, 3}, {5, 5}, {kNaN, kNaN}}, strokeOnly(kBlack, 2));
  canvas.polyline({{-1e300, 25.5}, {1e300, 25.5}}, strokeOnly(kBlack, 1));
  canvas.circle({kNaN, 3}, 5, fillOnly(kBlack));
  canvas.circle({5, 5}, kInf, fillOnly(kBlack));
  canvas.circle({5, 5}, -3, fillOnly(kBlack));
  canvas.circle({1e200, 5}, 1e250, fillOnly(kBlack));
  canvas.text({kNaN, 10}, "nan", TextStyle{});
  canvas.text({1e300, 10}, "far", TextStyle{});
  canvas.text({10, 10}, "", TextStyle{});
  TextStyle bad;
  bad.size_px = kNaN;
  canvas.text({10, 10}, "bad size", bad);
  canvas.polygon(square(30, 1, 35, 6), Style{kBlack, kBlack, kNaN, kNaN, true});
  std::string png;
  ASSERT_NO_THROW(png = canvas.toPng());
  const Image img = decode(png);
  EXPECT_RGB(img, 2, 28, kBlue, 0);
  EXPECT_RGB(img, 38, 15, kBlue, 0);
  EXPECT_RGB(img, 15, 15, kRed, 0);
  EXPECT_RGB(img, 20, 25, kBlack, 60);  // the far-reaching line crosses the canvas
  std::string svg;
  ASSERT_NO_THROW(svg = canvas.toSvg());
  EXPECT_FALSE(contains(svg, "nan"));
  EXPECT_FALSE(contains(svg, "inf"));
  EXPECT_FALSE(contains(svg, "far"));
  EXPECT_FALSE(contains(svg, "e+"));
}

TEST(Png, NonAsciiTextDoesNotCrash) {
  Canvas canvas(100, 30, kWhite);
  canvas.text({50, 20}, "Stra\xc3\x9f" "e \xe2\x86\x92 \xff\xfe bad", TextStyle{});
  const Image img = decode(canvas.toPng());
  EXPECT_GT(inkColumns(img, 0, 29).second, 0);
  const std::string svg = canvas.toSvg();
  EXPECT_TRUE(contains(svg, "Stra\xc3\x9f" "e \xe2\x86\x92 \xef\xbf\xbd\xef\xbf\xbd bad"));  // invalid bytes → U+FFFD
}

// ---- SVG ----------------------------------------------------------------------------------------

TEST(Svg, WritesAStandaloneDocument) {
  Canvas canvas(40, 30, Rgb{10, 20, 30});
  canvas.polygon(square(10, 10, 20, 20), Style{kRed, kBlack, 1.5, 0.5, true});
  canvas.polyline({{1, 2}, {3.14159, 4}}, strokeOnly(kBlue, 2));
  canvas.circle({5, 6}, 2.5, fillOnly(kWhite));
  const std::string svg = canvas.toSvg();
  EXPECT_EQ(svg.rfind("<?xml version=\"1.0\" encoding=\"UTF-8\"", 0), 0u);
  EXPECT_TRUE(contains(svg, "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"40\" height=\"30\" "
                            "viewBox=\"0 0 40 30\">"));
  EXPECT_TRUE(contains(svg, "<rect x=\"0\" y=\"0\" width=\"40\" height=\"30\" fill=\"#0a141e\"/>"));
  EXPECT_TRUE(contains(svg, "<polygon points=\"10.00,10.00 20.00,10.00 20.00,20.00 10.00,20.00\" fill=\"#ff0000\" "
                            "stroke=\"#000000\" stroke-width=\"1.50\""));
  EXPECT_TRUE(contains(svg, "stroke-dasharray=\"4.50 4.50\""));
  EXPECT_TRUE(contains(svg, "opacity=\"0.50\""));
  EXPECT_TRUE(contains(svg, "<polyline points=\"1.00,2.00 3.14,4.00\" fill=\"none\" stroke=\"#0000ff\" "
                            "stroke-width=\"2.00\" stroke-linejoin=\"round\""));
  EXPECT_TRUE(contains(svg, "<circle cx=\"5.00\" cy=\"6.00\" r=\"2.50\" fill=\"#ffffff\" stroke=\"none\"/>"));
  EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
}

TEST(Svg, TextAttributesAndEscaping) {
  Canvas canvas(100, 50, kWhite);
  TextStyle style;
  style.size_px = 14;
  style.anchor = Anchor::End;
  style.bold = true;
  style.halo = kWhite;
  canvas.text({50, 25}, "A <&> \"B\" 'C'", style);
  TextStyle plain;
  plain.color = Rgb{1, 2, 3};
  plain.anchor = Anchor::Start;
  canvas.text({10, 10}, "plain", plain);
  const std::string svg = canvas.toSvg();
  EXPECT_TRUE(contains(svg, ">A &lt;&amp;&gt; &quot;B&quot; &apos;C&apos;</text>"));
  EXPECT_FALSE(contains(svg, "<&>"));
  EXPECT_TRUE(contains(svg, "font-family=\"sans-serif\""));
  EXPECT_TRUE(contains(svg, "font-size=\"20.00\""));  // 14 px caps / 0.7 em
  EXPECT_TRUE(contains(svg, "text-anchor=\"end\""));
  EXPECT_TRUE(contains(svg, "text-anchor=\"start\""));
  EXPECT_TRUE(contains(svg, "font-weight=\"bold\""));
  EXPECT_TRUE(contains(svg, "stroke=\"#ffffff\""));
  EXPECT_TRUE(contains(svg, "paint-order: stroke"));
  EXPECT_TRUE(contains(svg, "fill=\"#010203\""));
  // Only the haloed, bold label has a stroke and weight.
  EXPECT_EQ(svg.find("font-weight"), svg.rfind("font-weight"));
}

// ---- determinism --------------------------------------------------------------------------------

Canvas sampleDrawing() {
  const View view = View::fitWidth(Box2(Vec2(0, 0), Vec2(300, 200)), 320, 10);
  Canvas canvas(view.width(), view.height(), Rgb{240, 238, 230});
  std::vector<Vec2> road;
  for (const Vec2& w : {Vec2(10, 10), Vec2(150, 80), Vec2(290, 60), Vec2(290, 70), Vec2(150, 95), Vec2(10, 25)}) {
    road.push_back(view.toPixel(w));
  }
  canvas.polygon(road, Style{Rgb{200, 200, 200}, Rgb{120, 120, 120}, 1.3, 0.8, false});
  canvas.polyline({view.toPixel({20, 150}), view.toPixel({280, 160}), view.toPixel({200, 20})},
                  Style{std::nullopt, Rgb{30, 90, 200}, 2.6, 1.0, true});
  canvas.circle(view.toPixel({150, 100}), 6.3, Style{Rgb{220, 40, 40}, kWhite, 1.5, 0.7, false});
  TextStyle label;
  label.halo = kWhite;
  canvas.text(view.toPixel({150, 120}), "Main St <A&B>", label);
  drawScaleBarAndNorthArrow(canvas, view);
  return canvas;
}

TEST(Canvas, SameDrawingGivesTheSameBytes) {
  const Canvas a = sampleDrawing(), b = sampleDrawing();
  EXPECT_EQ(a.toSvg(), b.toSvg());
  EXPECT_EQ(a.toPng(), b.toPng());
  EXPECT_EQ(a.toPng(), a.toPng());
  EXPECT_EQ(a.toSvg(), a.toSvg());
}

// ---- save ---------------------------------------------------------------------------------------

TEST(Canvas, SavesSvgAndPngByExtension) {
  const fs::path dir = testing::freshTempDir();
  const Canvas canvas = sampleDrawing();
  canvas.save(dir / "map.svg");
  canvas.save(dir / "map.PNG");
  canvas.save(dir / "map.Svg");
  EXPECT_EQ(readFile(dir / "map.svg"), canvas.toSvg());
  EXPECT_EQ(readFile(dir / "map.PNG"), canvas.toPng());
  EXPECT_EQ(readFile(dir / "map.Svg"), canvas.toSvg());
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 3u);  // no temporary files left over
  fs::remove_all(dir);
}

TEST(Canvas, SaveRejectsOtherExtensionsAndLeavesNoFile) {
  const fs::path dir = testing::freshTempDir();
  const Canvas canvas = sampleDrawing();
  for (const char* name : {"map.txt", "map", "map.jpg", "map.svg.bak"}) {
    try {
      canvas.save(dir / name);
      ADD_FAILURE() << name << ": no exception";
    } catch (const InvalidInput& e) {
      const std::string what = e.what();
      EXPECT_TRUE(contains(what, name)) << what;
      EXPECT_TRUE(contains(what, ".svg")) << what;
      EXPECT_TRUE(contains(what, ".png")) << what;
    }
  }
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

TEST(Canvas, SaveIntoAMissingFolderThrowsIoError) {
  const fs::path dir = testing::freshTempDir();
  const Canvas canvas = sampleDrawing();
  EXPECT_THROW(canvas.save(dir / "no-such-folder" / "map.png"), IoError);
  EXPECT_THROW(canvas.save(dir / "no-such-folder" / "map.svg"), IoError);
  EXPECT_FALSE(fs::exists(dir / "no-such-folder"));
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

// ---- scale bar and north arrow ------------------------------------------------------------------

TEST(ScaleBar, NiceLengthIsTheNearestOneTwoFive) {
  EXPECT_DOUBLE_EQ(niceScaleLength(100.0 / 2.0), 50.0);  // 100 px at 2 px/m
  EXPECT_DOUBLE_EQ(niceScaleLength(120.0 / 1.0), 100.0);
  EXPECT_DOUBLE_EQ(niceScaleLength(120.0 / 0.1), 1000.0);  // 1200 m
  EXPECT_DOUBLE_EQ(niceScaleLength(120.0 / 0.05), 2000.0);  // 2400 m
  EXPECT_DOUBLE_EQ(niceScaleLength(160.0), 200.0);
  EXPECT_DOUBLE_EQ(niceScaleLength(75.0), 50.0);  // a tie: the shorter
  EXPECT_DOUBLE_EQ(niceScaleLength(76.0), 100.0);
  EXPECT_DOUBLE_EQ(niceScaleLength(3.4), 2.0);
  EXPECT_DOUBLE_EQ(niceScaleLength(3.6), 5.0);
  EXPECT_DOUBLE_EQ(niceScaleLength(7.0), 5.0);
  EXPECT_DOUBLE_EQ(niceScaleLength(8.0), 10.0);
  EXPECT_DOUBLE_EQ(niceScaleLength(1.0), 1.0);
  EXPECT_DOUBLE_EQ(niceScaleLength(1000.0), 1000.0);
  EXPECT_DOUBLE_EQ(niceScaleLength(0.07), 0.05);
  EXPECT_DOUBLE_EQ(niceScaleLength(0.03), 0.02);
  EXPECT_DOUBLE_EQ(niceScaleLength(4.2e6), 5e6);
  EXPECT_THROW(niceScaleLength(0.0), InvalidInput);
  EXPECT_THROW(niceScaleLength(-5.0), InvalidInput);
  EXPECT_THROW(niceScaleLength(kNaN), InvalidInput);
  EXPECT_THROW(niceScaleLength(kInf), InvalidInput);
}

TEST(ScaleBar, Labels) {
  EXPECT_EQ(scaleLengthLabel(20), "20 m");
  EXPECT_EQ(scaleLengthLabel(500), "500 m");
  EXPECT_EQ(scaleLengthLabel(0.5), "0.5 m");
  EXPECT_EQ(scaleLengthLabel(0.05), "0.05 m");
  EXPECT_EQ(scaleLengthLabel(1000), "1 km");
  EXPECT_EQ(scaleLengthLabel(2000), "2 km");
  EXPECT_EQ(scaleLengthLabel(50000), "50 km");
}

const Canvas::TextCmd* findText(const Canvas& canvas, const std::string& text) {
  for (const Canvas::Command& cmd : canvas.commands()) {
    if (const auto* t = std::get_if<Canvas::TextCmd>(&cmd); t != nullptr && t->text == text) return t;
  }
  return nullptr;
}

TEST(ScaleBar, DrawsBarBottomLeftAndNorthArrowTopRight) {
  // 2 px/m: 190 m x 140 m into 400 x 300 px with 10 px margins.
  const View view(Box2(Vec2(0, 0), Vec2(190, 140)), 400, 300, 10);
  ASSERT_DOUBLE_EQ(view.pixelsPerMetre(), 2.0);
  Canvas canvas(400, 300, kWhite);
  drawScaleBarAndNorthArrow(canvas, view, 100);
  const Canvas::TextCmd* label = findText(canvas, "50 m");
  ASSERT_NE(label, nullptr);
  EXPECT_LT(label->position.x(), 50);   // left
  EXPECT_GT(label->position.y(), 250);  // bottom
  const Canvas::TextCmd* north = findText(canvas, "N");
  ASSERT_NE(north, nullptr);
  EXPECT_GT(north->position.x(), 350);  // right
  EXPECT_LT(north->position.y(), 60);   // top

  const Image img = decode(canvas.toPng());
  // The bar: 50 m = 100 px from u = 12.5, frame on rows 281 and 287; black half then white half.
  EXPECT_RGB(img, 30, 285, kBlack, 0);
  EXPECT_RGB(img, 90, 285, kWhite, 0);
  EXPECT_RGB(img, 90, 281, kBlack, 40);   // the frame around the white half
  EXPECT_RGB(img, 90, 287, kBlack, 40);
  EXPECT_RGB(img, 130, 285, kWhite, 0);   // past the end of the bar
  // The north arrow: a filled triangle pointing up near the top-right corner.
  EXPECT_RGB(img, 378, 26, kBlack, 0);
  EXPECT_RGB(img, 378, 5, kWhite, 0);
}

TEST(ScaleBar, ShortensTheBarToFitTheCanvas) {
  const View view(Box2(Vec2(0, 0), Vec2(40, 40)), 100, 100, 10);  // 2 px/m, 76 px for the bar
  Canvas canvas(100, 100, kWhite);
  drawScaleBarAndNorthArrow(canvas, view, 400);  // 200 m wanted; 100 m = 200 px and 50 m = 100 px do not fit
  EXPECT_NE(findText(canvas, "20 m"), nullptr);
  EXPECT_THROW(drawScaleBarAndNorthArrow(canvas, view, 0), InvalidInput);
  EXPECT_THROW(drawScaleBarAndNorthArrow(canvas, view, kNaN), InvalidInput);
}

TEST(ScaleBar, KilometreLabel) {
  const View view(Box2(Vec2(0, 0), Vec2(10000, 10000)), 1010, 1010, 5);  // 0.1 px/m
  Canvas canvas(1010, 1010, kWhite);
  drawScaleBarAndNorthArrow(canvas, view, 120);  // 1200 m → 1 km
  EXPECT_NE(findText(canvas, "1 km"), nullptr);
}

}  // namespace
}  // namespace mapnav::render
