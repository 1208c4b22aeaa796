// The mission runner's entry points: runReplay builds its frame source (a log), runClosedLoopOver
// takes the one its caller makes (a plant: mission_sim's simulator); both build the module loop, run
// the one loop over them, and say how the run ended.
#include "mapnav/mission/runner.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "mapnav/core/error.h"
#include "mapnav/core/option_table.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/map/map_io.h"
#include "mapnav/mission/frame_source.h"
#include "mapnav/navigator/road_position.h"

#include "module_loop.h"
#include "replay_source.h"

namespace mapnav {

const OptionTable<RunOptions>& runOptionTable() {
  using O = RunOptions;
  static const OptionTable<O> table =
      OptionTable<O>("RunOptions")
          .field("control_dt_s", &O::control_dt_s, aboveUpTo(0, 0.5),
                 "closed loop: the control period of Motion Control and the vehicle, s")
          .field("token_validity_frames", &O::token_validity_frames, above(0),
                 "a prediction, detection or position is used within this many frame periods")
          .field("command_validity_frames", &O::command_validity_frames, above(0),
                 "a steering plan is used within this many frame periods")
          .field("max_odometry_speed_mps", &O::max_odometry_speed_mps, atLeast(0),
                 "replay: odometry faster than this is a spike, m/s; 0 = twice the mission's speed, at least 5")
          .field("max_odometry_turn_rate_deg_s", &O::max_odometry_turn_rate_deg_s, above(0),
                 "replay: odometry turning faster than this is a spike, deg/s")
          .field("vehicle_width_m", &O::vehicle_width_m, atLeast(0),
                 "the vehicle's width for \"stays on the path\", m");
  return table;
}

void RunOptions::validate() const {
  runOptionTable().validate(*this);
  if (displace && !(std::isfinite(displace->forward_m) && std::isfinite(displace->left_m)))
    throw InvalidInput("RunOptions::displace: forward_m and left_m must be finite");
  path_agreement.validate();
  map.validate();
  navigator.validate();
}

namespace {

// The one loop: the source's next frame (its faults first) through the modules, until the source
// ends or the modules end the mission. A plant is driven between frames by Motion Control.
void runFrames(FrameSource& source, detail::ModuleLoop& loop, const RunOptions& options) {
  SourceFrame frame;
  while (true) {
    const bool got = source.next(loop, frame);
    for (const LogFault& f : frame.faults) loop.fault(f);
    if (!got) return;
    const bool go_on = loop.frame(frame);
    if (options.progress) {
      const std::size_t done = frame.index + 1;
      options.progress(RunProgress{done, std::max(source.expectedFrames(), done), frame.t});
    }
    if (!go_on) return;
  }
}

// The vehicle's limits, fast enough for the mission's speed.
VehicleLimits missionLimits(const MissionFile& mission) {
  VehicleLimits limits;
  limits.max_speed_mps = std::max(limits.max_speed_mps, mission.speed_mps);
  return limits;
}

}  // namespace

MissionRun runReplay(const MissionFile& mission, const std::filesystem::path& log_dir, const RunOptions& options) {
  options.validate();
  RunOptions source_options = options;
  if (source_options.max_odometry_speed_mps == 0) source_options.max_odometry_speed_mps = std::max(5.0, 2 * mission.speed_mps);
  detail::ReplaySource source(log_dir, source_options);
  const Map map = loadMap(mission.map);
  MissionRun run;
  run.mode = "replay";
  run.mission = mission.name;
  run.log = log_dir;
  detail::ModuleLoop loop(mission, map, map, source.camera(), options, false, missionLimits(mission), run);
  loop.header(detail::absolutePath(log_dir));
  runFrames(source, loop, options);
  run.distance_m = source.odometryDistance();
  run.stopped_early = !run.ended_by_halt && source.stoppedEarly();
  if (!run.frames.empty()) run.duration_s = run.frames.back().t - run.frames.front().t;
  loop.finish(source.truth());

  // The log's path goes where it was driven whatever the estimate did: the vehicle is judged where
  // it was when the Navigator believed it arrived, never at the log's end. The Navigator arrives
  // within 0.5 m of the goal by its estimate, so the goal is reached when that estimate was right
  // to 0.5 m.
  MissionMetrics& m = run.metrics;
  const auto arrival = std::find_if(run.frames.begin(), run.frames.end(),
                                    [&](const FrameRecord& f) { return m.arrived_frame && f.index == *m.arrived_frame; });
  const bool arrived = arrival != run.frames.end();
  if (!run.frames.empty()) {
    const FrameRecord& judged = arrived ? *arrival : run.frames.back();
    m.goal_distance_m = ((judged.truth ? *judged.truth : judged.estimate).translation() - run.goal.translation()).norm();
    const bool right = arrived && (!arrival->truth ||
                                   (arrival->truth->translation() - arrival->estimate.translation()).norm() <= 0.5);
    m.reached_goal = !run.ended_by_halt && right;
  }
  if (run.outcome.empty()) {
    const std::string vehicle = m.has_truth ? "the vehicle" : "its estimate";
    if (m.reached_goal) {
      run.outcome = strprintf("goal reached (the Navigator arrived at frame %zu, %s %.2f m from the goal)",
                              arrival->index, vehicle.c_str(), m.goal_distance_m);
    } else if (arrived) {
      run.outcome = strprintf("the Navigator believed it arrived at frame %zu, but the vehicle was %.2f m from the goal",
                              arrival->index, m.goal_distance_m);
    } else if (run.stopped_early) {
      run.outcome = "stopped after " + std::to_string(run.frames.size()) + " frames (the run's max_frames), " +
                    strprintf("%.1f m before the goal", loop.navigator().status().to_go_m);
    } else {
      run.outcome = strprintf("the log ended before the Navigator arrived: the estimate %.2f m from the goal",
                              m.estimate_goal_distance_m);
      if (m.has_truth) run.outcome += strprintf(", the vehicle %.2f m", m.goal_distance_m);
    }
  }
  loop.writeTrace();
  return run;
}

MissionRun runClosedLoopOver(const MissionFile& mission, const Map& map, const Camera& camera, const RunOptions& options,
                             const DrivenSourceFactory& make_source, const Map* world) {
  options.validate();
  MissionRun run;
  run.mode = "closed-loop";
  run.mission = mission.name;
  const VehicleLimits limits = missionLimits(mission);
  detail::ModuleLoop loop(mission, map, world ? *world : map, camera, options, true, limits, run);
  loop.header("");

  const std::unique_ptr<DrivenSource> made = make_source(run, limits);
  if (!made) throw InvalidInput("runClosedLoopOver: make_source returned no source");
  DrivenSource& source = *made;
  runFrames(source, loop, options);
  run.duration_s = source.duration_s();
  run.distance_m = source.distance_m();
  run.stopped_early =
      !run.ended_by_halt && !source.finished() && options.max_frames > 0 && source.frames() >= options.max_frames;
  loop.finish(detail::framesTruth(run.frames));

  MissionMetrics& m = run.metrics;
  // Where the goal truly is: its road position on the world's roads (the same metres from the same
  // intersection: what a person walking the mission would call the goal).
  const Vec2 goal = world ? toPose(*world, clampedTo(*world, mission.goal)).translation() : run.goal.translation();
  m.goal_distance_m = (source.pose().translation() - goal).norm();
  m.reached_goal = !run.ended_by_halt && source.finished() && m.goal_distance_m <= 0.5;
  if (run.outcome.empty()) {
    if (m.reached_goal) {
      run.outcome = strprintf("goal reached (%.2f m from it)", m.goal_distance_m);
    } else if (source.finished()) {
      run.outcome = strprintf("stopped where it believed the goal was, %.2f m from it", m.goal_distance_m);
    } else if (run.stopped_early) {
      run.outcome = "stopped after " + std::to_string(source.frames()) + " frames (the run's max_frames), " +
                    strprintf("%.1f m before the goal", loop.navigator().status().to_go_m);
    } else {
      run.outcome = strprintf("time limit (%.0f s) reached %.2f m from the goal", source.time_limit_s(), m.goal_distance_m);
    }
  }
  loop.writeTrace();
  return run;
}

}  // namespace mapnav
