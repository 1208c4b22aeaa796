#pragma once
// Finding the predicted landmarks in a frame: each is looked for near where the Map
// predicts its base, within the pose's uncertainty seen in the image (every second place, then
// every place about the best three of those). Something that stands (a pole, a trunk, a bollard,
// a bench) is a band of its predicted width, leaning as a vertical there does, with a colour step
// at both its sides all the way up its lower part and one at its foot against the ground in front;
// it is kept only when it stands out clearly from the next best place (its base row and its sides
// then refined at the strongest colour steps near them). A manhole cover is the ellipse its circle
// projects to, with a colour step across that rim all round it. Otherwise, and where the frame's
// edge cuts it, the landmark is reported as not there.
//
// Frames: the image (u right, v down, px). Colours: 8-bit RGB levels.
#include <vector>

#include "mapnav/core/option_table.h"
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
  double max_search_px = 150.0;
  /// How much of something standing is compared with its sides: from its base up this far (or its
  /// height, if less), m. 0.6: a bench's seat, most of a bollard, and a trunk or post below the
  /// parked bicycles and hedges that hide the rest (docs/measurements.md).
  double probe_height_m = 0.6;
  /// At least this much of that height must be in the frame (a landmark far ahead stands at the
  /// frame's top edge), as a fraction.
  double min_probe_in_frame = 0.25;
  /// The strips beside it that must differ from it, px.
  double side_px = 4.0;
  /// The ground in front of its base compared with it, px below the base.
  double below_px = 4.0;
  /// A manhole cover's rim is where the colour 1.5 px inside it differs from 1.5 px outside, px.
  double rim_step_px = 1.5;
  /// Found when the colour steps at its sides and foot (or all round a cover's rim) are at least
  /// this (Euclidean distance of mean RGB colours), levels. 12: a dark grey post on concrete steps
  /// by 60-100, a brown trunk on grass by 30-60, a shaded bollard's dark side on shaded grass by
  /// 15-25; sensor noise averages to under 2.
  double min_contrast = 12.0;
  /// Something standing is found only where it explains the frame this many times better than the
  /// best place more than its width across or a third of its probed height up or down from it: a
  /// shadow's edge across a bollard, or the patch of shade at a trunk's foot, can look as much like
  /// it as it does.
  double min_peak_ratio = 1.25;
  /// The standard deviation of a found base across (u) and up the image (v), px, at least: what
  /// the covariance of DetectedLandmark::image_base says (a quarter of the width is added across).
  /// 2 px: a few bases are off by several pixels where a cylinder's shaded side merges with shaded
  /// ground (docs/measurements.md).
  double base_sigma_u_px = 2.0;
  double base_sigma_v_px = 2.0;

  /// landmarkFinderOptionTable()'s rules. Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};
/// Its table: each option's name (the member's), rule and description.
const OptionTable<LandmarkFinderOptions>& landmarkFinderOptionTable();

/// Looks for every landmark `prediction` lists in `frame` (which needs its camera); one result per
/// predicted landmark, in the prediction's order. Throws InvalidInput for bad options or a frame
/// without pixels or camera.
std::vector<DetectedLandmark> findLandmarks(const VisionFrame& frame, const PredictedObject& prediction,
                                            const LandmarkFinderOptions& options = {});

}  // namespace mapnav
