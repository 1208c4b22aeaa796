#include "mapnav/navigator/vehicle.h"

#include <algorithm>
#include <cmath>

#include "mapnav/core/options.h"

namespace mapnav {

void VehicleLimits::validate() const {
  auto require = [](bool ok, const char* field, double value, const char* rule) {
    requireOption(ok, "VehicleLimits", field, value, rule);
  };
  require(std::isfinite(max_speed_mps) && max_speed_mps > 0, "max_speed_mps", max_speed_mps, "finite and > 0");
  require(std::isfinite(min_speed_mps) && min_speed_mps <= max_speed_mps, "min_speed_mps", min_speed_mps,
          "finite and <= max_speed_mps");
  require(std::isfinite(max_turn_rate_rad_s) && max_turn_rate_rad_s > 0, "max_turn_rate_rad_s", max_turn_rate_rad_s,
          "finite and > 0");
  require(std::isfinite(max_accel_mps2) && max_accel_mps2 > 0, "max_accel_mps2", max_accel_mps2, "finite and > 0");
}

Pose2 integrateUnicycle(const Pose2& pose, double speed_mps, double turn_rate_rad_s, double dt) {
  // exp of the body twist (v dt, 0, ω dt) is the arc of curvature ω / v (a straight line at ω = 0,
  // handled by Pose2::exp's series near zero), composed on the right: it is in the vehicle frame.
  return pose * Pose2::exp(Pose2::Tangent(speed_mps * dt, 0.0, turn_rate_rad_s * dt));
}

SkidSteerVehicle::SkidSteerVehicle(Pose2 pose, VehicleLimits limits, double speed_mps)
    : pose_(pose), limits_(limits), speed_(speed_mps) {
  limits_.validate();
  requireOption(std::isfinite(speed_mps) && speed_mps >= limits_.min_speed_mps && speed_mps <= limits_.max_speed_mps,
                "SkidSteerVehicle", "speed_mps", speed_mps, "in [min_speed_mps, max_speed_mps]");
}

VehicleCommand SkidSteerVehicle::step(const VehicleCommand& command, double dt) {
  requireOption(std::isfinite(dt) && dt > 0, "SkidSteerVehicle::step", "dt", dt, "finite and > 0");
  requireOption(std::isfinite(command.speed_mps), "VehicleCommand", "speed_mps", command.speed_mps, "finite");
  requireOption(std::isfinite(command.turn_rate_rad_s), "VehicleCommand", "turn_rate_rad_s", command.turn_rate_rad_s,
                "finite");
  VehicleCommand applied;
  const double dv = limits_.max_accel_mps2 * dt;
  applied.speed_mps = std::clamp(command.speed_mps, limits_.min_speed_mps, limits_.max_speed_mps);
  applied.speed_mps = std::clamp(applied.speed_mps, speed_ - dv, speed_ + dv);
  applied.turn_rate_rad_s =
      std::clamp(command.turn_rate_rad_s, -limits_.max_turn_rate_rad_s, limits_.max_turn_rate_rad_s);

  speed_ = applied.speed_mps;
  pose_ = integrateUnicycle(pose_, applied.speed_mps, applied.turn_rate_rad_s, dt);
  odometer_ += std::abs(applied.speed_mps) * dt;
  return applied;
}

}  // namespace mapnav
