#pragma once
// A world that differs from its map: the simulator renders a perturbed copy of the map the vehicle
// navigates by (a mission's `world.map_error`), as a real map differs from the ground it draws.
//
// The perturbation is a smooth random displacement field D(p) over the plane (world frame, m): each
// component a zero-mean Gaussian process of standard deviation offset_sigma_m and squared-exponential
// correlation exp(−d² / (2 offset_length_m²)) between points d apart, drawn as a sum of
// kMapErrorFeatures random cosines (random Fourier features; seeded). Every point of the map moves by
// D at that point: the centre lines (resampled first, so that a straight road bends with the
// field), the intersections and their authored shapes, the landmarks. Because D is one field, the
// roads stay joined at their intersections and a landmark keeps its place beside its road; a road's
// lateral offset (D across it) has standard deviation offset_sigma_m. Each road's width is scaled by
// 1 + width_sigma · z, z a standard normal draw per road clamped to [−2, 2].
#include <cstdint>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/map/map.h"

namespace mapnav {

struct MapErrorOptions {
  /// Standard deviation of the displacement, per axis (so of a road's lateral offset), m; 0 (the
  /// default) = the world is the map. In [0, 100].
  double offset_sigma_m = 0;
  /// Correlation length of the displacement, m: points this far apart are correlated by
  /// exp(−1/2) ≈ 0.61. Default 30 (a map drawn over imagery is wrong the same way over a block). In
  /// [1, 1e6].
  double offset_length_m = 30;
  /// Relative standard deviation of each road's width, 0 (the default) = the map's widths. In [0, 0.4].
  double width_sigma = 0;
  /// Seeds the field and the widths: the same seed gives the same world.
  std::uint64_t seed = 1;

  /// No perturbation at all (the renderer draws the map itself).
  bool none() const { return offset_sigma_m == 0 && width_sigma == 0; }
  /// Throws InvalidInput naming the first bad field and its value (mapErrorOptionTable()'s rules).
  void validate() const;
};

/// MapErrorOptions' fields by name, with their rules: validate() and the mission's `world.map_error`.
const OptionTable<MapErrorOptions>& mapErrorOptionTable();

/// The number of random cosines in the field.
inline constexpr int kMapErrorFeatures = 256;

/// The displacement field D of `options` (its widths aside).
class MapErrorField {
 public:
  /// Throws InvalidInput for bad options.
  explicit MapErrorField(const MapErrorOptions& options);
  /// D(p), m (world frame).
  Vec2 offset(const Vec2& p) const;
  /// The map's pose whose image is the world's `pose`: the point p with p + D(p) = pose's position
  /// (fixed-point iteration; D's slope is about offset_sigma_m / offset_length_m, far below 1) and the
  /// heading turned back by the field's rotation there (the direction d in the map is (I + ∂D/∂p) d
  /// in the world). Where a perfectly map-relative estimate would be.
  Pose2 pullBack(const Pose2& pose) const;

 private:
  struct Feature {
    Vec2 frequency;  // rad/m
    double phase;    // rad
    Vec2 amplitude;  // m, before the sqrt(2 / N) scale
  };
  std::vector<Feature> features_;
  double scale_ = 0;
};

/// The world of `map` under `options`: a copy with every point moved by the field and the widths
/// scaled (the map itself untouched). Centre lines are resampled to at most offset_length_m / 10
/// (and at most 2 m) between points before they move. With options.none() the copy is exact.
/// Throws InvalidInput for bad options and ValidationError (naming `source`) when the moved map is
/// no longer valid (a landmark now on the widened paving, say).
Map perturbedMap(const Map& map, const MapErrorOptions& options, const std::string& source = "<perturbed map>");

}  // namespace mapnav
