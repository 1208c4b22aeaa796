// `mapnav train segmentation` end to end: from photos, from a simulated log, and its bad inputs
// (nothing written); `mapnav run --pipeline learned --options` on the simulator's model.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "mapnav/learned/segmentation_model.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;
using testing::runCli;

/// Four camvid_train photos and their labels in a temp folder.
fs::path fourPhotos() {
  const fs::path src = testing::realDataPath("camvid_train");
  const fs::path dir = testing::freshTempDir();
  fs::create_directories(dir / "images");
  fs::create_directories(dir / "labels");
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(src / "images")) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (std::size_t i = 0; i < 4; ++i) {
    fs::copy_file(files[i], dir / "images" / files[i].filename());
    fs::copy_file(src / "labels" / files[i].filename(), dir / "labels" / files[i].filename());
  }
  return dir;
}

TEST(TrainCli, TrainsOnPhotosAndWritesALoadableModelThatRecordsItsCommand) {
  ASSERT_TRUE(testing::realDataPresent("camvid_train"));
  const fs::path dir = fourPhotos();
  const fs::path model = dir / "m.mnseg";
  const auto r = runCli({"train", "segmentation", "--images", (dir / "images").string(), "--labels", (dir / "labels").string(),
                         "--road-values", "3,4", "--ignore-values", "11", "--epochs", "2", "--size", "64x48", "--threads",
                         "1", "-o", model.string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["training_images"], 3);  // the fourth held apart (at least one of two or more)
  EXPECT_EQ(j["validation_images"], 1);
  EXPECT_EQ(j["input"]["width"], 64);
  EXPECT_EQ(j["epochs"], 2);
  EXPECT_NE(r.err.find("epoch 2/2"), std::string::npos) << r.err;  // the progress line
  const SegmentationModel m = SegmentationModel::load(model);
  EXPECT_EQ(m.inputWidth(), 64);
  EXPECT_EQ(m.inputHeight(), 48);
  EXPECT_NE(m.training().command.find("--epochs 2 --seed 1 --size 64x48"), std::string::npos) << m.training().command;
}

TEST(TrainCli, TrainsOnASimulatedLogsTruthMasks) {
  const fs::path dir = testing::freshTempDir();
  const auto sim = runCli({"simulate", "--mission", testing::mapPath("missions/campus_dialogue.json").string(), "--seed", "5",
                           "--max-frames", "6", "-o", (dir / "log").string()});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const auto r = runCli({"train", "segmentation", "--log", (dir / "log").string(), "--log-stride", "2", "--epochs", "1",
                         "--size", "64x60", "--threads", "1", "-o", (dir / "sim.mnseg").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["training_images"].get<int>() + j["validation_images"].get<int>(), 3);  // frames 0, 2, 4
}

TEST(TrainCli, BadInputsSayWhatAndWriteNothing) {
  const fs::path dir = testing::freshTempDir();
  const std::string out = (dir / "m.mnseg").string();
  struct Case {
    std::vector<std::string> args;
    int exit_code;
    std::string words;
  };
  const std::vector<Case> cases = {
      {{"--images", (dir / "none").string(), "--labels", (dir / "none").string()}, 2, "no such folder"},
      {{"--images", dir.string()}, 2, "--images and --labels go together"},  // a missing argument: usage
      {{}, 2, "nothing to train on"},
      {{"--log", dir.string()}, 2, dir.string()},
      {{"--log", dir.string(), "--size", "64"}, 1, "--size \"64\""},  // a malformed value: wrong input
      {{"--log", dir.string(), "--epochs", "0"}, 1, "SegmentationTrainOptions::epochs"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args = {"train", "segmentation", "-o", out};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const auto r = runCli(args);
    EXPECT_EQ(r.exit_code, c.exit_code) << c.words << ": " << r.err;
    EXPECT_NE(r.err.find(c.words), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.words;
  }
}

TEST(RunCli, LearnedPipelineWithTheSimulatorsModelDrivesCampusDialogue) {
  // models/sim.mnseg was trained on logs of other world seeds (scripts/train-models); the mission's is 1985.
  const auto r = runCli({"run", "--mission", testing::mapPath("missions/campus_dialogue.json").string(), "--pipeline",
                         "learned", "--options", R"({"model": "sim"})", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["pipeline"], "learned");
  EXPECT_TRUE(j["reached_goal"].get<bool>());
  EXPECT_EQ(j["vision_failures"], 0);
  EXPECT_LE(j["lateral_rms_m"].get<double>(), 0.05);
  EXPECT_LE(j["heading_rms_deg"].get<double>(), 0.5);
}

}  // namespace
}  // namespace mapnav
