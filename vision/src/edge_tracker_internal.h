#pragma once
// Internal to vision/: what the edge tracker's files share (see edge_tracker.h): degrees, the median,
// the operator's parameters from the options, and the start points of a frame's two edges.
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/types.h"
#include "mapnav/vision/edge_tracker.h"
#include "mapnav/tokens/predicted_object.h"

namespace mapnav {

constexpr double kDeg = std::numbers::pi / 180.0;  ///< radians per degree

/// orientedEdge as first written (every sample rounded by std::lround and bounds-checked): the
/// reference its fast path must equal bit for bit (tests/vision/fast_paths_test.cpp).
EdgeMatch orientedEdgeReference(const GreyImage& image, const Vec2& centre, const Vec2& direction,
                                const OrientedEdgeParams& params, int polarity = 0);

/// The median of v (the upper one of an even count); 0 when empty.
double edgeMedian(std::vector<double> v);

/// The oriented operator's window and step for an image of width × height pixels: the options' sizes
/// (at 512 × 480) scaled to it.
OrientedEdgeParams paramsFor(const EdgeTrackerOptions& o, int width, int height);

/// Where an edge's trace starts: an image point and direction (up the image), the predicted segment
/// it starts from, the expected contrast sign (0: unknown) and the band it is traced in.
struct EdgeStart {
  Vec2 point = Vec2::Zero(), direction = Vec2(0, -1);
  std::optional<std::string> label;
  int polarity = 0;
  GreyBand band = GreyBand::NormalizedGreen;
  /// The columns the first window's search covers along the start's row (hi < lo: the window's own
  /// width only): a start taken from a predicted region's side is only roughly where the edge is.
  double search_lo_u = 0, search_hi_u = -1;
};

bool normalised(GreyBand b);

/// A frame's start points for the vehicle's left and right edges, and where they came from
/// (EdgeTrackReport::start_source: "prediction", "carried" or "options").
struct EdgeStarts {
  EdgeStart left, right;
  std::vector<EdgeStart> left_next, right_next;  // from the prediction: each edge's segments, nearest first
  bool trace_left = true, trace_right = true;    // false: the prediction has that edge out of view
  std::string source;
};

/// The start of an edge carried from the last frame (EdgeTracker::advance()): its ground points'
/// nearest in the image, directed along them; nothing when fewer than 2 are in the image.
std::optional<EdgeStart> startFromCarried(const std::vector<Vec2>& ground, const std::optional<std::string>& label,
                                          const Camera& cam, int w, int h);
/// The starts in order of preference (see edge_tracker.h): the prediction's, else the carried edges'
/// (`carried_left` and `carried_right`, both or neither), else the options'.
EdgeStarts chooseStarts(const PredictedObject& pred, const Camera& cam, int w, int h, const EdgeTrackerOptions& o,
                        const std::optional<EdgeStart>& carried_left, const std::optional<EdgeStart>& carried_right);

}  // namespace mapnav
