#include "mapnav/logs/odometry.h"

#include "mapnav/geometry/types.h"

namespace mapnav {

const OptionTable<OdometryNoiseOptions>& odometryNoiseOptionTable() {
  using O = OdometryNoiseOptions;
  static const OptionTable<O> table =
      OptionTable<O>("OdometryNoiseOptions")
          .field("seed", &O::seed, "the same seed gives the same noise")
          .field("scale_error", &O::scale_error, inRange(-0.49, 0.49),
                 "relative distance error of the encoders (0.01: 1 % long)")
          .field("gyro_bias_deg_s", &O::gyro_bias_deg_s, inRange(-10, 10), "constant heading-rate bias, deg/s")
          .field("distance_sigma_m", &O::distance_sigma_m, inRange(0, 10), "white noise on each interval's distance, m")
          .field("heading_sigma_deg", &O::heading_sigma_deg, inRange(0, 90),
                 "white noise on each interval's heading change, degrees");
  return table;
}

void OdometryNoiseOptions::validate() const { odometryNoiseOptionTable().validate(*this); }

OdometryNoiseOptions parseOdometryNoise(const std::string& json, const std::string& pointer, Issues& issues) {
  return odometryNoiseOptionTable().read(json, {}, pointer, issues);
}

OdometrySensor::OdometrySensor(const OdometryNoiseOptions& options) : options_(options), rng_(options.seed) {
  options_.validate();
}

MotionIncrement OdometrySensor::measure(double distance_m, double dheading_rad, double dt) {
  std::normal_distribution<double> unit(0.0, 1.0);
  MotionIncrement o;
  o.distance_m = distance_m * (1.0 + options_.scale_error) + options_.distance_sigma_m * unit(rng_);
  o.dheading_rad = dheading_rad + degToRad(options_.gyro_bias_deg_s) * dt + degToRad(options_.heading_sigma_deg) * unit(rng_);
  return o;
}

}  // namespace mapnav
