// `mapnav eval segmentation` on three real CamVid photos (../shared/data/real/camvid), and its bad inputs.
#include <gtest/gtest.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "mapnav/core/io.h"
#include "mapnav/image/png.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;
using testing::runCli;

const std::vector<std::string> kStems = {"0006R0_f00930", "0016E5_00390", "Seq05VD_f00000"};

// Three photos and their labels copied to a temp folder (the data stays out of the repository).
fs::path threeImages() {
  const fs::path camvid = testing::realDataPath("camvid");
  const fs::path dir = testing::freshTempDir();
  fs::create_directories(dir / "images");
  fs::create_directories(dir / "labels");
  for (const std::string& s : kStems) {
    fs::copy_file(camvid / "images" / (s + ".png"), dir / "images" / (s + ".png"));
    fs::copy_file(camvid / "labels" / (s + ".png"), dir / "labels" / (s + ".png"));
  }
  return dir;
}

std::vector<std::string> evalArgs(const fs::path& dir, const std::vector<std::string>& more) {
  std::vector<std::string> a = {"eval", "segmentation", "--pipeline", "sidewalk", "--images", (dir / "images").string(),
                                "--labels", (dir / "labels").string(), "--road-values", "3,4", "--ignore-values", "11"};
  a.insert(a.end(), more.begin(), more.end());
  return a;
}

TEST(EvalCli, ScoresThreeCamVidPhotosWithOverlays) {
  ASSERT_TRUE(testing::realDataPresent("camvid"));
  const fs::path dir = threeImages();
  // The sidewalk pipeline's options for photos (docs/eval.md): its defaults are for the campus
  // simulation and give up on most CamVid photos.
  const auto r = runCli(evalArgs(dir, {"--json", "--overlays", (dir / "overlays").string(), "--options",
                                       R"({"adaptive":false,"min_separation":0,"llr_threshold":-10})"}));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["images"], 3);
  EXPECT_EQ(j["pipeline"], "sidewalk");
  EXPECT_TRUE(j["maxf"].is_null());  // no pipeline gives a per-pixel confidence
  EXPECT_TRUE(j["ap"].is_null());
  // The summary agrees with the per-image figures it prints.
  std::vector<double> ious;
  for (const auto& p : j["per_image"]) ious.push_back(p["iou"].get<double>());
  ASSERT_EQ(ious.size(), 3u);
  std::sort(ious.begin(), ious.end());
  EXPECT_DOUBLE_EQ(j["iou_median"].get<double>(), ious[1]);
  EXPECT_DOUBLE_EQ(j["iou_worst"].get<double>(), ious[0]);
  // IoU ≤ min(precision, recall) always: TP/(TP+FP+FN) has the larger denominator.
  EXPECT_LE(j["iou"].get<double>(), std::min(j["precision"].get<double>(), j["recall"].get<double>()) + 1e-4);
  // The road is found, if not perfectly (0.874 over all 30 photos, docs/eval.md).
  EXPECT_GT(j["iou"].get<double>(), 0.75) << r.out;
  // One overlay per photo, the photo's size; an unlabelled (11) pixel is the photo darkened to a third.
  for (const std::string& s : kStems) {
    const Image o = readPng(dir / "overlays" / (s + ".png"));
    const Image photo = readPng(dir / "images" / (s + ".png"));
    const Image label = readPng(dir / "labels" / (s + ".png"));
    ASSERT_EQ(o.width, 480);
    ASSERT_EQ(o.height, 360);
    const auto it = std::find(label.data.begin(), label.data.end(), 11);
    ASSERT_NE(it, label.data.end()) << s;
    const std::size_t i = static_cast<std::size_t>(it - label.data.begin());
    for (int k = 0; k < 3; ++k) EXPECT_EQ(o.data[3 * i + k], photo.data[3 * i + k] / 3) << s;
  }
  // The text form and the other bootstrap.
  const auto text = runCli(evalArgs(dir, {"--bootstrap", "labels-first-frame"}));
  EXPECT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("sidewalk (bootstrap labels-first-frame): 3 images"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("MaxF null, AP null: the pipeline gives no per-pixel confidence"), std::string::npos);
}

TEST(EvalCli, BadInputNamesTheFileAndWritesNothing) {
  ASSERT_TRUE(testing::realDataPresent("camvid"));
  const fs::path dir = threeImages();
  const std::string overlays = (dir / "overlays").string();

  auto r = runCli({"eval", "segmentation", "--images", (dir / "nope").string(), "--labels", (dir / "labels").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find((dir / "nope").string() + ": no such folder"), std::string::npos) << r.err;

  // A label of another size.
  const fs::path label = dir / "labels" / (kStems[1] + ".png");
  fs::rename(label, dir / "saved.png");
  writePng(Image(10, 10, 1), label);
  r = runCli(evalArgs(dir, {"--overlays", overlays}));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(label.string() + ": the label is 10x10 but its image is 480x360"), std::string::npos) << r.err;

  // A corrupt PNG.
  writeFileAtomic(label, std::string("not a png"));
  r = runCli(evalArgs(dir, {"--overlays", overlays}));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(label.string()), std::string::npos) << r.err;

  // An image without its label.
  fs::remove(label);
  r = runCli(evalArgs(dir, {"--overlays", overlays}));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find((dir / "images" / (kStems[1] + ".png")).string() + ": no label"), std::string::npos) << r.err;

  // Bad values.
  fs::rename(dir / "saved.png", label);
  r = runCli(evalArgs(dir, {"--bootstrap", "middle"}));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--bootstrap \"middle\""), std::string::npos) << r.err;
  r = runCli({"eval", "segmentation", "--images", (dir / "images").string(), "--labels", (dir / "labels").string(),
              "--road-values", "3", "--ignore-values", "3"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("ignore: label value 3 is also a road value"), std::string::npos) << r.err;

  EXPECT_FALSE(fs::exists(overlays));  // nothing written by any failed run
}

}  // namespace
}  // namespace mapnav
