#pragma once
// Odometry as a real vehicle's wheel encoders and gyro report it: a scale error on distance, a
// constant gyro bias, and white noise on both, so that dead reckoning drifts. The simulator's sensor
// (sim/plant.h) and a KITTI raw import's degraded odometry (kitti_raw_import.h) both use it; a
// reading is a MotionIncrement (distance in m, heading change in rad, vehicle frame).
#include <cstdint>
#include <random>
#include <string>

#include "mapnav/core/issue.h"
#include "mapnav/core/option_table.h"
#include "mapnav/geometry/motion.h"

namespace mapnav {

struct OdometryNoiseOptions {
  std::uint64_t seed = 1;          ///< the same seed gives the same noise
  double scale_error = 0.0;        ///< relative distance error of the encoders (0.01: 1 % long)
  double gyro_bias_deg_s = 0.0;    ///< constant heading-rate bias, degrees per second
  double distance_sigma_m = 0.0;   ///< white noise on each interval's distance, m
  double heading_sigma_deg = 0.0;  ///< white noise on each interval's heading change, degrees

  /// Throws InvalidInput naming the first bad field and its value (odometryNoiseOptionTable()'s rules).
  void validate() const;
};

/// OdometryNoiseOptions' fields by name, with their rules: validate() and the mission file's
/// `odometry` block.
const OptionTable<OdometryNoiseOptions>& odometryNoiseOptionTable();

/// Reads an `odometry` block of a mission ({"seed": 7, "scale_error": 0.01, ...}) by the table;
/// unknown members and bad values are issues at their pointers under `pointer`.
OdometryNoiseOptions parseOdometryNoise(const std::string& json, const std::string& pointer, Issues& issues);

class OdometrySensor {
 public:
  explicit OdometrySensor(const OdometryNoiseOptions& options);
  /// What the sensors report for a true motion of `distance_m` and `dheading_rad` over `dt` s.
  MotionIncrement measure(double distance_m, double dheading_rad, double dt);

 private:
  OdometryNoiseOptions options_;
  std::mt19937_64 rng_;
};

}  // namespace mapnav
