#pragma once
// The oriented road-edge tracker (Wallace et al. 1985, 3.1-3.2).
//
// An oriented step-edge operator integrates the grey image along the edge direction (nearest pixels
// when the direction is not a column) inside a search window of `window_rows` (along the edge) ×
// `window_cols` (across it), giving a one-dimensional edge profile; the edge is where an ideal step
// correlates best with the profile. The operator is tried at a few orientations around the expected
// one (the paper's "edge operators at a number of different orientations"). The tracer starts at a
// point and direction, places the next window at the predicted point (a step along θ), updates θ from
// the last two edge points, and repeats until the window leaves the image.
//
// The pipeline "edge-tracker" traces the road's left and right edges, back-projects them to the
// ground, checks them for parallelism and the expected width, and reports the paper's evaluation
// measures (3.2.1: contrast height, edge width, smoothness, consistency).
//
// Start points, in order of preference:
//   1. the PredictedObject's interest segments: for the road whose edge segment comes nearest the
//      vehicle, its nearest left and right segments' near ends in the image (clipped to the image,
//      16 px from its sides), directed along the segments; the segments' predicted side colours give
//      each edge's expected contrast sign. An edge lost within min_points of its start starts again
//      from its next segment up the image (on a curve the edge enters at the image's side, where
//      the window is half outside the image);
//   2. the previous frame's edges carried into the new frame with EdgeTracker::advance(motion);
//   3. the sides of the prediction's road region, when it has no interest segments (`mapnav eval`'s
//      bootstrap trapezoid): the region's leftmost and rightmost columns half a window above its
//      bottom, directed to its top; the first window searches start_search_m either side;
//   4. the options: start_left_u / start_right_u on row start_v, at start_left_angle_deg /
//      start_right_angle_deg.
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/tokens/detected_object.h"
#include "mapnav/tokens/predicted_object.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {

/// A grey image, float levels 0..255, row-major.
struct GreyImage {
  int width = 0, height = 0;
  std::vector<float> data;
  float at(int u, int v) const { return data[static_cast<std::size_t>(v) * width + u]; }
};

enum class GreyBand { Blue, Luminance, NormalizedGreen, NormalizedRed };

/// The band's level of one colour: the blue band (the paper's Warp runs, 3.6.3), the luminance
/// (0.299 R + 0.587 G + 0.114 B), or the normalised green g = G / (R + G + B) of the paper's 3.4.3
/// scaled by 255 (a grey surface is at 85; (G + 1) / (R + G + B + 3), so that black is grey too).
/// A shadow scales a colour by k, which the normalised green does not see: on the park path the
/// tree shadows' steps on the asphalt vanish while grass (g = 0.50) against asphalt (g = 0.33)
/// stays a step of ~44 levels, sunlit or shaded. The normalised red r = R / (R + G + B), likewise:
/// dirt (r = 0.43) against asphalt (r = 0.33) is a step of ~26 levels where the green sees none.
double bandLevel(double r, double g, double b, GreyBand band);
/// The image in that band.
GreyImage toGrey(const std::uint8_t* rgb, int width, int height, GreyBand band);

/// Parameters of one application of the oriented operator.
struct OrientedEdgeParams {
  int along_px = 64;             ///< window length along the edge (the operator's columns), px
  int across_px = 128;           ///< window width across the edge (the profile's length), px
  int step_half_width_px = 6;    ///< the ideal step: this many samples each side
  double angle_search_deg = 10;  ///< orientations tried: the expected one ± this ...
  double angle_step_deg = 1;     ///< ... in steps of this
  /// Only steps within this distance of the window's centre line are candidates (px); the tracer
  /// sets it to step × tan(max_turn_deg) after the first point, so that a shadow edge elsewhere in
  /// the window cannot pull the trace off. Infinite: the whole window.
  double max_offset_px = std::numeric_limits<double>::infinity();
};

/// The best step edge in one window.
struct EdgeMatch {
  bool found = false;
  Vec2 point = Vec2::Zero();      ///< the edge point on the window's centre line, pixels
  Vec2 direction = Vec2(0, -1);   ///< unit direction of the best operator (along the edge)
  double contrast = 0;            ///< mean grey right of the edge − left of it (right = direction turned clockwise on screen)
  double correlation = 0;         ///< normalised correlation with the ideal step, −1..1
  double width_px = 0;            ///< edge width: |contrast| / the profile's steepest slope, px
  std::vector<double> profile;    ///< the edge profile at the best orientation (NaN where outside the image)
};

/// The oriented operator at `centre`, expected direction `direction` (unit, image coordinates).
/// polarity +1 / −1 accepts only edges of that contrast sign, 0 either.
EdgeMatch orientedEdge(const GreyImage& image, const Vec2& centre, const Vec2& direction,
                       const OrientedEdgeParams& params, int polarity = 0);

struct EdgeTrackerOptions {
  /// The band the edges are traced in. Normalised green (the paper's 3.4.3): in luminance the tree
  /// shadows' steps on the asphalt are larger than the grass-to-asphalt step (docs/measurements.md);
  /// blue is the paper's Warp band, but the simulated grass is bright in blue.
  GreyBand band = GreyBand::NormalizedGreen;
  /// With a normalised band: an edge whose predicted side colours the prediction gives is traced in
  /// whichever of the normalised green and the normalised red separates them more (or in luminance:
  /// see min_normalised_step). On the park path dirt and gravel have the asphalt's normalised green
  /// (docs/measurements.md), while the grass edges keep the green.
  bool band_from_prediction = true;
  /// With band_from_prediction: when neither normalised band separates an edge's predicted side
  /// colours by this many levels, the edge is traced in luminance (when that separates them more).
  /// Gravel against asphalt differs in brightness only (docs/measurements.md); in luminance tree
  /// shadows step too (the expected contrast sign rejects those of the other sign; see
  /// gate_luminance for the others). 0: never luminance.
  double min_normalised_step = 12;
  int window_rows = 64;               ///< at 480 rows; scaled with the image height
  int window_cols = 128;              ///< at 512 columns; scaled with the image width
  double step_fraction = 0.5;         ///< the next point is predicted this × window_rows ahead
  int step_half_width_px = 6;         ///< the ideal step's half-width (at 512 columns; scaled)
  double angle_search_deg = 10;
  double angle_step_deg = 1;
  double min_contrast = 6;            ///< a weaker step ends the trace, grey levels
  double max_turn_deg = 30;           ///< a larger change of θ between steps ends the trace
  int min_points = 3;                 ///< fewer edge points: the edge is lost
  int max_points = 200;
  double start_left_u = -1;           ///< start columns (−1: 0.25 and 0.75 of the width) ...
  double start_right_u = -1;
  double start_v = -1;                ///< ... on this row (−1: half a window above the bottom)
  double start_left_angle_deg = 20;   ///< start directions, degrees from straight up, + leaning right
  double start_right_angle_deg = -20;
  double expected_width_m = 0;        ///< 0: the prediction's parallel separation_m (no check without one)
  double width_tolerance = 0.15;      ///< fraction of the expected width
  double parallel_tolerance_deg = 10; ///< angle between the two edges' ground lines
  double max_width_sd_m = 0.4;        ///< spread of the width along the edges
  /// An edge ends at its first point that back-projects farther than this (or not at all: above the
  /// horizon), metres. Near the horizon a pixel spans metres of ground: with a wide lens the trace
  /// runs on toward the vanishing point, and those points would swing the edges' ground lines.
  double max_range_m = 15;
  bool gate_search = false;           ///< search only offsets reachable within max_turn_deg (see OrientedEdgeParams::max_offset_px)
  /// gate_search for the edges min_normalised_step sends to luminance alone. There a tree shadow's
  /// step on the brighter shoulder beats the material step (docs/measurements.md).
  bool gate_luminance = true;
  bool use_carried_edges = true;      ///< use advance()'d edges when the prediction has no segments
  /// When one edge is lost and the other, labelled, is tracked: report that edge alone (its lines,
  /// no centre line, half the confidence) instead of failing. On a 3 m park path the pin-hole sees
  /// the edges only in the image's upper corners, and on a curve one of them leaves the image; one
  /// edge still gives the Map the lateral position and the heading. Without the pair's width and
  /// parallelism check only the Map's gate stands between a wrong edge and the estimate
  /// (docs/measurements.md).
  bool single_edge = true;
  /// Where a start comes from the predicted road region's sides (a prediction without interest
  /// segments: `mapnav eval`'s bootstrap trapezoid), the first window searches this far either side
  /// of the predicted edge, metres on the ground at the start's range, clipped to the image. A region
  /// says where the road is, not where its edges are: the trapezoid's sides are 0.9 m from the
  /// centre, CamVid's kerbs and verges 2 to 6 m. 4 m at the trapezoid's 3.7 m start reaches both
  /// image sides.
  double start_search_m = 4;
  /// With starts from a region: the road region reported reaches up to the row that sees the ground
  /// this far ahead, metres (the edges' lines extended up to it), and a lost edge's side reaches to
  /// the image's side: the search found no step between the predicted edge and it. The edges say
  /// nothing of where the road ends ahead (cars, crossings and buildings close a street beyond; why
  /// 25: docs/measurements.md).
  double region_far_m = 25;
  /// With starts from a region: the first window tries orientations within this of the region's
  /// side (in steps of at least 2 deg). A region's side is not the edge's direction: CamVid's kerbs
  /// lean 20 to 60 deg from the trapezoid's sides at the image's bottom.
  double start_angle_search_deg = 40;
  /// With starts from a region: a traced edge whose ground line is more than this off the vehicle's
  /// heading is no side of the road the vehicle is on (a crossing marking, the lower edge of a car or
  /// of its shadow) and counts as lost. 45: CamVid's kerbs on curves run within 30.
  double max_heading_deg = 45;

  /// edgeTrackerOptionTable()'s rules (max_points >= min_points among them). Throws InvalidInput naming the field.
  void validate() const;
};

/// The paper's per-edge evaluation measures.
struct EdgeEvaluation {
  double contrast = 0;     ///< "height": mean |step contrast|, grey levels
  double width_px = 0;     ///< "width": mean edge width (ramp), px
  double smoothness = 0;   ///< RMS distance of each inner point from its neighbours' chord, px (0 = smooth)
  double consistency = 0;  ///< fraction of points with contrast within ½..2× the median and turn ≤ max_turn/2
  double score = 0;        ///< 0..1, combines the above
};

struct TrackedEdge {
  std::optional<std::string> label;  ///< the predicted segment it started from
  GreyBand band = GreyBand::NormalizedGreen;  ///< the band it was traced in
  Vec2 start = Vec2::Zero(), start_direction = Vec2(0, -1);
  std::vector<Vec2> image;           ///< edge points, bottom → top, pixels
  std::vector<EdgeMatch> matches;    ///< one per point (profiles dropped)
  std::vector<Vec2> ground;          ///< back-projected points (those below the horizon), vehicle frame
  bool reached_top = false;          ///< stopped because the next window left the image
  std::string stop_reason;
  EdgeEvaluation eval;
};

struct EdgePairCheck {
  double width_m = 0;          ///< median distance between the edges on the ground
  double width_sd_m = 0;
  double angle_deg = 0;        ///< between the two edges' fitted ground lines
  double expected_width_m = 0; ///< 0 when none was known
  bool parallel_ok = false;
  bool width_ok = false;
};

struct EdgeTrackReport {
  TrackedEdge left, right;     ///< left / right of the vehicle (vehicle y > 0 is left)
  EdgePairCheck pair;
  std::string start_source;    ///< "prediction", "carried", "region", "options"
};

/// The tracker, with memory of the last frame's edges for advance().
class EdgeTracker {
 public:
  explicit EdgeTracker(EdgeTrackerOptions options = {});
  const EdgeTrackerOptions& options() const { return options_; }
  void setOptions(const EdgeTrackerOptions& options);

  /// Traces one edge from `start` along `direction` (unit, pointing up the image). `polarity`: the
  /// expected sign of the contrast (grey right of the edge − left of it, looking up the image), 0 =
  /// take the first window's.
  /// `gate`: search as gate_search does, also when that option is off.
  /// `search_lo_u` ≤ `search_hi_u`: the first window searches the columns between them along the
  /// start's row (see searchRow); else only its own width around `start`.
  TrackedEdge trace(const GreyImage& image, const Vec2& start, const Vec2& direction, int polarity = 0,
                    bool gate = false, double search_lo_u = 0, double search_hi_u = -1) const;

  /// Both edges, ground check and evaluation; also kept as lastReport().
  DetectedObject detect(const VisionFrame& frame, const PredictedObject& prediction);
  const EdgeTrackReport& lastReport() const { return report_; }

  /// Carries the last detected edges (their ground points) into the next frame: `motion` is the
  /// odometry delta, the new vehicle pose expressed in the previous vehicle frame. The next detect()
  /// starts from them when its prediction has no interest segments.
  void advance(const Pose2& motion);
  /// Forgets the carried edges.
  void reset();

 private:
  /// The start's search along the image row through `at`: windows every half window width from
  /// column lo to hi, each at orientations within start_angle_search_deg of `dir`; the strongest step
  /// found between lo and hi.
  EdgeMatch searchRow(const GreyImage& image, const Vec2& at, const Vec2& dir, const OrientedEdgeParams& p,
                      int polarity, double lo, double hi) const;
  /// The road between the last report's edges, with starts from a predicted region (see region_far_m).
  DetectedObject regionDetection(const VisionFrame& frame, const std::string& why) const;

  EdgeTrackerOptions options_;
  EdgeTrackReport report_;
  struct Carried {
    std::vector<Vec2> ground;
    std::optional<std::string> label;
  };
  std::optional<Carried> carried_left_, carried_right_;
  std::optional<Carried> last_left_, last_right_;
};

/// The options' table: names, ranges and the descriptions `mapnav pipelines` lists; the pipeline
/// reads its JSON options with it (absent members keep their values).
const OptionTable<EdgeTrackerOptions>& edgeTrackerOptionTable();
/// The "edge-tracker" pipeline.
std::unique_ptr<VisionPipeline> createEdgeTrackerPipeline();

}  // namespace mapnav
