// The test helpers' own behaviour that other tests rely on: freshTempDir's folders go away with a
// passing test and stay with a failing one; throwsInvalidInputNaming fails where a check should.
#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;

// Run by the tests below in a child process of this program (disabled, so never on their own):
// each writes a file into its fresh folder and prints the folder's path.
TEST(FreshTempDirChild, DISABLED_Passes) {
  const fs::path dir = testing::freshTempDir();
  std::ofstream(dir / "file.txt") << "x";
  std::printf("dir=%s\n", dir.c_str());
}
TEST(FreshTempDirChild, DISABLED_Fails) {
  testing::freshTempDir();  // asked twice, as some tests do: the same folder, named once
  const fs::path dir = testing::freshTempDir();
  std::ofstream(dir / "file.txt") << "x";
  std::printf("dir=%s\n", dir.c_str());
  ADD_FAILURE() << "failing on purpose";
}

// The folder the child printed, after it has exited.
fs::path childsFolder(const testing::CommandResult& r) {
  const auto at = r.out.find("dir=");
  if (at == std::string::npos) return {};
  return fs::path(r.out.substr(at + 4, r.out.find('\n', at) - at - 4));
}

testing::CommandResult runChild(const std::string& test) {
  return testing::runProgram(fs::read_symlink("/proc/self/exe").string(),
                             {"--gtest_also_run_disabled_tests", "--gtest_filter=FreshTempDirChild.DISABLED_" + test});
}

TEST(FreshTempDir, APassingTestsFolderIsRemoved) {
  const testing::CommandResult r = runChild("Passes");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const fs::path dir = childsFolder(r);
  ASSERT_FALSE(dir.empty()) << r.out;
  EXPECT_NE(dir.string().find("FreshTempDirChild-DISABLED_Passes"), std::string::npos) << dir;
  EXPECT_FALSE(fs::exists(dir)) << dir << " was left behind";
}

TEST(FreshTempDir, AFailingTestsFolderIsKeptAndNamed) {
  const testing::CommandResult r = runChild("Fails");
  ASSERT_EQ(r.exit_code, 1) << r.out << r.err;
  const fs::path dir = childsFolder(r);
  ASSERT_FALSE(dir.empty()) << r.out;
  EXPECT_TRUE(fs::is_regular_file(dir / "file.txt")) << dir;
  EXPECT_EQ(testing::occurrences(r.err, "mapnav test: kept " + dir.string() + "\n"), 1u) << r.err;
  fs::remove_all(dir);
}

TEST(ThrowsInvalidInputNaming, SucceedsOnlyOnAnInvalidInputThatNamesTheWords) {
  const auto bad_speed = [] { throw InvalidInput("speed_mps: -1 is not positive"); };
  EXPECT_TRUE(testing::throwsInvalidInputNaming(bad_speed, "speed_mps"));
  const ::testing::AssertionResult other_field = testing::throwsInvalidInputNaming(bad_speed, "width");
  EXPECT_FALSE(other_field);
  EXPECT_EQ(std::string(other_field.message()), "the message \"speed_mps: -1 is not positive\" does not name width");
  const ::testing::AssertionResult accepted = testing::throwsInvalidInputNaming([] {}, "speed_mps");
  EXPECT_FALSE(accepted);
  EXPECT_EQ(std::string(accepted.message()), "nothing thrown: accepted (speed_mps)");
  EXPECT_THROW(testing::throwsInvalidInputNaming([] { throw IoError("disk"); }, "disk"), IoError);
}

}  // namespace
}  // namespace mapnav
