#include "mapnav/vision/bev_eval.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "mapnav/core/error.h"

namespace mapnav {

namespace {

constexpr double kMaxCells = 20e6;  // 0.05 m cells over 200 m × 100 m; more is a typo, not a grid

// KITTI's count of cells over an extent, round(extent / cell), in doubles (a typo's cell of 1e-12 m
// would overflow an int).
double columnsOf(const BevGrid& g) { return std::round((g.x_max_m - g.x_min_m) / g.cell_m); }
double rowsOf(const BevGrid& g) { return std::round((g.z_max_m - g.z_min_m) / g.cell_m); }

}  // namespace

int BevGrid::columns() const { return static_cast<int>(columnsOf(*this)); }
int BevGrid::rows() const { return static_cast<int>(rowsOf(*this)); }

const OptionTable<BevGrid>& bevGridOptionTable() {
  using O = BevGrid;
  static const OptionTable<O> table =
      OptionTable<O>("BevGrid")
          .field("x_min_m", &O::x_min_m, "the bird's-eye grid's left edge, m right of the camera (KITTI's road frame)")
          .field("x_max_m", &O::x_max_m, "... its right edge, m")
          .field("z_min_m", &O::z_min_m, "... its near edge, m ahead of the camera (KITTI starts at 6)")
          .field("z_max_m", &O::z_max_m, "... its far edge, m")
          .field("cell_m", &O::cell_m, above(0), "the side of a cell, m")
          .check("x_max_m", [](const O& o) { return o.x_max_m > o.x_min_m; }, "> x_min_m")
          .check("z_max_m", [](const O& o) { return o.z_max_m > o.z_min_m; }, "> z_min_m")
          .check("cell_m", [](const O& o) { return columnsOf(o) * rowsOf(o) <= kMaxCells; },
                 "such that the grid has at most 20 million cells")
          .check("cell_m", [](const O& o) { return columnsOf(o) >= 1 && rowsOf(o) >= 1; },
                 "such that round((x_max_m - x_min_m) / cell_m) and round((z_max_m - z_min_m) / cell_m) are >= 1");
  return table;
}

void BevGrid::validate() const { bevGridOptionTable().validate(*this); }

BevSampling bevSampling(const Camera& camera, const BevGrid& grid) {
  grid.validate();
  BevSampling s;
  s.columns = grid.columns();
  s.rows = grid.rows();
  s.pixel_of_cell.assign(static_cast<std::size_t>(s.columns) * static_cast<std::size_t>(s.rows), -1);
  // KITTI's frame has its origin on the ground below the optical centre: x right (vehicle −y), z ahead.
  const Vec3 centre = camera.center();
  const int w = camera.width(), h = camera.height();
  for (int r = 0; r < s.rows; ++r) {
    const double z = grid.z_max_m - (r + 0.5) * grid.cell_m;
    for (int c = 0; c < s.columns; ++c) {
      const double x = grid.x_min_m + (c + 0.5) * grid.cell_m;
      const std::optional<Vec2> p = camera.projectGround(Vec2(centre.x() + z, centre.y() - x));
      if (!p || !camera.inImage(*p)) continue;
      // The nearest pixel centre; the area's rim (−0.5, w − 0.5) rounds onto the border pixels.
      const int u = std::clamp(static_cast<int>(std::lround(p->x())), 0, w - 1);
      const int v = std::clamp(static_cast<int>(std::lround(p->y())), 0, h - 1);
      const std::int32_t pixel = v * w + u;
      s.pixel_of_cell[static_cast<std::size_t>(r) * static_cast<std::size_t>(s.columns) + static_cast<std::size_t>(c)] =
          pixel;
      s.samples.push_back(static_cast<std::uint32_t>(pixel));
    }
  }
  return s;
}

Image resampleToBev(const Image& image, const BevSampling& sampling) {
  Image out(sampling.columns, sampling.rows, image.channels);
  const std::size_t n = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  const std::size_t ch = static_cast<std::size_t>(image.channels);
  for (std::size_t cell = 0; cell < sampling.pixel_of_cell.size(); ++cell) {
    const std::int32_t pixel = sampling.pixel_of_cell[cell];
    if (pixel < 0) continue;
    if (static_cast<std::size_t>(pixel) >= n)
      throw InvalidInput("image: " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                         " is smaller than the camera the grid was looked up in");
    std::copy_n(image.data.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(pixel) * ch),
                static_cast<std::ptrdiff_t>(ch), out.data.begin() + static_cast<std::ptrdiff_t>(cell * ch));
  }
  return out;
}

}  // namespace mapnav
