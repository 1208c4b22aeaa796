#pragma once
// Predicted views (Wallace 1985, 2.1.2 and 2.2): for a pose and a camera, what should be seen —
// the roads and intersections in view, their kinds and shapes, and the interest segments, "the
// primary edge line segments of roads and intersections", with what lies on each side.
//
// Interest segments come from the map, not from the view, so their ids are the same from frame to
// frame: each road edge is simplified into straight pieces, the parts inside other paved areas
// (a crossing road, a plaza) are cut away, and the parts left are numbered along the edge
// (`R1.left.0`, `R1.left.1`, ...). An intersection's outline, less what roads cover, gives its
// corner segments (`I5.corner.0`, ...). A view then clips these to its footprint.
#include <memory>
#include <string>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/map/map.h"
#include "mapnav/tokens/predicted_object.h"

namespace mapnav {

struct PredictOptions {
  /// The footprint: ground in view at least `near_m` ahead of the camera and at most `far_m` from
  /// it (a distance, so that a fish-eye's 180° field does not reach far out to the sides), m.
  double near_m = 1.0;
  double far_m = 15.0;
  /// Curved edges become straight pieces that stay within this of the curve, m.
  double simplify_tolerance_m = 0.10;
  /// Segments shorter than this on the ground (m) or in the image (px) are dropped.
  double min_segment_length_m = 0.5;
  double min_segment_length_px = 8.0;
  /// Segments with less than this fraction of their length inside the image are dropped.
  double min_in_image_fraction = 0.5;
  /// Segments within this angle (degrees) of each other and at most this far apart (m) are a
  /// parallel pair, like a road's two edges...
  double parallel_tolerance_deg = 5.0;
  double max_parallel_separation_m = 10.0;
  /// ... and those at least this far apart in angle cross, where their lines meet within
  /// `crossing_reach_m` of both.
  double crossing_min_angle_deg = 20.0;
  double crossing_reach_m = 1.0;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// PredictOptions' fields by name, with their rules.
const OptionTable<PredictOptions>& predictOptionTable();

/// The Map module's prediction: the token for Vision plus what only the Map may know (the pose and
/// world coordinates, index-aligned with the token's regions and segments).
struct Prediction {
  Pose2 pose;
  Polygon2 footprint_world;
  PredictedObject view;                            ///< what Vision is given
  std::vector<Segment2> segments_world;            ///< view.segments[i] in the world frame
  std::vector<std::vector<Polygon2>> regions_world;  ///< view.regions[i] in the world frame
  std::vector<const Landmark*> landmarks;          ///< view.landmarks[i] in the map

  bool empty() const { return view.empty(); }
};

/// Predicted views of one map with one set of options, frame after frame. What does not depend on
/// the pose — each road's and intersection's interest segments, simplified centre line and simple
/// pieces — is worked out the first time the road or intersection comes into view and kept, and so
/// is the view footprint of the last camera (it depends on the camera and the range alone), so a
/// frame pays for clipping to its footprint only. The answers are predictView's.
///
/// It keeps a reference to `map`, which must outlive it and not change while it lives (the kept
/// work is the map's); the options are copied (and validated: InvalidInput for bad ones). The store
/// holds at most one entry per road and intersection, and one footprint. Not safe to share between
/// threads: predict() fills the store (use one per thread). A moved-from predictor may only be
/// assigned to or destroyed.
class ViewPredictor {
 public:
  explicit ViewPredictor(const Map& map, const PredictOptions& options = {});
  ~ViewPredictor();
  ViewPredictor(ViewPredictor&&) noexcept;
  ViewPredictor& operator=(ViewPredictor&&) noexcept;
  ViewPredictor(const ViewPredictor&) = delete;
  ViewPredictor& operator=(const ViewPredictor&) = delete;

  /// What `camera` on a vehicle at `pose` (world frame) should see of the map (see predictView).
  Prediction predict(const Pose2& pose, const Camera& camera);

  const Map& map() const { return *map_; }
  const PredictOptions& options() const { return options_; }

 private:
  struct Store;  // the pose-independent work, per road and intersection (predict.cpp)
  const Map* map_;
  PredictOptions options_;
  std::unique_ptr<Store> store_;
};

/// What `camera` on a vehicle at `pose` (world frame) should see of `map`. A pose off every road,
/// or a camera that sees no ground, gives an empty prediction. The cost grows with what is in
/// view, not with the map (R-tree queries). One frame of a fresh ViewPredictor: for many frames
/// of one map, keep a ViewPredictor.
Prediction predictView(const Map& map, const Pose2& pose, const Camera& camera, const PredictOptions& options = {});

/// The prediction as `mapnav predict --json` prints it: {"pose", "view": the PredictedObject token as
/// the trace writes it (tokens/token_json.h, vehicle axes and pixels), "world": the footprint, each
/// region's area, each segment and each landmark in the map's frame (metres)}.
std::string predictionToJson(const Prediction& prediction);

/// The surface an intersection is paved with: that of the widest road meeting there (the first in
/// the map's order among equals); empty when no road meets it. The simulator paints it and the
/// prediction expects it, so the two agree on what Vision should see.
std::string intersectionSurface(const Map& map, const Intersection& intersection);

/// "cross intersection", "T intersection", "Y intersection", "L turn", "dead end", "plaza", "junction".
std::string regionKind(IntersectionKind kind);

}  // namespace mapnav
