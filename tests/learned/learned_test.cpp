// The learned segmentation: its model file, training (falls, rises, same bytes), the committed
// model's figure on shared photos and the "learned" pipeline (docs/learned.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "mapnav/core/error.h"
#include "mapnav/image/png.h"
#include "mapnav/learned/learned_pipeline.h"
#include "mapnav/mission/image_region.h"
#include "mapnav/learned/segmentation_model.h"
#include "mapnav/learned/train_segmentation.h"
#include "mapnav/testing/support.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision/segmentation_eval.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {
namespace {

namespace fs = std::filesystem;
using testing::freshTempDir;
using testing::realDataPath;
using testing::realDataPresent;

/// The pin-hole `mapnav eval` and `mapnav train` assume for photos without a camera: level, so the
/// ground is the lower half of the image (docs/eval.md).
Image lowerHalf(int width, int height) {
  Image g(width, height, 1);
  for (int v = height / 2; v < height; ++v)
    for (int u = 0; u < width; ++u) g.pixel(u, v)[0] = 1;
  return g;
}

/// `count` CamVid photos of `set` from `first` (in file-name order), road = 3, 4, 11 left out.
std::vector<TrainingPhoto> camvid(const std::string& set, std::size_t first, std::size_t count) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(realDataPath(set) / "images")) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<TrainingPhoto> out;
  for (std::size_t i = first; i < std::min(files.size(), first + count); ++i) {
    TrainingPhoto p;
    p.name = files[i].string();
    p.rgb = readPng(files[i]);
    const Image label = readPng(realDataPath(set) / "labels" / files[i].filename());
    p.road = Image(label.width, label.height, 1);
    for (std::size_t k = 0; k < label.data.size(); ++k)
      p.road.data[k] = label.data[k] == 3 || label.data[k] == 4 ? 1 : label.data[k] == 11 ? 255 : 0;
    p.ground = lowerHalf(label.width, label.height);
    out.push_back(std::move(p));
  }
  return out;
}

SegmentationTrainOptions quick() {
  SegmentationTrainOptions o;
  o.epochs = 6;
  o.width = 96;
  o.height = 72;
  o.batch = 4;
  o.validation_fraction = 0.25;  // 2 of 8 photos held apart
  o.threads = 1;
  return o;
}

TEST(SegmentationTraining, DefaultsAreValidAndBadOptionsNamed) {
  EXPECT_NO_THROW(SegmentationTrainOptions{}.validate());
  SegmentationTrainOptions o;
  o.learning_rate = 0;
  try {
    o.validate();
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("SegmentationTrainOptions::learning_rate"), std::string::npos) << e.what();
  }
  for (const auto& [field, bad] : std::vector<std::pair<std::string, SegmentationTrainOptions>>{
           {"grey_fraction", [] { SegmentationTrainOptions b; b.grey_fraction = 1.5; return b; }()},
           {"contrast", [] { SegmentationTrainOptions b; b.contrast = 1; return b; }()},
           {"noise_levels", [] { SegmentationTrainOptions b; b.noise_levels = -1; return b; }()},
           {"zoom", [] { SegmentationTrainOptions b; b.zoom = 0.5; return b; }()}}) {
    try {
      bad.validate();
      ADD_FAILURE() << field;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("SegmentationTrainOptions::" + field), std::string::npos) << e.what();
    }
  }
}

TEST(SegmentationTraining, LossFallsAndValidationIouRisesOnEightPhotos) {
  ASSERT_TRUE(realDataPresent("camvid_train"));
  const std::vector<TrainingPhoto> photos = camvid("camvid_train", 0, 8);
  ASSERT_EQ(photos.size(), 8u);
  const std::vector<TrainingPhoto> held = {photos[3], photos[7]};  // every 4th: what the trainer holds apart
  SegmentationTrainOptions o = quick();
  // The optimiser alone: six epochs of six augmented photos teach next to nothing yet.
  o.grey_fraction = o.contrast = o.blur_fraction = o.noise_levels = 0;
  o.zoom = 1;
  const std::optional<double> before = segmentationIou(SegmentationModel(o.width, o.height, o.seed), held);
  std::vector<EpochReport> reports;
  const SegmentationModel model = trainSegmentation(photos, o, [&](const EpochReport& r) { reports.push_back(r); });
  ASSERT_EQ(reports.size(), 6u);
  EXPECT_LT(reports.back().loss, 0.7 * reports.front().loss);
  ASSERT_TRUE(reports.back().validation_iou);
  // The untrained network calls next to nothing road; trained, most of the held-apart road.
  EXPECT_LT(before.value_or(0), 0.5);
  EXPECT_GT(*reports.back().validation_iou, before.value_or(0) + 0.2);
  EXPECT_NEAR(*segmentationIou(model, held), *reports.back().validation_iou, 0.05);  // the same figure, at full size
  EXPECT_EQ(model.training().training_images, 6);
  EXPECT_EQ(model.training().validation_images, 2);
}

// With the augmentation's defaults (grey, contrast, blur, noise, zoom drawn from the seed) too.
TEST(SegmentationTraining, SameSeedSameBytesOtherSeedOtherBytes) {
  ASSERT_TRUE(realDataPresent("camvid_train"));
  const std::vector<TrainingPhoto> photos = camvid("camvid_train", 0, 4);
  SegmentationTrainOptions o = quick();
  o.epochs = 2;
  const std::string a = trainSegmentation(photos, o).bytes(), b = trainSegmentation(photos, o).bytes();
  EXPECT_TRUE(a == b);
  o.seed = 2;
  EXPECT_FALSE(trainSegmentation(photos, o).bytes() == a);
}

TEST(SegmentationModelFile, RoundTripsByteForByteAndAnswersTheSame) {
  SegmentationModel m(32, 24, 7);
  SegmentationTraining t;
  t.command = "test";
  t.seed = 7;
  t.epochs = 1;
  t.validation_iou = 0.5;
  m.setTraining(t);
  const fs::path file = freshTempDir() / "m.mnseg";
  m.save(file);
  const SegmentationModel back = SegmentationModel::load(file);
  EXPECT_TRUE(back.bytes() == m.bytes());
  EXPECT_EQ(back.training().command, "test");
  EXPECT_DOUBLE_EQ(back.training().validation_iou, 0.5);
  Image rgb(40, 30, 3);
  for (std::size_t i = 0; i < rgb.data.size(); ++i) rgb.data[i] = static_cast<std::uint8_t>(i * 37);
  EXPECT_EQ(m.roadProbability(rgb.data.data(), 40, 30, nullptr), back.roadProbability(rgb.data.data(), 40, 30, nullptr));
}

TEST(SegmentationModelFile, BadFilesNamedWithWhatIsWrong) {
  const fs::path dir = freshTempDir();
  const std::string good = SegmentationModel(16, 16, 1).bytes();
  const auto write = [&](const std::string& name, const std::string& bytes) {
    std::ofstream(dir / name, std::ios::binary) << bytes;
    return dir / name;
  };
  const auto expectError = [&](const fs::path& file, const std::string& words) {
    try {
      SegmentationModel::load(file);
      ADD_FAILURE() << file << " loaded";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  EXPECT_THROW(SegmentationModel::load(dir / "missing.mnseg"), IoError);
  expectError(write("png.mnseg", "\x89PNG\r\n"), "not a mapnav segmentation model");
  expectError(write("truncated.mnseg", good.substr(0, good.size() - 10)), "truncated");
  expectError(write("long.mnseg", good + "xx"), "2 bytes after the last weight");
  const std::size_t header = good.find('\n') + 1;
  expectError(write("json.mnseg", good.substr(0, header) + "{not json\n"), "JSON header");
  std::string shape = good;
  const std::size_t at = shape.find("[16,4,3,3]");
  ASSERT_NE(at, std::string::npos);
  shape.replace(at, 10, "[16,3,3,3]");
  expectError(write("shape.mnseg", shape), "/parameters/0/shape");
  std::string nan = good;
  const float q = std::numeric_limits<float>::quiet_NaN();
  nan.replace(nan.size() - 4, 4, std::string(reinterpret_cast<const char*>(&q), 4));
  expectError(write("nan.mnseg", nan), "not finite");
}

/// The committed model's road IoU on camvid's first five photos, measured when it was trained.
constexpr double kCamvidFirstFiveIou = 0.9553;

TEST(LearnedPipeline, CommittedModelKeepsItsFigureOnFiveCamvidPhotos) {
  ASSERT_TRUE(realDataPresent("camvid"));
  const SegmentationModel model = SegmentationModel::load(resolveSegmentationModel("camvid"));
  // Measured with the committed model when it was trained (scripts/train-models); photos never trained on.
  EXPECT_NEAR(segmentationIou(model, camvid("camvid", 0, 5)).value_or(0), kCamvidFirstFiveIou, 0.003);
}

TEST(LearnedPipeline, RegisteredWithOptionsAndFindsTheRoadOfAPhoto) {
  ASSERT_TRUE(realDataPresent("camvid"));
  registerLearnedPipeline();
  EXPECT_NO_THROW(LearnedPipelineOptions{}.validate());
  try {
    createPipeline("learned", R"({"model": "/no/such.mnseg"})");
    FAIL();
  } catch (const NotFound& e) {
    EXPECT_NE(std::string(e.what()).find("/no/such.mnseg"), std::string::npos) << e.what();
  }
  EXPECT_THROW(createPipeline("learned", R"({"threshold": 2})"), InvalidInput);
  const TrainingPhoto photo = camvid("camvid", 0, 1).front();
  const int w = photo.rgb.width, h = photo.rgb.height;
  const std::unique_ptr<Camera> camera = assumedPhotoCamera(w, h);
  const Image ground = groundMask(*camera);
  for (std::size_t i = 0; i < ground.data.size(); ++i)
    ASSERT_EQ(ground.data[i] != 0, photo.ground.data[i] != 0) << "pixel " << i;
  auto pipeline = createPipeline("learned", "{}");
  VisionFrame frame{w, h, photo.rgb.data.data(), camera.get(), 0.0};
  frame.want_masks = true;
  const DetectedObject d = pipeline->detect(frame, predictionFromImageRegion(bottomTrapezoid(w, h), *camera).view);
  ASSERT_EQ(d.status, DetectedObject::Status::Ok) << d.reason;
  ASSERT_FALSE(d.road_confidence.empty());
  EXPECT_FALSE(d.lines.empty());
  Image label(w, h, 1);
  for (std::size_t i = 0; i < label.data.size(); ++i) label.data[i] = photo.road.data[i];
  LabelClasses classes;
  classes.road = {1};
  classes.ignore = {255};
  // The region steps smooth and fill the model's answer; they keep its score on the photo.
  const double alone = segmentationIou(SegmentationModel::load(resolveSegmentationModel("camvid")), {photo}).value_or(0);
  const double iou = countPixels(d.road_mask, label, classes).iou().value_or(0);
  EXPECT_GT(alone, 0.9);
  EXPECT_GT(iou, alone - 0.03);
}

/// A photo's labels as SegmentationModel::adapt takes them: 1 road, 0 not, 2 left out (unlabelled
/// or above the ground).
std::vector<std::uint8_t> adaptLabels(const TrainingPhoto& photo) {
  std::vector<std::uint8_t> labels(photo.road.data.size());
  for (std::size_t i = 0; i < labels.size(); ++i)
    labels[i] = photo.ground.data[i] == 0 || photo.road.data[i] == 255 ? 2 : photo.road.data[i];
  return labels;
}

/// The committed camvid model and camvid's first photo, the model's file bytes as loaded.
class SegmentationModelAdapt : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(realDataPresent("camvid")); }
  SegmentationModel model = SegmentationModel::load(resolveSegmentationModel("camvid"));
  const std::string loaded = model.bytes();
  const TrainingPhoto photo = camvid("camvid", 0, 1).front();
  const int w = photo.rgb.width, h = photo.rgb.height;
  const std::uint8_t *rgb = photo.rgb.data.data(), *ground = photo.ground.data.data();
};

TEST_F(SegmentationModelAdapt, StepsLowerTheLossAndResetGivesTheLoadedModelBack) {
  const std::vector<std::uint8_t> labels = adaptLabels(photo);
  const std::vector<float> before = model.roadProbability(rgb, w, h, ground);
  // Gradient descent on one frame's loss: each step's loss (measured before it) below the last.
  std::vector<double> losses;
  for (int k = 0; k < 4; ++k) losses.push_back(model.adapt(rgb, w, h, ground, labels.data(), 0.05, 2));
  EXPECT_GT(losses.front(), 0);
  for (std::size_t k = 1; k < losses.size(); ++k) EXPECT_LT(losses[k], losses[k - 1]) << "step " << k;
  EXPECT_NE(model.roadProbability(rgb, w, h, ground), before);
  EXPECT_NE(model.bytes(), loaded);
  model.resetAdaptation();
  EXPECT_EQ(model.roadProbability(rgb, w, h, ground), before);
  EXPECT_EQ(model.bytes(), loaded);
  // Adapting again starts from the loaded weights: the first step's loss is the first loss again.
  EXPECT_DOUBLE_EQ(model.adapt(rgb, w, h, ground, labels.data(), 0.05, 2), losses.front());
}

TEST_F(SegmentationModelAdapt, NothingLabelledIsNoStepAndBadArgumentsAreNamed) {
  const std::vector<std::uint8_t> none(photo.road.data.size(), 2);
  EXPECT_EQ(model.adapt(rgb, w, h, ground, none.data(), 0.05, 2), -1);
  EXPECT_EQ(model.bytes(), loaded);
  const std::vector<std::uint8_t> labels = adaptLabels(photo);
  for (int layers : {0, 12}) {
    try {
      model.adapt(rgb, w, h, ground, labels.data(), 0.05, layers);
      FAIL() << layers;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("layers " + std::to_string(layers) + ": must be 1..11"), std::string::npos)
          << e.what();
    }
  }
  EXPECT_THROW(model.adapt(rgb, w, h, ground, labels.data(), std::nan(""), 2), InvalidInput);
  EXPECT_THROW(model.adapt(rgb, 0, h, ground, labels.data(), 0.05, 2), InvalidInput);
  EXPECT_EQ(model.bytes(), loaded);
}

TEST(LearnedPipeline, AdaptsFromThePredictionAndGoesBackToTheLoadedModelOnResetOrARunaway) {
  ASSERT_TRUE(realDataPresent("camvid"));
  registerLearnedPipeline();
  const TrainingPhoto photo = camvid("camvid", 0, 1).front();
  const int w = photo.rgb.width, h = photo.rgb.height;
  const std::unique_ptr<Camera> camera = assumedPhotoCamera(w, h);
  const Prediction trapezoid = predictionFromImageRegion(bottomTrapezoid(w, h), *camera);
  auto confidence = [&](VisionPipeline& p, const Image& rgb, const Prediction& prediction) {
    VisionFrame frame{w, h, rgb.data.data(), camera.get(), 0.0};
    frame.want_masks = true;
    const DetectedObject d = p.detect(frame, prediction.view);
    return d.road_confidence.data;
  };
  auto frozen = createPipeline("learned", "{}");
  const std::vector<std::uint8_t> first = confidence(*frozen, photo.rgb, trapezoid);
  ASSERT_FALSE(first.empty());
  EXPECT_EQ(confidence(*frozen, photo.rgb, trapezoid), first);  // frozen: the same answer every time

  auto adaptive = createPipeline("learned", R"({"adapt": true, "adapt_rate": 0.05})");
  EXPECT_EQ(confidence(*adaptive, photo.rgb, trapezoid), first);  // it learns after answering
  const std::vector<std::uint8_t> second = confidence(*adaptive, photo.rgb, trapezoid);
  EXPECT_NE(second, first);
  adaptive->reset();
  EXPECT_EQ(confidence(*adaptive, photo.rgb, trapezoid), first);

  // A runaway: a predicted road the region does not hold (the grass verge on the left of this
  // photo) puts the loaded weights back, and no step is taken from it.
  confidence(*adaptive, photo.rgb, trapezoid);
  const Prediction verge = predictionFromImageRegion({{0, 215}, {45, 205}, {25, 275}, {0, 282}}, *camera);
  confidence(*adaptive, photo.rgb, verge);
  EXPECT_EQ(confidence(*adaptive, photo.rgb, trapezoid), first);
}

}  // namespace
}  // namespace mapnav
