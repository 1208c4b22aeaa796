#include "mapnav/testing/support.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace mapnav::testing {
namespace fs = std::filesystem;

fs::path sourceDir() { return fs::path(MAPNAV_SOURCE_DIR); }
fs::path mapPath(const std::string& name) { return sourceDir() / "maps" / name; }
fs::path fixturePath(const std::string& name) { return sourceDir() / "tests" / "data" / name; }

fs::path realDataPath(const std::string& name) { return sourceDir().parent_path() / "shared" / "data" / "real" / name; }

::testing::AssertionResult realDataPresent(const std::string& name) {
  const fs::path path = realDataPath(name);
  if (fs::exists(path)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "missing ../shared/data/real/" << name << " (looked for " << path.string()
                                       << "): this test needs the real data sets beside the repository "
                                          "(../shared/data/real/README.md)";
}

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

namespace {

// Removes the folders freshTempDir made once their test has passed, so that a suite run leaves
// nothing behind in the temp dir (about 1 GB a run had filled a CI machine's disk). A failed test's
// folders stay, named on stderr, for a look; MAPNAV_KEEP_TEST_DIRS keeps every folder. Folders made
// outside a test (in SetUpTestSuite) go when the program ends, unless a test failed.
class TempDirCleaner : public ::testing::EmptyTestEventListener {
 public:
  /// A folder asked for again (the same test's name) is listed once.
  void add(const fs::path& dir, bool in_test) {
    std::vector<fs::path>& dirs = in_test ? test_dirs_ : program_dirs_;
    if (std::find(dirs.begin(), dirs.end(), dir) == dirs.end()) dirs.push_back(dir);
  }
  void OnTestEnd(const ::testing::TestInfo& info) override { finish(test_dirs_, !info.result()->Failed()); }
  void OnTestProgramEnd(const ::testing::UnitTest& unit) override { finish(program_dirs_, unit.Passed()); }

 private:
  static void finish(std::vector<fs::path>& dirs, bool passed) {
    const bool keep = !passed || std::getenv("MAPNAV_KEEP_TEST_DIRS") != nullptr;
    for (const fs::path& dir : dirs) {
      std::error_code ignored;
      if (keep) {
        std::fprintf(stderr, "mapnav test: kept %s\n", dir.c_str());
      } else {
        fs::remove_all(dir, ignored);
      }
    }
    dirs.clear();
  }
  std::vector<fs::path> test_dirs_, program_dirs_;
};

TempDirCleaner& tempDirCleaner() {
  static TempDirCleaner* cleaner = [] {
    auto* made = new TempDirCleaner;  // owned by GoogleTest's listener list from here on
    ::testing::UnitTest::GetInstance()->listeners().Append(made);
    return made;
  }();
  return *cleaner;
}

}  // namespace

fs::path freshTempDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = "mapnav-test-" + std::to_string(::getpid());
  if (info != nullptr) name += std::string("-") + info->test_suite_name() + "-" + info->name();
  for (char& c : name) {
    if (c == '/') c = '_';
  }
  const fs::path dir = fs::temp_directory_path() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  tempDirCleaner().add(dir, info != nullptr);
  return dir;
}

::testing::AssertionResult vecNear(const Vec2& actual, const Vec2& expected, double tolerance) {
  const double d = (actual - expected).norm();
  if (d <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "(" << actual.x() << ", " << actual.y() << ") is " << d << " from ("
                                       << expected.x() << ", " << expected.y() << "), tolerance " << tolerance;
}

::testing::AssertionResult poseNear(const Pose2& actual, const Pose2& expected, double tolerance) {
  const double dt = (actual.translation() - expected.translation()).norm();
  const double dh = std::abs(normalizeAngle(actual.heading() - expected.heading()));
  if (dt <= tolerance && dh <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "pose (" << actual.x() << ", " << actual.y() << ", " << actual.heading()
                                       << ") vs (" << expected.x() << ", " << expected.y() << ", "
                                       << expected.heading() << "): translation off by " << dt << ", heading by "
                                       << dh << ", tolerance " << tolerance;
}

namespace {
std::unique_ptr<Camera> terregator(LensModel lens, int width, int height, double tilt_deg, double yaw_deg) {
  CameraIntrinsics in;
  in.width = width;
  in.height = height;
  in.fx = in.fy = (lens == LensModel::Pinhole ? 904.0 : 257.0) * width / 512.0;
  in.cx = (width - 1) / 2.0;
  in.cy = (height - 1) / 2.0;
  CameraMount mount;
  mount.height_m = 1.5;
  mount.tilt_rad = degToRad(tilt_deg);
  mount.yaw_rad = degToRad(yaw_deg);
  return createCamera(lens, in, mount);
}
}  // namespace

std::unique_ptr<Camera> terregatorPinhole(double tilt_deg, double yaw_deg) {
  return terregator(LensModel::Pinhole, 512, 480, tilt_deg, yaw_deg);
}

std::unique_ptr<Camera> terregatorCamera(LensModel lens, int width, int height) {
  return terregator(lens, width, height, lens == LensModel::Pinhole ? 22.0 : 20.0, 0.0);
}

namespace {
std::string slurp(int fd) {
  std::string data;
  char buffer[65536];
  ssize_t n;
  while ((n = ::read(fd, buffer, sizeof buffer)) > 0) data.append(buffer, static_cast<std::size_t>(n));
  return data;
}
}  // namespace

CommandResult runCli(const std::vector<std::string>& args) { return runProgram(MAPNAV_CLI, args); }

CommandResult runProgram(const std::string& program_path, const std::vector<std::string>& args) {
  // Output goes to temporary files rather than pipes, so a chatty child cannot dead-lock us.
  const fs::path dir = fs::temp_directory_path();
  const std::string stem = "mapnav-cli-" + std::to_string(::getpid());
  const fs::path outPath = dir / (stem + ".out"), errPath = dir / (stem + ".err");
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int out = ::open(outPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int err = ::open(errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int in = ::open("/dev/null", O_RDONLY);
    ::dup2(in, 0);
    ::dup2(out, 1);
    ::dup2(err, 2);
    std::vector<char*> argv;
    std::string program = program_path;
    argv.push_back(program.data());
    std::vector<std::string> copy = args;
    for (std::string& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(program.c_str(), argv.data());
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  CommandResult result;
  if (WIFSIGNALED(status)) {
    result.signaled = true;
    result.exit_code = 128 + WTERMSIG(status);
  } else {
    result.exit_code = WEXITSTATUS(status);
  }
  for (auto [path, target] : {std::pair{outPath, &result.out}, std::pair{errPath, &result.err}}) {
    const int fd = ::open(path.c_str(), O_RDONLY);
    if (fd >= 0) {
      *target = slurp(fd);
      ::close(fd);
    }
    fs::remove(path);
  }
  return result;
}

}  // namespace mapnav::testing
