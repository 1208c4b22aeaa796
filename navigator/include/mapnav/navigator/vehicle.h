#pragma once
// The vehicle Motion Control drives: a skid-steer platform like the CMU Terregator, modelled as a
// unicycle (it turns about its reference point, so a speed and a turn rate are all it takes).
// Deterministic: odometry and actuation noise belong to the simulator.
#include "mapnav/core/option_table.h"
#include "mapnav/geometry/pose2.h"

namespace mapnav {

/// What the vehicle can do. The defaults are Terregator-like: it ran the paper's road following at
/// up to 1.08 km/h (0.3 m/s) and is a slow, heavy, six-wheeled skid-steer base.
struct VehicleLimits {
  /// Highest forward speed, m/s (> 0). About 3.6 km/h, a walking pace for a sidewalk.
  double max_speed_mps = 1.0;
  /// Lowest speed, m/s (≤ max_speed_mps). 0: the vehicle does not back up; negative allows reversing.
  double min_speed_mps = 0.0;
  /// Highest turn rate either way, rad/s (> 0). 0.6 rad/s ≈ 34°/s: a skid-steer base turning on
  /// its tracks' friction, not a car's steering geometry, so it can also turn in place.
  double max_turn_rate_rad_s = 0.6;
  /// Largest change of speed, either way, m/s² (> 0). 0.5 m/s²: from rest to full speed in 2 s.
  double max_accel_mps2 = 0.5;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// The limits' names, rules and descriptions; validate() checks them.
const OptionTable<VehicleLimits>& vehicleLimitsOptionTable();

/// A motion command, held for one control period.
struct VehicleCommand {
  double speed_mps = 0.0;        ///< forward speed, m/s
  double turn_rate_rad_s = 0.0;  ///< dτ/dt, rad/s, left (counter-clockwise) positive
};

/// Unicycle kinematics: ẋ = v cos θ, ẏ = v sin θ, θ̇ = ω, with the limits applied to each command.
class SkidSteerVehicle {
 public:
  /// Throws InvalidInput for invalid limits or an initial speed outside [min, max] speed.
  explicit SkidSteerVehicle(Pose2 pose = {}, VehicleLimits limits = {}, double speed_mps = 0.0);

  /// Applies `command` for `dt` seconds (> 0, else InvalidInput). The command is first clamped: the
  /// speed to [min_speed_mps, max_speed_mps] and then to within max_accel_mps2 · dt of the current
  /// speed, the turn rate to ±max_turn_rate_rad_s (each on its own: limiting the speed does not
  /// scale the turn rate). The clamped command is then held over dt (the new speed takes effect at
  /// the step's start) and integrated exactly: an arc of radius v/ω, or a straight line when ω = 0.
  /// Returns the command applied.
  VehicleCommand step(const VehicleCommand& command, double dt);

  const Pose2& pose() const { return pose_; }
  double speed() const { return speed_; }  ///< m/s, as applied in the last step
  const VehicleLimits& limits() const { return limits_; }
  /// Arc length driven since construction, m (|v| · dt summed).
  double odometer() const { return odometer_; }

  void setPose(const Pose2& pose) { pose_ = pose; }

 private:
  Pose2 pose_;
  VehicleLimits limits_;
  double speed_ = 0.0;
  double odometer_ = 0.0;
};

/// The pose reached from `pose` by driving at `speed_mps` and `turn_rate_rad_s` for `dt` seconds:
/// the exact unicycle solution (SE(2) exponential of the constant twist).
Pose2 integrateUnicycle(const Pose2& pose, double speed_mps, double turn_rate_rad_s, double dt);

}  // namespace mapnav
