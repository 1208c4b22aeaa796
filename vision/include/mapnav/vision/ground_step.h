#pragma once
// How far the vehicle drove between two frames, measured from the ground: ground-plane
// visual odometry. A patch of the ground ahead is seen in both frames; the previous frame's view
// of it, moved by the Map's predicted motion, is registered onto this frame's by phase correlation
// (the ground's texture: the paving's grain and cracks, leaves, shadows, joints). What is left is
// the odometry's error over the step, along the heading and across it. The wheels' scale error
// drifts the position along a road where no line crosses it; the ground does not.
//
// Frames: the vehicle frame (x ahead, y left, m, on the ground) and the image (u right, v down, px).
// Colours: 8-bit RGB levels, compared as their sum.
#include "mapnav/core/option_table.h"
#include "mapnav/geometry/motion.h"
#include "mapnav/tokens/detected_object.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {

struct GroundStepOptions {
  /// The patch of ground compared, vehicle frame: from near_m to far_m ahead and half_width_m to
  /// either side, m. 3-7 m and ±0.8 m: the Terregator camera (1.5 m up, 22° down, 32° across) sees
  /// the ground from 2 m ahead and 1.7 m wide at 3 m; a step of 1 m keeps 3/4 of the patch in both
  /// frames, and beyond 7 m a pixel spans more than 4 cm of ground along the road. A camera that
  /// sees no ground that near (a car's, looking ahead) has the patch, as long, moved out to 10 %
  /// beyond the nearest ground it sees straight ahead.
  double near_m = 3.0;
  double far_m = 7.0;
  double half_width_m = 0.8;
  /// The patch's cell, m: 2 cm, what a pixel spans along the road at 5 m.
  double cell_m = 0.02;
  /// Looked at when the patch's brightness (the channels' sum) varies by at least this much,
  /// standard deviation in levels: a grey card or a blank frame does not.
  double min_texture = 2.0;
  /// Registered when the phase correlation's peak reaches min_peak (0..1) and min_peak_ratio
  /// times the highest value more than clear_m away from it along or across: one clear candidate,
  /// not a ridge (texture in one direction only, a kerb along the road) or a repeated pattern (the
  /// peaks measured: docs/measurements.md).
  double min_peak = 0.05;
  double min_peak_ratio = 1.5;
  double clear_m = 0.1;
  /// Kept when the residual against the predicted motion is within this, m (along and across):
  /// 0.25 m is 25 % of a 1 m step, ten times the odometry's scale error; a larger one is a wrong
  /// registration (a sidewalk's joints every 1.5 m), not the wheels.
  double max_residual_m = 0.25;
  /// Looked at only where a pixel spans at most this much ground along the road at the patch's
  /// far end (seen straight ahead), m: a shallow view (a car's camera, the ground beyond 7 m) turns
  /// the camera's pitch into the step's length. 0.05: the Terregator camera's 3.8 cm at 7 m; KITTI's
  /// car camera sees 9 cm per pixel at the 10 m its patch would reach, and is refused.
  double max_ground_per_px_m = 0.05;
  /// The measured distance's 1-sigma, m: the registration's, with the camera's pitch added: a pitch
  /// error of p radians scales the ground seen at depression angle a by 2 p / sin(2 a) (3.6 p at the
  /// Terregator patch's middle), and the step with it.
  double sigma_m = 0.01;
  /// The camera's pitch uncertainty as the vehicle rocks, deg (the mount's calibration is assumed
  /// good: a static pitch error biases every step alike, as a wheel's scale error does). 0.2: a
  /// small vehicle's pitch on smooth paving; 0.8 cm on a 0.8 m step of the Terregator camera.
  double pitch_sigma_deg = 0.2;

  /// groundStepOptionTable()'s rules. Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};
/// Its table: each option's name (the member's), rule and description.
const OptionTable<GroundStepOptions>& groundStepOptionTable();

/// The motion from `previous` to `current` (two frames of the same camera) along the vehicle's
/// heading, starting from `predicted` (the odometry's, corrected as the Map believes it). Not found,
/// with a reason, when the patch is not in view of both frames, the ground does not register, or
/// the residual is beyond max_residual_m. Throws InvalidInput for bad options, a frame without
/// pixels or camera, or frames of different sizes.
MeasuredStep measureGroundStep(const VisionFrame& previous, const VisionFrame& current, const MotionIncrement& predicted,
                               const GroundStepOptions& options = {});

}  // namespace mapnav
