// The cluster-perceptron's bootstrap outline (Jochem & Baluja 1993 §4-5): road outline masks (a
// prediction's road region, polygons, a centre curve's road band) and the per-row road widths the
// Hough's kernel uses. See cluster_perceptron.h.
#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "cv_view.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav {

Polygon2 roadBand(const std::vector<Vec2>& centre, const std::vector<double>& row_widths, int width) {
  Polygon2 left, right;
  const long last = static_cast<long>(row_widths.size()) - 1;
  for (const Vec2& c : centre) {
    const double hw = 0.5 * row_widths[static_cast<std::size_t>(std::clamp(std::lround(c.y()), 0L, last))];
    left.emplace_back(std::clamp(c.x() - hw, -0.5, width - 0.5), c.y());
    right.emplace_back(std::clamp(c.x() + hw, -0.5, width - 0.5), c.y());
  }
  Polygon2 band = right;
  for (auto it = left.rbegin(); it != left.rend(); ++it) band.push_back(*it);
  return band;
}

Image fillPolygonMask(const std::vector<Polygon2>& polygons, int width, int height) {
  Image out(width, height, 1);
  cv::Mat m = cvview::view(out);
  for (const Polygon2& poly : polygons) {
    std::vector<cv::Point> pts;
    for (const Vec2& p : poly)
      pts.emplace_back(cvRound(std::clamp(p.x(), -1e5, 1e5)), cvRound(std::clamp(p.y(), -1e5, 1e5)));
    if (pts.size() >= 3) cv::fillPoly(m, std::vector<std::vector<cv::Point>>{pts}, cv::Scalar(255));
  }
  return out;
}

Image predictedRoadMask(const PredictedObject& prediction, const Camera& camera) {
  std::vector<Polygon2> rings;
  for (const PredictedRegion& region : prediction.regions)
    for (const Polygon2& ring : region.vehicle) {
      Polygon2 img;
      for (std::size_t i = 0; i < ring.size(); ++i) {
        const Vec2 a = ring[i], b = ring[(i + 1) % ring.size()];
        const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / 0.05)));
        for (int k = 0; k < steps; ++k)
          if (const auto p = camera.projectGround(a + (b - a) * (static_cast<double>(k) / steps))) img.push_back(*p);
      }
      rings.push_back(std::move(img));
    }
  return fillPolygonMask(rings, camera.width(), camera.height());
}

std::vector<double> trapezoidRowWidths(const Image& mask) {
  const int w = mask.width, h = mask.height;
  std::vector<double> widths(static_cast<std::size_t>(h), 0.0);
  std::vector<double> vs, ws;
  int top = h;
  for (int v = 0; v < h; ++v) {
    int lo = w, hi = -1;
    for (int u = 0; u < w; ++u)
      if (mask.pixel(u, v)[0] != 0) {
        lo = std::min(lo, u);
        hi = std::max(hi, u);
      }
    if (hi < 0) continue;
    top = std::min(top, v);
    widths[v] = hi - lo + 1;
    if (lo > 0 && hi < w - 1) {
      vs.push_back(v);
      ws.push_back(hi - lo + 1);
    }
  }
  if (vs.size() >= 8 && vs.back() - vs.front() >= 8) {
    // A flat road of constant width: the width is linear in v. Fit and extrapolate below the top.
    double sv = 0, sw = 0, svv = 0, svw = 0;
    const double m = static_cast<double>(vs.size());
    for (std::size_t i = 0; i < vs.size(); ++i) {
      sv += vs[i];
      sw += ws[i];
      svv += vs[i] * vs[i];
      svw += vs[i] * ws[i];
    }
    const double den = m * svv - sv * sv;
    if (std::abs(den) > 1e-9) {
      const double slope = (m * svw - sv * sw) / den, icpt = (sw - slope * sv) / m;
      for (int v = top; v < h; ++v) widths[v] = std::max(widths[v], std::max(1.0, icpt + slope * v));
    }
  }
  return widths;
}

}  // namespace mapnav
