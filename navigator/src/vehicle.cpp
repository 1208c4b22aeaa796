#include "mapnav/navigator/vehicle.h"

#include <algorithm>
#include <cmath>

#include "mapnav/core/options.h"

namespace mapnav {

const OptionTable<VehicleLimits>& vehicleLimitsOptionTable() {
  using O = VehicleLimits;
  static const OptionTable<O> table =
      OptionTable<O>("VehicleLimits")
          .field("max_speed_mps", &O::max_speed_mps, above(0), "highest forward speed, m/s")
          .field("min_speed_mps", &O::min_speed_mps, "lowest speed, m/s (0: no backing up; negative allows reversing)")
          .field("max_turn_rate_rad_s", &O::max_turn_rate_rad_s, above(0), "highest turn rate either way, rad/s")
          .field("max_accel_mps2", &O::max_accel_mps2, above(0), "largest change of speed, either way, m/s^2")
          .check("min_speed_mps", [](const O& o) { return o.min_speed_mps <= o.max_speed_mps; }, "<= max_speed_mps");
  return table;
}

void VehicleLimits::validate() const { vehicleLimitsOptionTable().validate(*this); }

Pose2 integrateUnicycle(const Pose2& pose, double speed_mps, double turn_rate_rad_s, double dt) {
  // exp of the body twist (v dt, 0, ω dt) is the arc of curvature ω / v (a straight line at ω = 0,
  // handled by Pose2::exp's series near zero), composed on the right: it is in the vehicle frame.
  return pose * Pose2::exp(Pose2::Tangent(speed_mps * dt, 0.0, turn_rate_rad_s * dt));
}

SkidSteerVehicle::SkidSteerVehicle(Pose2 pose, VehicleLimits limits, double speed_mps)
    : pose_(pose), limits_(limits), speed_(speed_mps) {
  limits_.validate();
  requireArgument(std::isfinite(speed_mps) && speed_mps >= limits_.min_speed_mps && speed_mps <= limits_.max_speed_mps,
                  "SkidSteerVehicle", "speed_mps", speed_mps, "in [min_speed_mps, max_speed_mps]");
}

VehicleCommand SkidSteerVehicle::step(const VehicleCommand& command, double dt) {
  requireArgument(std::isfinite(dt) && dt > 0, "SkidSteerVehicle::step", "dt", dt, "finite and > 0");
  requireArgument(std::isfinite(command.speed_mps), "SkidSteerVehicle::step", "command.speed_mps", command.speed_mps,
                  "finite");
  requireArgument(std::isfinite(command.turn_rate_rad_s), "SkidSteerVehicle::step", "command.turn_rate_rad_s",
                  command.turn_rate_rad_s, "finite");
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
