// Atomic outputs and damaged logs, end to end on the built `mapnav`: a
// command that fails midway, or is interrupted by Ctrl-C (SIGINT) or SIGTERM while it works, leaves
// the previous outputs byte-identical and no temporary file or folder behind; `replay --strict` names
// the damaged log's file and line.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "mapnav/core/io.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;

// Every file and folder under `dir`, relative, sorted.
std::vector<std::string> listing(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir)) names.push_back(fs::relative(e.path(), dir).string());
  std::sort(names.begin(), names.end());
  return names;
}

struct Exit {
  int code = -1;
  bool signaled = false;
  std::string err;
};

// Starts `mapnav args...`, waits until `ready(pid)` exists (the command is under way), sends `signal`
// and waits for the end. Stderr goes to `err_file`.
Exit interruptWhen(const std::vector<std::string>& args, const std::function<fs::path(pid_t)>& ready, int signal,
                   const fs::path& err_file) {
  std::vector<std::string> argv_s = {MAPNAV_CLI};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string err_path = err_file.string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    FILE* err = std::freopen(err_path.c_str(), "w", stderr);
    FILE* out = std::freopen("/dev/null", "w", stdout);
    if (err == nullptr || out == nullptr) ::_exit(127);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  Exit result;
  if (pid < 0) return result;
  // Poll (no time is asserted: the limit only keeps a broken command from hanging the test).
  const fs::path marker = ready(pid);
  int status = 0;
  bool exited = false;
  for (int i = 0; i < 6000 && !fs::exists(marker); ++i) {
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      exited = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (!exited) {
    ::kill(pid, signal);
    ::waitpid(pid, &status, 0);
  }
  result.signaled = WIFSIGNALED(status);
  result.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  result.err = readFile(err_file);
  return result;
}

TEST(CtrlC, DuringSimulateLeavesNeitherTheLogNorItsPartialFolder) {
  const fs::path dir = testing::freshTempDir();
  fs::create_directories(dir / "work");
  writeFileAtomic(dir / "work" / "keep.txt", std::string_view("previous\n"));
  const fs::path log = dir / "work" / "log";
  const Exit e = interruptWhen(
      {"simulate", "--mission", testing::sourceDir().string() + "/maps/missions/campus_dialogue.json", "-o", log.string()},
      [&](pid_t pid) { return fs::path(log.string() + ".partial-" + std::to_string(pid)) / "images" / "000002.png"; },
      SIGINT, dir / "err.txt");
  EXPECT_FALSE(e.signaled) << "the handler did not run";
  EXPECT_EQ(e.code, 128 + SIGINT) << e.err;
  EXPECT_NE(e.err.find("mapnav: error: interrupted by signal 2"), std::string::npos) << e.err;
  EXPECT_EQ(listing(dir / "work"), std::vector<std::string>{"keep.txt"});
  EXPECT_EQ(readFile(dir / "work" / "keep.txt"), "previous\n");
  fs::remove_all(dir);
}

TEST(CtrlC, DuringTheDemoKeepsTheEarlierDemosLog) {
  const fs::path dir = testing::freshTempDir();
  const fs::path out = dir / "demo";
  const auto first = testing::runCli({"demo", "-o", out.string(), "--max-frames", "3"});
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const std::string frames = readFile(out / "log" / "frames.jsonl");
  const std::string report = readFile(out / "report.html");
  const std::vector<std::string> before = listing(out);
  // The second demo simulates beside the earlier log; interrupted, it must leave that log alone.
  const Exit e = interruptWhen(
      {"demo", "-o", out.string()},
      [&](pid_t pid) { return out / ("log.new.partial-" + std::to_string(pid)) / "images" / "000002.png"; }, SIGINT,
      dir / "err.txt");
  EXPECT_FALSE(e.signaled) << "the handler did not run";
  EXPECT_EQ(e.code, 128 + SIGINT) << e.err;
  EXPECT_EQ(listing(out), before);
  EXPECT_EQ(readFile(out / "log" / "frames.jsonl"), frames);
  EXPECT_EQ(readFile(out / "report.html"), report);
  fs::remove_all(dir);
}

TEST(CtrlC, DuringARunKeepsThePreviousTraceAndReport) {
  const fs::path dir = testing::freshTempDir();
  const fs::path out = dir / "out";
  fs::create_directories(out / "report");
  writeFileAtomic(out / "trace.jsonl", std::string_view("previous trace\n"));
  writeFileAtomic(out / "report" / "report.html", std::string_view("previous report\n"));
  // The command creates the report folder `started` before the mission's first frame, and removes it
  // again when interrupted.
  const fs::path started = dir / "started";
  const Exit e = interruptWhen({"run", "--mission", testing::sourceDir().string() + "/maps/missions/campus_dialogue.json",
                                "--trace", (out / "trace.jsonl").string(), "--report", started.string()},
                               [&](pid_t) { return started; }, SIGTERM, dir / "err.txt");
  EXPECT_FALSE(e.signaled) << "the handler did not run";
  EXPECT_EQ(e.code, 128 + SIGTERM) << e.err;
  EXPECT_EQ(listing(out), (std::vector<std::string>{"report", "report/report.html", "trace.jsonl"}));
  EXPECT_EQ(readFile(out / "trace.jsonl"), "previous trace\n");
  EXPECT_EQ(readFile(out / "report" / "report.html"), "previous report\n");
  EXPECT_FALSE(fs::exists(started)) << "the report folder the run created, left empty";
  fs::remove_all(dir);
}

// The lenient replay counts the fault in --json; --strict names the file and line and exits 1.
TEST(DamagedLog, StrictReplayNamesTheFileAndLine) {
  const fs::path dir = testing::freshTempDir();
  const std::string mission = testing::fixturePath("missions/short_crossing.json").string();
  const fs::path log = dir / "log";
  const auto sim = testing::runCli({"simulate", "--mission", mission, "-o", log.string(), "--max-frames", "6"});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  fs::remove(log / "images" / "000003.png");
  const auto lenient = testing::runCli({"replay", "--mission", mission, "--log", log.string(), "--json"});
  EXPECT_FALSE(lenient.signaled);
  const auto json = nlohmann::json::parse(lenient.out);
  EXPECT_EQ(json["log_faults"]["missing_image"], 1);
  EXPECT_EQ(json["log_faults"]["total"], 1);
  EXPECT_EQ(json["frames"], 5);
  const auto strict = testing::runCli({"replay", "--mission", mission, "--log", log.string(), "--strict"});
  EXPECT_EQ(strict.exit_code, 1);
  EXPECT_NE(strict.err.find((log / "frames.jsonl").string() + ":4:1: error: log.missing_image: /image:"),
            std::string::npos)
      << strict.err;
  EXPECT_TRUE(strict.out.empty()) << strict.out;
  fs::remove_all(dir);
}

TEST(FailingCommand, StrictReplayOfADamagedLogKeepsThePreviousOutputs) {
  const fs::path dir = testing::freshTempDir();
  const std::string mission = testing::fixturePath("missions/short_crossing.json").string();
  const auto sim = testing::runCli({"simulate", "--mission", mission, "-o", (dir / "log").string(), "--max-frames", "8"});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  // Frame 5 does not decode: found after the modules have run on frames 0..4.
  writeFileAtomic(dir / "log" / "images" / "000005.png", std::string_view("not a png"));
  const fs::path out = dir / "out";
  fs::create_directories(out / "report");
  writeFileAtomic(out / "trace.jsonl", std::string_view("previous trace\n"));
  writeFileAtomic(out / "report" / "report.html", std::string_view("previous report\n"));
  const auto r = testing::runCli({"replay", "--mission", mission, "--log", (dir / "log").string(), "--strict", "--trace",
                                  (out / "trace.jsonl").string(), "--report", (out / "report").string()});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("frames.jsonl:6:1: error: log.corrupt_image"), std::string::npos) << r.err;
  EXPECT_EQ(listing(out), (std::vector<std::string>{"report", "report/report.html", "trace.jsonl"}));
  EXPECT_EQ(readFile(out / "trace.jsonl"), "previous trace\n");
  EXPECT_EQ(readFile(out / "report" / "report.html"), "previous report\n");
  // Without --strict the same command goes through and replaces both.
  const auto lenient = testing::runCli({"replay", "--mission", mission, "--log", (dir / "log").string(), "--trace",
                                        (out / "trace.jsonl").string(), "--report", (out / "report").string()});
  EXPECT_FALSE(lenient.signaled) << lenient.err;
  EXPECT_NE(readFile(out / "trace.jsonl"), "previous trace\n");
  EXPECT_NE(readFile(out / "report" / "report.html").find("log-fault-list"), std::string::npos);
  for (const std::string& name : listing(out)) EXPECT_EQ(name.find(".tmp"), std::string::npos) << name;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mapnav
