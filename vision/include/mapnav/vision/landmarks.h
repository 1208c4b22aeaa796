#pragma once
// Finding the predicted landmarks in a frame (issue 28): each is looked for near where the Map
// predicts its base, within the pose's uncertainty seen in the image. Something that stands (a
// pole, a trunk, a bollard, a bench) is a band of its predicted width whose colour differs from
// the ground on both sides of it and from the ground just in front of its base; a manhole cover is
// a patch of its predicted size that differs from the paving all round it. The best place is kept
// when it stands out enough (its base row and its sides then refined at the strongest colour
// steps near them); otherwise,
// and where the frame's side may cut it off, the landmark is reported as not there.
//
// Frames: the image (u right, v down, px). Colours: 8-bit RGB levels.
#include <vector>

#include "mapnav/tokens/detected_object.h"
#include "mapnav/tokens/predicted_object.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {

struct LandmarkFinderOptions {
  /// The search about the predicted base: gate_sigma standard deviations of the pose's covariance
  /// (PredictedObject::pose_covariance) seen in the image, at least min_search_px and at most
  /// max_search_px in each direction, px.
  double gate_sigma = 3.0;
  double min_search_px = 6.0;
  double max_search_px = 60.0;
  /// How much of something standing is compared with its sides: from its base up this far (or its
  /// height, if less), m. 0.6: a bench's seat, most of a bollard, and a trunk or post below the
  /// parked bicycles and hedges that hide the rest.
  double probe_height_m = 0.3;
  /// The strips beside it (and, for a manhole, all round it) that must differ from it, px.
  double side_px = 4.0;
  /// The ground in front of its base compared with it, px below the base.
  double below_px = 4.0;
  /// Found when its colour differs from each side and from the ground in front by at least this
  /// much (Euclidean distance of the mean RGB colours), levels. 20: a dark grey post on concrete
  /// differs by 60-100, a brown trunk on grass by 30-60, sensor noise averages to under 2.
  double min_contrast = 20.0;
  /// The standard deviation of a found base across (u) and up the image (v), px, at least: what
  /// the covariance of DetectedLandmark::image_base says (a quarter of the width is added across).
  /// 2 px: on the simulator's frames with shadows the median error is 0.3 px, but a few are off by
  /// 3-8 px (a cylinder's shaded side merges with shaded ground); 30 of 31 within 3 sigma.
  double base_sigma_u_px = 2.0;
  double base_sigma_v_px = 2.0;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// Looks for every landmark `prediction` lists in `frame` (which needs its camera); one result per
/// predicted landmark, in the prediction's order. Throws InvalidInput for bad options or a frame
/// without pixels or camera.
std::vector<DetectedLandmark> findLandmarks(const VisionFrame& frame, const PredictedObject& prediction,
                                            const LandmarkFinderOptions& options = {});

}  // namespace mapnav
