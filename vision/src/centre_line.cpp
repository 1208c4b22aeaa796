// The centre line of the road ahead from its region (centre_line.h).
#include "mapnav/vision/centre_line.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "mapnav/core/error.h"

namespace mapnav {

namespace {

struct Run {
  int begin = 0, end = 0;  // cells [begin, end)
  int width() const { return end - begin; }
};

std::vector<Run> runsOf(const Image& mask, int row) {
  std::vector<Run> runs;
  const std::uint8_t* p = mask.data.data() + static_cast<std::size_t>(row) * mask.width;
  for (int x = 0; x < mask.width;) {
    if (p[x] == 0) {
      ++x;
      continue;
    }
    Run r{x, x};
    while (x < mask.width && p[x] != 0) ++x;
    r.end = x;
    runs.push_back(r);
  }
  return runs;
}

int overlap(const Run& a, const Run& b) { return std::max(0, std::min(a.end, b.end) - std::max(a.begin, b.begin)); }

int predictedCells(const Image& predicted, int row, const Run& r) {
  if (predicted.empty()) return 0;
  const std::uint8_t* p = predicted.data.data() + static_cast<std::size_t>(row) * predicted.width;
  return static_cast<int>(std::count_if(p + r.begin, p + r.end, [](std::uint8_t v) { return v != 0; }));
}

// The run of `runs` that `pick` scores highest (ties: the first), or nothing when none scores > 0.
template <typename Score>
std::optional<Run> best(const std::vector<Run>& runs, Score pick) {
  std::optional<Run> out;
  int top = 0;
  for (const Run& r : runs) {
    if (const int s = pick(r); s > top) {
      top = s;
      out = r;
    }
  }
  return out;
}

}  // namespace

std::optional<Segment2> regionCentreLine(const Image& mask, const Image& predicted, const Camera& camera, int scale,
                                         const CentreLineOptions& options) {
  if (mask.channels != 1 || scale < 1) throw InvalidInput("regionCentreLine: a 1-channel mask and a scale >= 1");
  if (!predicted.empty() && (predicted.width != mask.width || predicted.height != mask.height))
    throw InvalidInput("regionCentreLine: the prediction's grid differs from the mask's");
  std::vector<Vec2> points;
  std::optional<Run> below;
  for (int row = mask.height - 1; row >= 0; --row) {
    const std::vector<Run> runs = runsOf(mask, row);
    std::optional<Run> run;
    if (below) {
      run = best(runs, [&](const Run& r) { return overlap(r, *below); });
      if (!run) break;  // the region ends (or turns away) here
    } else if (!runs.empty()) {
      run = best(runs, [&](const Run& r) { return predictedCells(predicted, row, r); });
      if (!run) run = best(runs, [](const Run& r) { return r.width(); });
    }
    if (!run) continue;  // no region yet: rows below it
    below = run;
    if (run->begin == 0 || run->end == mask.width) continue;  // cut by the frame: its middle is not the road's
    const double middle = 0.5 * (run->begin + run->end) * scale - 0.5;  // cells [b, e) = pixels [b s, e s)
    if (const auto g = camera.backproject(Vec2(middle, (row + 0.5) * scale - 0.5))) points.push_back(*g);
  }
  if (static_cast<int>(points.size()) < options.min_rows) return std::nullopt;
  // Weighted least squares y = a + b x, weights 1 / x².
  double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, x_min = points.front().x(), x_max = x_min;
  for (const Vec2& p : points) {
    if (p.x() <= 0) continue;
    const double w = 1.0 / (p.x() * p.x());
    sw += w;
    sx += w * p.x();
    sy += w * p.y();
    sxx += w * p.x() * p.x();
    sxy += w * p.x() * p.y();
    x_min = std::min(x_min, p.x());
    x_max = std::max(x_max, p.x());
  }
  const double det = sw * sxx - sx * sx;
  if (x_max - x_min < options.min_length_m || !(det > 0)) return std::nullopt;
  const double b = (sw * sxy - sx * sy) / det, a = (sy - b * sx) / sw;
  return Segment2{Vec2(x_min, a + b * x_min), Vec2(x_max, a + b * x_max)};
}

}  // namespace mapnav
