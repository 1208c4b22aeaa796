#include "mapnav/vision/bev_eval.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "mapnav/core/error.h"

namespace mapnav {

namespace {

constexpr double kMaxCells = 20e6;  // 0.05 m cells over 200 m × 100 m; more is a typo, not a grid

int cellsAcross(double min, double max, double cell) { return static_cast<int>(std::lround((max - min) / cell)); }

}  // namespace

int BevGrid::columns() const { return cellsAcross(x_min_m, x_max_m, cell_m); }
int BevGrid::rows() const { return cellsAcross(z_min_m, z_max_m, cell_m); }

void BevGrid::validate() const {
  const std::pair<const char*, double> fields[] = {
      {"x_min_m", x_min_m}, {"x_max_m", x_max_m}, {"z_min_m", z_min_m}, {"z_max_m", z_max_m}, {"cell_m", cell_m}};
  for (const auto& [name, v] : fields)
    if (!std::isfinite(v)) throw InvalidInput(std::string(name) + ": must be a finite number");
  if (!(cell_m > 0)) throw InvalidInput("cell_m: " + std::to_string(cell_m) + " must be > 0");
  if (!(x_min_m < x_max_m))
    throw InvalidInput("x_max_m: " + std::to_string(x_max_m) + " must be greater than x_min_m " + std::to_string(x_min_m));
  if (!(z_min_m < z_max_m))
    throw InvalidInput("z_max_m: " + std::to_string(z_max_m) + " must be greater than z_min_m " + std::to_string(z_min_m));
  const double cells = std::round((x_max_m - x_min_m) / cell_m) * std::round((z_max_m - z_min_m) / cell_m);
  if (cells > kMaxCells)
    throw InvalidInput("cell_m: " + std::to_string(cell_m) + " makes " + std::to_string(static_cast<long long>(cells)) +
                       " cells, more than 20 million");
  if (columns() < 1 || rows() < 1) throw InvalidInput("cell_m: " + std::to_string(cell_m) + " is larger than the grid");
}

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
