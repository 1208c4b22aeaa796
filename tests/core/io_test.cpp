#include "mapnav/core/io.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "mapnav/core/error.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;

TEST(WriteFileAtomic, WritesTheBytesAndLeavesNoTemporaryFile) {
  const fs::path dir = testing::freshTempDir();
  writeFileAtomic(dir / "out.txt", std::string_view("hello\n"));
  EXPECT_EQ(readFile(dir / "out.txt"), "hello\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(WriteFileAtomic, AFailingWriterLeavesTheOldFileAndNoTemporary) {
  const fs::path dir = testing::freshTempDir();
  writeFileAtomic(dir / "out.png", std::string_view("old"));
  EXPECT_THROW(writeFileAtomic(dir / "out.png",
                               [](const fs::path& tmp) {
                                 EXPECT_EQ(tmp.extension(), ".png");  // writers choose formats by extension
                                 writeFileAtomic(tmp, std::string_view("half"));
                                 throw std::runtime_error("encoder failed");
                               }),
               std::runtime_error);
  EXPECT_EQ(readFile(dir / "out.png"), "old");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(WriteFileAtomic, MissingFolderIsAnIoErrorNamingTheFile) {
  const fs::path target = testing::freshTempDir() / "no" / "such" / "dir" / "x.json";
  try {
    writeFileAtomic(target, std::string_view("x"));
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(target.string()), std::string::npos) << e.what();
  }
}

TEST(ReadFile, MissingFileAndFolderAreIoErrors) {
  const fs::path dir = testing::freshTempDir();
  EXPECT_THROW(readFile(dir / "missing.json"), IoError);
  EXPECT_THROW(readFile(dir), IoError);
}

}  // namespace
}  // namespace mapnav
