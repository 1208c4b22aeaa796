#pragma once
// DetectedObject: Vision → Map (Wallace 1985, 2.1.1): what Vision found in one frame — the road
// region, the edge lines with the predicted interest segment each one matches, the centre line —
// in image and vehicle (ground-plane) coordinates.
#include <optional>
#include <string>
#include <vector>

#include "mapnav/geometry/segment2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/image/image.h"

namespace mapnav {

struct DetectedLine {
  std::optional<std::string> label;  ///< the predicted segment id it matches ("R1.left.0"), or none
  double score = 0;                  ///< how well it matches, 0..1 (0 when unlabelled)
  Segment2 image;                    ///< pixels
  Segment2 vehicle;                  ///< metres on the ground, vehicle frame
  bool frame_edge = false;           ///< part of the image border, never a road edge
};

/// A predicted landmark looked for in the frame: found where it meets the ground, or
/// not there.
struct DetectedLandmark {
  std::string id;                      ///< the predicted landmark's id (PredictedLandmark::id)
  bool found = false;                  ///< false: looked for near its prediction and not seen
  std::string reason;                  ///< why not found ("no vertical edge pair near the prediction")
  Vec2 image_base = Vec2::Zero();      ///< where it meets the ground (its centre), px
  Mat2 covariance = Mat2::Identity();  ///< of image_base, px^2
  double score = 0;                    ///< how sure, 0..1
};

/// How far the vehicle drove since the previous frame, measured from the ground itself
/// (ground-plane visual odometry): the ground ahead in the previous frame, moved by the
/// Map's predicted motion (PredictedObject::motion), registered onto this frame's. Independent of
/// the wheels, it observes the odometry's scale error wherever the ground has texture.
struct MeasuredStep {
  bool found = false;     ///< false: the ground did not tell (no texture, no previous frame in view)
  std::string reason;     ///< why not found
  double distance_m = 0;  ///< driven along the heading since the previous frame, m
  double sigma_m = 0;     ///< its 1-sigma, m
  double left_m = 0;      ///< the sideways residual against the predicted motion, m (diagnostic)
  double peak = 0;        ///< the registration's phase-correlation peak, 0..1 (how sure)
};

struct DetectedObject {
  double timestamp = 0;
  enum class Status { Ok, Failed };
  Status status = Status::Ok;
  std::string reason;                ///< why it failed ("no road-coloured pixels", "frame over-exposed")
  double confidence = 0;             ///< 0..1
  Polygon2 region_image;             ///< the road region, pixels (may be empty when the frame did not want_region)
  Polygon2 region_vehicle;           ///< the same on the ground, vehicle frame (empty where above the horizon)
  std::vector<DetectedLine> lines;
  std::optional<Segment2> centerline_vehicle;  ///< when the pipeline finds one
  std::vector<DetectedLandmark> landmarks;     ///< the predicted landmarks looked for, in their order
  std::optional<MeasuredStep> step;            ///< when the motion since the previous frame was measured
  /// The road region found, per pixel and holes and all (a car on the road is not road), when the
  /// frame wants it (VisionFrame::want_masks) and the pipeline gives one; else empty: region_image
  /// is its outline. 1 channel, the frame's size, 255 inside. For scoring, not for the mission loop.
  Image road_mask;
  /// Per-pixel road confidence, when the frame wants it (VisionFrame::want_masks) and the
  /// pipeline gives one; else empty. 1 channel, the frame's size: 0 (surely not road) .. 255
  /// (surely road), ≥ 129 where the pipeline's own per-pixel decision is road, 0 where the camera
  /// does not see the ground. For scoring (MaxF, AP), not for the mission loop.
  Image road_confidence;

  static DetectedObject failed(std::string why) {
    DetectedObject d;
    d.status = Status::Failed;
    d.reason = std::move(why);
    return d;
  }
};

}  // namespace mapnav
