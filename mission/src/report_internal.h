#pragma once
// Shared by the report's page (report.cpp) and its figures (report_figures.cpp), internal to
// mission/: the colours of the route, the trajectories and the failures (the figures draw in them,
// the legends' swatches show them), the page's text escaping, the runs of failed frames, the
// trajectories as points, and the two figures the page places.
#include <optional>
#include <string>
#include <vector>

#include "mapnav/map/map.h"
#include "mapnav/mission/report.h"
#include "mapnav/render/canvas.h"
#include "mapnav/render/xml.h"

namespace mapnav::detail {

using render::Rgb;

constexpr Rgb kRouteColor{120, 170, 255};
constexpr Rgb kTruthColor{20, 20, 20};
constexpr Rgb kEstimateColor{0, 90, 230};
constexpr Rgb kOdometryColor{240, 120, 0};
constexpr Rgb kAlongColor{0, 150, 70};
constexpr Rgb kFailureColor{220, 30, 30};
constexpr Rgb kGnssColor{150, 0, 200};
constexpr Rgb kHaltColor{250, 170, 170};
constexpr Rgb kIntersectionCueColor{90, 90, 90};  // the along-road position fixed by lines across the road
constexpr Rgb kLandmarkCueColor{200, 120, 0};     // ... by a landmark

inline std::string escape(const std::string& text) { return render::escapeXml(text); }

// Frames whose Vision failed, grouped into runs of consecutive frames.
struct FailureRun {
  std::size_t first = 0, last = 0;  // indices into run.frames
  std::string reason;
};

inline std::vector<FailureRun> failureRuns(const MissionRun& run) {
  std::vector<FailureRun> runs;
  for (std::size_t i = 0; i < run.frames.size(); ++i) {
    if (run.frames[i].vision_ok) continue;
    if (!runs.empty() && runs.back().last + 1 == i) {
      runs.back().last = i;
    } else {
      runs.push_back({i, i, run.frames[i].vision_reason});
    }
  }
  return runs;
}

inline std::vector<Vec2> track(const MissionRun& run, std::optional<Pose2> FrameRecord::*truth) {
  std::vector<Vec2> points;
  for (const FrameRecord& f : run.frames) {
    if (const auto& p = f.*truth) points.push_back(p->translation());
  }
  return points;
}

inline std::vector<Vec2> track(const MissionRun& run, Pose2 FrameRecord::*pose) {
  std::vector<Vec2> points;
  for (const FrameRecord& f : run.frames) points.push_back((f.*pose).translation());
  return points;
}

/// The map with the planned route, the true, estimated and odometry-only trajectories, the GNSS
/// fixes and where Vision failed, as an inline <svg> (report_figures.cpp).
std::string mapFigure(const MissionRun& run, const Map& map, const ReportOptions& options);
/// The plots of the errors over time, failed and halted frames shaded; a note when the run has no
/// ground truth (report_figures.cpp).
std::string errorPlots(const MissionRun& run, const ReportOptions& options);

}  // namespace mapnav::detail
