// The mission's option structs validate through their option tables (core/option_table.h) in the
// words "OWNER::FIELD = VALUE: must be RULE".
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>

#include "mapnav/core/error.h"
#include "mapnav/mission/modules.h"
#include "mapnav/mission/runner.h"

namespace mapnav {
namespace {

template <class T>
std::string rejection(const T& options) {
  try {
    options.validate();
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

template <class T>
std::string rejectionOf(const std::function<void(T&)>& change) {
  T options;
  change(options);
  return rejection(options);
}

TEST(MissionOptions, DefaultsValidate) {
  EXPECT_EQ(rejection(MapModuleOptions{}), "");
  EXPECT_EQ(rejection(NavigatorOptions{}), "");
  EXPECT_EQ(rejection(RunOptions{}), "");
}

TEST(MissionOptions, BadValuesAreNamedInTheSameWords) {
  EXPECT_EQ(rejectionOf<RunOptions>([](RunOptions& o) { o.control_dt_s = 0.6; }),
            "RunOptions::control_dt_s = 0.59999999999999998: must be in (0, 0.5]");
  EXPECT_EQ(rejectionOf<RunOptions>([](RunOptions& o) { o.token_validity_frames = 0; }),
            "RunOptions::token_validity_frames = 0: must be finite and > 0");
  EXPECT_EQ(rejectionOf<RunOptions>([](RunOptions& o) { o.vehicle_width_m = std::numeric_limits<double>::infinity(); }),
            "RunOptions::vehicle_width_m = inf: must be finite and >= 0");
  EXPECT_EQ(rejectionOf<RunOptions>([](RunOptions& o) { o.navigator.plan_ahead_m = 0; }),
            "NavigatorOptions::plan_ahead_m = 0: must be finite and > 0");
  EXPECT_EQ(rejectionOf<MapModuleOptions>([](MapModuleOptions& o) { o.filter.motion.scale_sigma = -0.5; }),
            "MotionNoiseOptions::scale_sigma = -0.5: must be finite and >= 0");
  EXPECT_EQ(rejectionOf<MapModuleOptions>([](MapModuleOptions& o) { o.filter.motion.gyro_bias_sigma_deg_s = NAN; }),
            "MotionNoiseOptions::gyro_bias_sigma_deg_s = nan: must be finite and >= 0");
  EXPECT_EQ(rejectionOf<MapModuleOptions>([](MapModuleOptions& o) { o.supervisor.after_rejections = -1; }),
            "MapModuleOptions::park_reset_after_rejections = -1: must be >= 0");
  EXPECT_EQ(rejectionOf<MapModuleOptions>([](MapModuleOptions& o) { o.initial_heading_sigma_deg = 0; }),
            "MapModuleOptions::initial_heading_sigma_deg = 0: must be finite and > 0");
  EXPECT_EQ(rejectionOf<MapModuleOptions>([](MapModuleOptions& o) { o.relocalize.max_lost_frames = 0; }),
            "RelocalizeOptions::max_lost_frames = 0: must be >= 1");
}

}  // namespace
}  // namespace mapnav
