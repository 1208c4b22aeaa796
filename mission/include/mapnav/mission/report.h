#pragma once
// The HTML report of a mission run (docs/report.md): ONE self-contained file that opens
// without network access — inline CSS and SVG, frames as base64 PNG data URIs, no script. In it:
// the summary metrics; the map with the planned route and the true, estimated and odometry-only
// trajectories; the errors over time (lateral, along, heading of the estimate; the position error
// of the estimate and of odometry alone) with vision failures and halts marked; those failures
// listed; a strip of frame thumbnails with the predicted segments thin and the matched (labelled)
// detections bold, as the paper's Figure 2 (Wallace 1985); and the dialogue, the trace read back
// as `mapnav trace show` prints it. The trajectories also go to GeoJSON (lon/lat) for QGIS.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/map/map.h"
#include "mapnav/mission/runner.h"

namespace mapnav {

struct ReportOptions {
  /// Thumbnails in the strip at most (>= 2): every k-th frame, k doubling as the run grows so that
  /// between half and all of `max_thumbnails - max_failure_thumbnails` remain, plus the first frame
  /// of each vision failure up to `max_failure_thumbnails` (< max_thumbnails).
  std::size_t max_thumbnails = 24;
  std::size_t max_failure_thumbnails = 6;
  /// A thumbnail is the frame shrunk by the whole factor that brings its width nearest to this, px
  /// (in [16, 2048]).
  int thumbnail_width_px = 256;
  /// Width of the map picture and of the plots, px (in [200, 4096]).
  int figure_width_px = 960;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// The options' names, rules and descriptions; validate() checks them.
const OptionTable<ReportOptions>& reportOptionTable();

/// A frame of the strip: the shrunk picture and what to draw on it, in the full frame's pixels.
struct ReportThumbnail {
  struct Line {
    Segment2 image;     ///< pixels of the full frame
    std::string label;  ///< the predicted segment it matches ("" : none)
  };
  std::size_t index = 0;
  double t = 0;
  int width = 0, height = 0;          ///< the full frame's size (the overlay's coordinates)
  std::string png;                    ///< the shrunk frame, PNG bytes
  std::vector<Segment2> predicted;    ///< the predicted interest segments
  std::vector<Line> detected;         ///< Vision's lines (frame edges left out)
  bool vision_ok = true;
  std::string reason;                 ///< why Vision failed
};

/// Picks and keeps the strip's frames while a run goes on: call add() from RunOptions::on_frame.
/// Memory stays bounded by the options whatever the length of the run.
class ReportFrames {
 public:
  /// Throws InvalidInput for bad options.
  explicit ReportFrames(const ReportOptions& options = {});
  void add(const FrameView& frame);
  /// The kept frames in frame order.
  std::vector<ReportThumbnail> thumbnails() const;

 private:
  ReportOptions options_;
  std::size_t stride_ = 1;
  bool previous_failed_ = false;
  std::vector<ReportThumbnail> regular_, failures_;
};

/// The report's HTML. `dialogue` is the trace as traceDialogue() says it ("" : none written).
std::string reportHtml(const MissionRun& run, const Map& map, const std::vector<ReportThumbnail>& thumbnails,
                       const std::string& dialogue, const ReportOptions& options = {});

/// The trajectories as a GeoJSON FeatureCollection in lon/lat (9 decimals, the map's origin, as
/// exportGeoJson): LineString features named (property "name") "route" (as planned), "true" (when
/// the run has the truth), "estimate" and "odometry" (dead reckoning alone). Throws InvalidInput
/// when the map has no geodetic origin.
std::string trajectoriesGeoJson(const MissionRun& run, const Map& map);

struct ReportFiles {
  std::filesystem::path html;                    ///< DIR/report.html
  std::optional<std::filesystem::path> geojson;  ///< DIR/trajectories.geojson, when the map has an origin
};

/// Writes DIR/report.html and DIR/trajectories.geojson (each atomically; DIR is created). `trace`
/// is the run's trace text, `trace_file` its name for messages ("" text: no dialogue). Throws
/// IoError naming the file, ValidationError when the trace does not read back.
ReportFiles writeReport(const std::filesystem::path& dir, const MissionRun& run, const Map& map,
                        const ReportFrames& frames, const std::string& trace, const std::string& trace_file,
                        const ReportOptions& options = {});

}  // namespace mapnav
