#include "mapnav/sim/odometry.h"

#include <cmath>

#include "mapnav/core/json.h"
#include "mapnav/core/options.h"
#include "mapnav/geometry/types.h"

namespace mapnav {

void OdometryNoiseOptions::validate() const {
  requireOption(std::isfinite(scale_error) && std::abs(scale_error) < 0.5, "OdometryNoiseOptions", "scale_error",
                scale_error, "finite and within ±0.5");
  requireOption(std::isfinite(gyro_bias_deg_s), "OdometryNoiseOptions", "gyro_bias_deg_s", gyro_bias_deg_s, "finite");
  requireOption(std::isfinite(distance_sigma_m) && distance_sigma_m >= 0, "OdometryNoiseOptions", "distance_sigma_m",
                distance_sigma_m, "finite and >= 0");
  requireOption(std::isfinite(heading_sigma_deg) && heading_sigma_deg >= 0, "OdometryNoiseOptions", "heading_sigma_deg",
                heading_sigma_deg, "finite and >= 0");
}

OdometryNoiseOptions parseOdometryNoise(const std::string& json, const std::string& pointer, Issues& issues) {
  OdometryNoiseOptions o;
  const auto parsed = parseJson(json, issues);
  if (!parsed) return o;
  JsonObject block(*parsed, pointer, issues);
  if (const auto seed = block.number("seed", false, 0, 9007199254740992.0)) o.seed = static_cast<std::uint64_t>(*seed);
  o.scale_error = block.number("scale_error", false, -0.49, 0.49).value_or(o.scale_error);
  o.gyro_bias_deg_s = block.number("gyro_bias_deg_s", false, -10, 10).value_or(o.gyro_bias_deg_s);
  o.distance_sigma_m = block.number("distance_sigma_m", false, 0, 10).value_or(o.distance_sigma_m);
  o.heading_sigma_deg = block.number("heading_sigma_deg", false, 0, 90).value_or(o.heading_sigma_deg);
  block.rejectUnknownMembers();
  return o;
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
