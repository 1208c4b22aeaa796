// A world that differs from its map: the displacement field and the perturbed copy (map_error.h).
#include "mapnav/sim/map_error.h"

#include <algorithm>
#include <cmath>

#include "mapnav/core/error.h"
#include "mapnav/core/seeded_draw.h"

namespace mapnav {

const OptionTable<MapErrorOptions>& mapErrorOptionTable() {
  using O = MapErrorOptions;
  static const OptionTable<O> table =
      OptionTable<O>("MapErrorOptions")
          .field("offset_sigma_m", &O::offset_sigma_m, inRange(0, 100),
                 "standard deviation of the displacement per axis (a road's lateral offset), m; 0: the world is the map")
          .field("offset_length_m", &O::offset_length_m, inRange(1, 1e6),
                 "correlation length of the displacement, m (points this far apart correlate by 0.61)")
          .field("width_sigma", &O::width_sigma, inRange(0, 0.4), "relative standard deviation of each road's width")
          .field("seed", &O::seed, "seeds the field and the widths");
  return table;
}

void MapErrorOptions::validate() const { mapErrorOptionTable().validate(*this); }

namespace {

// `line` with points inserted so that no two consecutive are more than `step` apart.
std::vector<Vec2> resampled(const std::vector<Vec2>& line, double step) {
  std::vector<Vec2> out;
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (i > 0) {
      const Vec2 a = line[i - 1], b = line[i];
      const int pieces = static_cast<int>(std::ceil((b - a).norm() / step));
      for (int k = 1; k < pieces; ++k) out.push_back(a + (b - a) * (static_cast<double>(k) / pieces));
    }
    out.push_back(line[i]);
  }
  return out;
}

}  // namespace

MapErrorField::MapErrorField(const MapErrorOptions& options) {
  options.validate();
  if (options.offset_sigma_m == 0) return;
  // Random Fourier features of the squared-exponential kernel: frequencies ~ N(0, I / L²), phases
  // uniform, amplitudes ~ N(0, S² I); D(p) = sqrt(2 / N) Σ a cos(ω·p + φ) has covariance
  // S² exp(−|d|² / (2 L²)) per axis.
  SeededDraw draw(options.seed);
  features_.reserve(kMapErrorFeatures);
  for (int i = 0; i < kMapErrorFeatures; ++i) {
    Feature f;
    f.frequency = Vec2(draw.normal(), draw.normal()) / options.offset_length_m;
    f.phase = 2.0 * kPi * draw.open01();
    f.amplitude = options.offset_sigma_m * Vec2(draw.normal(), draw.normal());
    features_.push_back(f);
  }
  scale_ = std::sqrt(2.0 / kMapErrorFeatures);
}

Vec2 MapErrorField::offset(const Vec2& p) const {
  Vec2 d = Vec2::Zero();
  for (const Feature& f : features_) d += f.amplitude * std::cos(f.frequency.dot(p) + f.phase);
  return scale_ * d;
}

Pose2 MapErrorField::pullBack(const Pose2& pose) const {
  if (features_.empty()) return pose;
  const Vec2 q = pose.translation();
  Vec2 p = q;
  for (int i = 0; i < 50; ++i) {
    const Vec2 next = q - offset(p);
    const bool converged = (next - p).norm() < 1e-9;
    p = next;
    if (converged) break;
  }
  // The world's direction of the heading, mapped back through (I + J)^-1, J = ∂D/∂p by central differences.
  const double h = 1e-3;
  Mat2 jacobian;
  jacobian.col(0) = (offset(p + Vec2(h, 0)) - offset(p - Vec2(h, 0))) / (2 * h);
  jacobian.col(1) = (offset(p + Vec2(0, h)) - offset(p - Vec2(0, h))) / (2 * h);
  const Vec2 world_dir(std::cos(pose.heading()), std::sin(pose.heading()));
  const Vec2 map_dir = (Mat2::Identity() + jacobian).inverse() * world_dir;
  return Pose2(p, std::atan2(map_dir.y(), map_dir.x()));
}

Map perturbedMap(const Map& map, const MapErrorOptions& options, const std::string& source) {
  const MapErrorField field(options);
  MapData data = map.data();
  if (options.none()) return Map(std::move(data), source);
  const auto move = [&](const Vec2& p) { return Vec2(p + field.offset(p)); };
  const double step = std::min(2.0, options.offset_length_m / 10.0);
  // The widths' draws come from their own stream (seed + 1), so that they do not change the field.
  SeededDraw widths(options.seed + 1);
  for (Road& road : data.roads) {
    std::vector<Vec2> points = options.offset_sigma_m > 0 ? resampled(road.centerline.points(), step)
                                                          : road.centerline.points();
    for (Vec2& p : points) p = move(p);
    road.centerline = Polyline2(std::move(points));
    road.width *= 1.0 + options.width_sigma * std::clamp(widths.normal(), -2.0, 2.0);
  }
  for (Intersection& x : data.intersections) {
    x.position = move(x.position);
    if (x.shape) {
      for (Vec2& p : *x.shape) p = move(p);
    }
  }
  for (Landmark& l : data.landmarks) l.position = move(l.position);
  return Map(std::move(data), source);
}

}  // namespace mapnav
