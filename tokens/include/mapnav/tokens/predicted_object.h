#pragma once
// PredictedObject: Map → Vision, "what the camera should see" (Wallace 1985, 2.1.2). Information
// hiding: it carries only vehicle- and image-frame geometry and appearance. No world coordinates,
// no pose, no route, nothing of the map beyond what is in view: Vision "does not know where the
// vehicle is" (2.1.1). It knows how sure the Map is, in its own frame: the pose covariance.
#include <optional>
#include <string>
#include <vector>

#include "mapnav/geometry/motion.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/geometry/types.h"

namespace mapnav {

/// A primary straight edge the camera should see: a road edge or an intersection's outline.
struct InterestSegment {
  std::string id;          ///< stable across views: "R1.left.0", "I14.corner.2"
  std::string owner;       ///< the road or intersection it belongs to
  std::string side;        ///< "left", "right" (of a road, walking from → to) or "corner"
  Segment2 vehicle;        ///< metres on the ground, vehicle frame (x forward, y left)
  Segment2 image;          ///< pixels (u right, v down); the end points' projections
  std::string left_surface, right_surface;  ///< what lies on each side, walking a → b
  Vec3 left_rgb = Vec3::Zero(), right_rgb = Vec3::Zero();  ///< their mean colours
};

/// A road or intersection in view.
struct PredictedRegion {
  std::string id;
  std::string kind;   ///< "straight road", "curve", "cross intersection", "T intersection", ...
  std::string surface;
  Vec3 rgb = Vec3::Zero();
  std::vector<Polygon2> vehicle;  ///< its paved area inside the view footprint, vehicle frame
  std::vector<std::string> segments;  ///< ids of its interest segments
};

/// How two interest segments relate.
struct SegmentRelation {
  enum class Type { Parallel, Crossing };
  Type type = Type::Parallel;
  std::string a, b;           ///< segment ids
  double separation_m = 0;    ///< parallel: distance between the lines
  double angle_rad = 0;       ///< crossing: angle between the lines, (0, pi/2]
  Vec2 point = Vec2::Zero();  ///< crossing: where the lines meet, vehicle frame
};

/// A landmark the camera should see: something beside the road at a known place, whose
/// sighting fixes the position along the road. Vehicle- and image-frame geometry only.
struct PredictedLandmark {
  std::string id;           ///< the map's landmark id
  std::string kind;         ///< "pole", "tree", "bench", "bollard", "manhole"
  Vec2 vehicle = Vec2::Zero();     ///< where it meets the ground (its centre), vehicle frame, m
  double radius_m = 0, height_m = 0;  ///< its size (height 0: flat on the ground)
  Vec2 image_base = Vec2::Zero();  ///< the projection of its ground contact point (centre), px
  Vec2 image_top = Vec2::Zero();   ///< the projection of its top above that point, px (= base when flat)
  double width_px = 0;      ///< its diameter as seen at the base, px
};

struct PredictedObject {
  double timestamp = 0;           ///< seconds, of the frame this prediction is for
  Polygon2 footprint;             ///< the ground the camera sees, vehicle frame
  std::vector<PredictedRegion> regions;
  std::vector<InterestSegment> segments;
  std::vector<SegmentRelation> relations;
  /// Landmarks whose ground contact point lies in the footprint and projects into the image,
  /// nearest first.
  std::vector<PredictedLandmark> landmarks;
  /// The vehicle's motion since the previous frame as the Map predicts it (the odometry corrected
  /// by its estimated scale and gyro bias); none on the first frame. Vision measures it against the
  /// ground (DetectedObject::step).
  std::optional<MotionIncrement> motion;
  /// How uncertain the pose this view was predicted from is, in the vehicle frame: the covariance of
  /// (x forward m, y left m, heading rad). Zero when unknown (a bootstrap, an eval). Line labelling
  /// widens its gate with it: a predicted line's place in the vehicle frame is that uncertain.
  Mat3 pose_covariance = Mat3::Zero();
  /// How well the map places the roads this view was predicted from: their position's 1-sigma, m
  /// (the map's or the road's `position_sigma_m`); 0 for an exact map (or unknown). Where it is > 0
  /// the map's shape error is in pose_covariance too (PoseFilter::setMapSigma) and line labelling
  /// widens its gate by it (LineOptions::gate_sigma_uncertain_map).
  double map_sigma_m = 0;

  bool empty() const { return regions.empty() && segments.empty(); }
};

}  // namespace mapnav
