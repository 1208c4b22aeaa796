#pragma once
// Helpers shared by every test program.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "mapnav/core/error.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/types.h"

namespace mapnav::testing {

/// The source tree's root (fixtures, maps/).
std::filesystem::path sourceDir();
/// `maps/NAME` in the source tree.
std::filesystem::path mapPath(const std::string& name);
/// `tests/data/NAME` in the source tree.
std::filesystem::path fixturePath(const std::string& name);
/// `../shared/data/real/NAME` beside the source tree: real data recorded by others (its README),
/// read in place, never copied into the repository.
std::filesystem::path realDataPath(const std::string& name);
/// Success when realDataPath(name) exists; otherwise a failure naming the missing folder or file.
/// Tests that need real data fail without it (never skip): `ASSERT_TRUE(realDataPresent("camvid"))`.
::testing::AssertionResult realDataPresent(const std::string& name);
/// True in the sanitizer build (build-asan/, AddressSanitizer), where the code runs 5-10 times
/// slower: the long closed-loop and evaluation tests drive a shorter stretch there, and the release
/// stage of scripts/test runs them whole.
inline constexpr bool kUnderSanitizers =
#if defined(__SANITIZE_ADDRESS__)
    true;
#else
    false;
#endif

/// A fresh empty folder under the system temp dir, unique to the running test; removed when the
/// test passes, kept (and named on stderr) when it fails or MAPNAV_KEEP_TEST_DIRS is set.
std::filesystem::path freshTempDir();

/// How many times `what` occurs in `text` (overlapping occurrences counted).
std::size_t occurrences(const std::string& text, const std::string& what);

/// Success when calling `f` throws InvalidInput whose message contains `words` (the bad field's
/// name, say); otherwise a failure saying what happened instead. Another exception propagates.
template <class F>
::testing::AssertionResult throwsInvalidInputNaming(F&& f, const std::string& words) {
  try {
    f();
  } catch (const InvalidInput& e) {
    if (std::string(e.what()).find(words) != std::string::npos) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "the message \"" << e.what() << "\" does not name " << words;
  }
  return ::testing::AssertionFailure() << "nothing thrown: accepted (" << words << ")";
}

::testing::AssertionResult vecNear(const Vec2& actual, const Vec2& expected, double tolerance);
::testing::AssertionResult poseNear(const Pose2& actual, const Pose2& expected, double tolerance);
#define EXPECT_VEC2_NEAR(a, b, tol) EXPECT_TRUE(::mapnav::testing::vecNear((a), (b), (tol)))
#define EXPECT_POSE_NEAR(a, b, tol) EXPECT_TRUE(::mapnav::testing::poseNear((a), (b), (tol)))

/// The camera of maps/cameras/terregator_pinhole.json, built in code: 512 x 480, f = 904 px,
/// principal point (255.5, 239.5), 1.5 m high, tilted `tilt_deg` down (22 in the file), yawed
/// `yaw_deg` left.
std::unique_ptr<Camera> terregatorPinhole(double tilt_deg = 22.0, double yaw_deg = 0.0);
/// The Terregator cameras of maps/cameras/ at width x height, for frames smaller or squarer than
/// the files': the focal length scaled with the width (pin-hole 904 px, 22 deg down; the paper's
/// fish-eye 257 px, 20 deg down; per 512 px), the principal point at the centre, 1.5 m high.
/// terregatorCamera(LensModel::Pinhole, 512, 480) is terregatorPinhole().
std::unique_ptr<Camera> terregatorCamera(LensModel lens, int width, int height);

/// What running the built `mapnav` CLI gave.
struct CommandResult {
  int exit_code = -1;     ///< the exit status, or 128 + signal when it was killed by one
  bool signaled = false;  ///< true when the process died of a signal (a crash)
  std::string out;
  std::string err;
};
/// Runs the built `mapnav` with `args` (no shell), capturing stdout and stderr.
CommandResult runCli(const std::vector<std::string>& args);
/// Runs `program` (a path; no shell, no PATH search) with `args` the same way.
CommandResult runProgram(const std::string& program, const std::vector<std::string>& args);

}  // namespace mapnav::testing
