// The library's evaluation (eval/segmentation_evaluation.h) on a hand-made labelled set of three
// 20 x 12 photos and a stub pipeline whose road is the photo's grey pixels: every count below is
// worked out by hand from the pictures drawn here.
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mapnav/core/error.h"
#include "mapnav/eval/labelled_photos.h"
#include "mapnav/eval/segmentation_evaluation.h"
#include "mapnav/image/png.h"
#include "mapnav/testing/support.h"
#include "mapnav/vision/resize.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;

constexpr int kW = 20, kH = 12;
const LabelClasses kClasses{{1}, {2}};  // 1 road, 2 ignored, 0 the rest

// Road where the photo is grey (128, 128, 128), with that as its confidence when `confidence`;
// fails on a photo without grey. Records how many grey pixels each frame it sees has, and how many
// regions its prediction.
class GreyIsRoad : public VisionPipeline {
 public:
  explicit GreyIsRoad(bool confidence) : confidence_(confidence) {}
  std::string name() const override { return "grey-is-road"; }
  void configure(const std::string&) override {}
  void reset() override {}
  DetectedObject detect(const VisionFrame& frame, const PredictedObject& prediction) override {
    regions_seen.push_back(prediction.regions.size());
    sizes_seen.push_back({frame.width, frame.height});
    Image mask(frame.width, frame.height, 1);
    int grey = 0;
    for (std::size_t i = 0; i < mask.data.size(); ++i) {
      const std::uint8_t* p = frame.rgb + 3 * i;
      if (p[0] == 128 && p[1] == 128 && p[2] == 128) mask.data[i] = 255, ++grey;
    }
    seen.push_back(grey);
    bool all_grey = true;
    for (std::size_t i = 0; i < mask.data.size(); ++i) {
      const std::uint8_t* p = frame.rgb + 3 * i;
      all_grey = all_grey && p[0] == p[1] && p[1] == p[2];
    }
    grey_frames += all_grey ? 1 : 0;
    if (grey == 0) return DetectedObject::failed("no road-coloured pixels");
    DetectedObject d;
    d.road_mask = mask;
    if (confidence_) d.road_confidence = mask;
    return d;
  }
  std::vector<int> seen;
  std::vector<std::size_t> regions_seen;
  std::vector<ImageSize> sizes_seen;
  int grey_frames = 0;  ///< frames whose every pixel has R = G = B

 private:
  bool confidence_;
};

struct Box {
  int v0, v1, u0, u1;  // rows v0..v1, columns u0..u1, inclusive
  bool has(int u, int v) const { return v >= v0 && v <= v1 && u >= u0 && u <= u1; }
};

// A photo: grey inside `road` (none: all black), green elsewhere.
Image photo(const std::optional<Box>& road) {
  Image out(kW, kH, 3);
  for (int v = 0; v < kH; ++v)
    for (int u = 0; u < kW; ++u) {
      const bool grey = road && road->has(u, v);
      const std::array<std::uint8_t, 3> rgb =
          !road ? std::array<std::uint8_t, 3>{0, 0, 0}
                : (grey ? std::array<std::uint8_t, 3>{128, 128, 128} : std::array<std::uint8_t, 3>{40, 140, 40});
      std::copy(rgb.begin(), rgb.end(), out.pixel(u, v));
    }
  return out;
}

// A label: 1 inside `road`, 2 inside `ignored`, 0 elsewhere.
Image label(const Box& road, const std::optional<Box>& ignored = std::nullopt) {
  Image out(kW, kH, 1);
  for (int v = 0; v < kH; ++v)
    for (int u = 0; u < kW; ++u) out.pixel(u, v)[0] = road.has(u, v) ? 1 : (ignored && ignored->has(u, v) ? 2 : 0);
  return out;
}

// The set, in a fresh folder (images/, labels/):
//   a: grey rows 8-11 x columns 4-15 (48 px); road rows 6-11 x columns 6-13 (48 px), ignored row 11
//      columns 4-5 (inside the grey);
//   b: grey rows 6-11, every column (120 px); road rows 7-11 x columns 2-17 (80 px);
//   c: all black (the stub fails); road rows 9-11 x columns 8-11 (12 px).
fs::path handMadeSet() {
  const fs::path dir = testing::freshTempDir();
  fs::create_directories(dir / "images");
  fs::create_directories(dir / "labels");
  writePng(photo(Box{8, 11, 4, 15}), dir / "images" / "a.png");
  writePng(label(Box{6, 11, 6, 13}, Box{11, 11, 4, 5}), dir / "labels" / "a.png");
  writePng(photo(Box{6, 11, 0, 19}), dir / "images" / "b.png");
  writePng(label(Box{7, 11, 2, 17}), dir / "labels" / "b.png");
  writePng(photo(std::nullopt), dir / "images" / "c.png");
  writePng(label(Box{9, 11, 8, 11}), dir / "labels" / "c.png");
  return dir;
}

// The bootstrap: a "trapezoid" that is a rectangle with its corners on pixel centres (rows 10-11,
// columns 7-13: 14 px), so that the pixels it holds are plain to count.
SegmentationEvalOptions rectangleBootstrap() {
  SegmentationEvalOptions o;
  o.trapezoid = TrapezoidOptions{.bottom_width = 0.3, .top_width = 0.3, .top = 10.0 / kH, .bottom = 11.0 / kH};
  return o;
}

void expectCounts(const PixelCounts& c, std::uint64_t tp, std::uint64_t fp, std::uint64_t fn) {
  EXPECT_EQ(c.tp, tp);
  EXPECT_EQ(c.fp, fp);
  EXPECT_EQ(c.fn, fn);
}

// The pipeline against the labels:
//   a: TP = rows 8-11 x columns 6-13 = 32; FP = 48 - 32 - 2 ignored = 14; FN = rows 6-7 x 6-13 = 16
//   b: TP 80, FP 40, FN 0;  c: failed, so no road: FN 12.
// Set: TP 112, FP 54, FN 28: IoU 112/194, precision 112/166, recall 112/140; per image 32/62, 2/3, 0.
// "Below the horizon": the assumed level camera has cy = 5.5, so rows 6-11 (120 px):
//   a: TP 48, FP 120 - 48 - 2 = 70;  b: TP 80, FP 40;  c: TP 12, FP 108.  Set: 140 / 358.
// The bootstrap rectangle, rows 10-11 x columns 7-13:
//   a: TP 14, FN 48 - 14 = 34;  b: TP 14, FN 66;  c: TP rows 10-11 x columns 8-11 = 8, FP 6, FN 4.
//   Set: TP 36, FP 6, FN 104: 36/146, below the horizon's.
TEST(SegmentationEvaluation, AHandMadeSetScoresAsCountedByHand) {
  const fs::path dir = handMadeSet();
  GreyIsRoad pipeline(false);
  const SegmentationEvaluation e =
      evaluateSegmentation(pipeline, dir / "images", dir / "labels", kClasses, rectangleBootstrap());
  EXPECT_EQ(pipeline.seen, (std::vector<int>{48, 120, 0}));  // a, b, c: in file-name order
  EXPECT_EQ(pipeline.regions_seen, (std::vector<std::size_t>{1, 1, 1}));  // the trapezoid, one road
  EXPECT_EQ(e.pipeline, "grey-is-road");
  EXPECT_EQ(e.bootstrap, EvalBootstrap::Trapezoid);
  EXPECT_FALSE(e.bev.has_value());
  ASSERT_EQ(e.photos.size(), 3u);
  EXPECT_EQ(e.photos[0].image, "a.png");
  expectCounts(e.photos[0].counts, 32, 14, 16);
  expectCounts(e.photos[1].counts, 80, 40, 0);
  expectCounts(e.photos[2].counts, 0, 0, 12);
  EXPECT_EQ(e.photos[0].failure, "");
  EXPECT_EQ(e.photos[2].failure, "no road-coloured pixels");
  EXPECT_EQ(e.failed, 1);
  EXPECT_EQ(e.scores.images, 3);
  EXPECT_DOUBLE_EQ(*e.scores.iou, 112.0 / 194.0);
  EXPECT_DOUBLE_EQ(*e.scores.precision, 112.0 / 166.0);
  EXPECT_DOUBLE_EQ(*e.scores.recall, 112.0 / 140.0);
  EXPECT_DOUBLE_EQ(*e.scores.iou_median, 32.0 / 62.0);
  EXPECT_DOUBLE_EQ(*e.scores.iou_worst, 0.0);
  EXPECT_FALSE(e.confidence_given);
  EXPECT_FALSE(e.scores.maxf.has_value());
  EXPECT_FALSE(e.scores.ap.has_value());
  expectCounts(e.baseline_horizon.total, 140, 218, 0);
  EXPECT_DOUBLE_EQ(*e.baseline_horizon.iou, 140.0 / 358.0);
  expectCounts(e.baseline_bootstrap.total, 36, 6, 104);
  EXPECT_DOUBLE_EQ(*e.baseline_bootstrap.iou, 36.0 / 146.0);
  EXPECT_DOUBLE_EQ(*e.margin, 112.0 / 194.0 - 140.0 / 358.0);  // 0.5773 - 0.3911: the horizon is the better
}

// resize_width / resize_height: the photos and their labels at twice their size before anything
// runs. The pipeline sees 40 x 24 frames; the labels, doubled by their nearest pixel, hold four times
// the road pixels (TP + FN: 192, 320, 48); "below the horizon" (rows 12-23 of the assumed camera at
// 40 x 24) counts exactly four times its 20 x 12 figures: TP 560, FP 872 (the ignored pixels too).
TEST(SegmentationEvaluation, PhotosAndLabelsAreScoredAtTheAskedSize) {
  const fs::path dir = handMadeSet();
  GreyIsRoad pipeline(false);
  SegmentationEvalOptions options = rectangleBootstrap();
  options.resize_width = 2 * kW;
  options.resize_height = 2 * kH;
  const SegmentationEvaluation e = evaluateSegmentation(pipeline, dir / "images", dir / "labels", kClasses, options);
  EXPECT_EQ(pipeline.sizes_seen, (std::vector<ImageSize>(3, ImageSize{2 * kW, 2 * kH})));
  ASSERT_EQ(e.photos.size(), 3u);
  EXPECT_EQ(e.photos[0].counts.tp + e.photos[0].counts.fn, 192u);
  EXPECT_EQ(e.photos[1].counts.tp + e.photos[1].counts.fn, 320u);
  expectCounts(e.photos[2].counts, 0, 0, 48);
  expectCounts(e.baseline_horizon.total, 560, 872, 0);
  // A size needs both.
  options.resize_height = 0;
  try {
    options.validate();
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& error) {
    EXPECT_STREQ(error.what(),
                 "SegmentationEvalOptions::resize_height = 0: must be 0 exactly when resize_width is 0 (a size needs both)");
  }
}

// grey: the pipeline sees every photo as a grey camera gives it (the hand-made photos' grass,
// (40, 140, 40), becomes luminance 99 in every channel; the road's 128 grey stays), so the same
// road pixels are found; without it, none of the coloured photos is grey.
TEST(SegmentationEvaluation, GreyPhotosAreWhatAGreyCameraGives) {
  const fs::path dir = handMadeSet();
  GreyIsRoad colour(false), grey(false);
  SegmentationEvalOptions options = rectangleBootstrap();
  evaluateSegmentation(colour, dir / "images", dir / "labels", kClasses, options);
  EXPECT_EQ(colour.grey_frames, 1);  // c.png: black
  options.grey = true;
  const SegmentationEvaluation e = evaluateSegmentation(grey, dir / "images", dir / "labels", kClasses, options);
  EXPECT_EQ(grey.grey_frames, 3);
  EXPECT_EQ(grey.seen, (std::vector<int>{48, 120, 0}));
  ASSERT_EQ(e.photos.size(), 3u);
  Image rgb(2, 1, 3);
  rgb.data = {40, 140, 40, 10, 20, 30};
  EXPECT_EQ(greyed(rgb).data, (std::vector<std::uint8_t>{99, 99, 99, 18, 18, 18}));  // 98.7, 18.15 rounded
  EXPECT_THROW(greyed(Image(2, 1, 1)), InvalidInput);
}

// With the mask as its confidence (255 on its road, a failed photo 0 everywhere), every threshold
// predicts the same pixels: MaxF is the set's F1, 2 TP / (2 TP + FP + FN) = 224/306, and AP is that
// precision at the recall levels 0, 0.1, ..., 0.8 it reaches (recall 0.8), 0 at 0.9 and 1: 9/11 of 112/166.
TEST(SegmentationEvaluation, APerPixelConfidenceGivesMaxFAndAp) {
  const fs::path dir = handMadeSet();
  GreyIsRoad pipeline(true);
  const SegmentationEvaluation e = evaluateSegmentation(pipeline, dir / "images", dir / "labels", kClasses);
  EXPECT_TRUE(e.confidence_given);
  EXPECT_DOUBLE_EQ(*e.scores.maxf, 224.0 / 306.0);
  EXPECT_DOUBLE_EQ(*e.scores.ap, 9.0 / 11.0 * 112.0 / 166.0);
}

// The first photo's labelled road (rows 6-11 x columns 6-13, 48 px) as the bootstrap, its outline
// through the pixel centres on its border, which the region holds:
//   a: TP 48;  b: TP rows 7-11 x 6-13 = 40, FP 8, FN 40;  c: TP 12, FP 36.  Set: TP 100, FP 44, FN 40.
TEST(SegmentationEvaluation, TheFirstLabelsRoadAsTheBootstrap) {
  const fs::path dir = handMadeSet();
  GreyIsRoad pipeline(false);
  SegmentationEvalOptions options;
  options.bootstrap = EvalBootstrap::LabelsFirstFrame;
  const SegmentationEvaluation e = evaluateSegmentation(pipeline, dir / "images", dir / "labels", kClasses, options);
  expectCounts(e.baseline_bootstrap.total, 100, 44, 40);
  EXPECT_DOUBLE_EQ(*e.margin, 112.0 / 194.0 - 100.0 / 184.0);  // the first label's region is the better baseline
  // A first label without road gives nothing to bootstrap from.
  writePng(label(Box{0, -1, 0, -1}), dir / "labels" / "a.png");
  try {
    evaluateSegmentation(pipeline, dir / "images", dir / "labels", kClasses, options);
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "labels" / "a.png").string() + ": no road labelled to bootstrap from");
  }
}

// The JSON `mapnav eval segmentation --json` prints: figures to 4 decimals, null where undefined.
TEST(SegmentationEvaluation, TheJsonRoundsToFourDecimals) {
  const fs::path dir = handMadeSet();
  GreyIsRoad pipeline(false);
  const auto j = nlohmann::json::parse(
      evaluationJson(evaluateSegmentation(pipeline, dir / "images", dir / "labels", kClasses, rectangleBootstrap())));
  EXPECT_EQ(j["pipeline"], "grey-is-road");
  EXPECT_EQ(j["bootstrap"], "trapezoid");
  EXPECT_EQ(j["space"], "image");
  EXPECT_TRUE(j["bev"].is_null());
  EXPECT_EQ(j["images"], 3);
  EXPECT_EQ(j["failed"], 1);
  EXPECT_DOUBLE_EQ(j["iou"].get<double>(), 0.5773);                     // 112/194 = 0.57732
  EXPECT_DOUBLE_EQ(j["iou_median"].get<double>(), 0.5161);              // 32/62 = 0.516129
  EXPECT_DOUBLE_EQ(j["precision"].get<double>(), 0.6747);               // 112/166 = 0.674699
  EXPECT_DOUBLE_EQ(j["recall"].get<double>(), 0.8);
  EXPECT_TRUE(j["maxf"].is_null());
  EXPECT_DOUBLE_EQ(j["baseline_horizon_iou"].get<double>(), 0.3911);    // 140/358 = 0.391061
  EXPECT_DOUBLE_EQ(j["baseline_bootstrap_iou"].get<double>(), 0.2466);  // 36/146 = 0.246575
  EXPECT_DOUBLE_EQ(j["margin"].get<double>(), 0.1863);                  // 0.186259
  ASSERT_EQ(j["per_image"].size(), 3u);
  EXPECT_EQ(j["per_image"][1], nlohmann::json::parse(R"({"image": "b.png", "iou": 0.6667, "failed": null})"));
  EXPECT_EQ(j["per_image"][2]["failed"], "no road-coloured pixels");
}

TEST(SegmentationEvaluation, OverlaysOnePerPhotoOnlyOnceEveryPhotoIsScored) {
  const fs::path dir = handMadeSet();
  GreyIsRoad pipeline(false);
  SegmentationEvalOptions options;
  options.overlays = (dir / "overlays").string();
  evaluateSegmentation(pipeline, dir / "images", dir / "labels", kClasses, options);
  // Photo a's pixel (8, 10) is grey and road: green blended half and half, (128 + 0, 128 + 220, 128 + 0) / 2.
  const Image a = readPng(dir / "overlays" / "a.png");
  EXPECT_EQ((std::vector<int>{a.pixel(8, 10)[0], a.pixel(8, 10)[1], a.pixel(8, 10)[2]}), (std::vector<int>{64, 174, 64}));
  EXPECT_TRUE(fs::exists(dir / "overlays" / "c.png"));
  // A photo without its label: nothing scored, nothing written.
  fs::remove_all(dir / "overlays");
  fs::remove(dir / "labels" / "b.png");
  EXPECT_THROW(evaluateSegmentation(pipeline, dir / "images", dir / "labels", kClasses, options), InvalidInput);
  EXPECT_FALSE(fs::exists(dir / "overlays"));
}

TEST(SegmentationEvaluation, BadInputNamesTheFileOrTheOption) {
  const fs::path dir = handMadeSet();
  const auto message = [](auto&& f) -> std::string {
    try {
      f();
    } catch (const Error& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(message([&] { readLabelledPhotos(dir / "nope", dir / "labels", true); }),
            (dir / "nope").string() + ": no such folder (the images)");
  EXPECT_THROW(readLabelledPhotos(dir / "nope", dir / "labels", true), IoError);
  writePng(Image(kW, 4, 1), dir / "labels" / "b.png");
  EXPECT_EQ(message([&] { readLabelledPhotos(dir / "images", dir / "labels", true); }),
            (dir / "labels" / "b.png").string() + ": the label is 20x4 but its image is 20x12");
  fs::remove(dir / "labels" / "b.png");
  EXPECT_EQ(message([&] { readLabelledPhotos(dir / "images", dir / "labels", true); }),
            (dir / "images" / "b.png").string() + ": no label " + (dir / "labels" / "b.png").string() +
                " (labels are matched by file stem)");
  // The options' own rules, in the table's words.
  SegmentationEvalOptions options;
  options.bev = true;
  EXPECT_EQ(message([&] { options.validate(); }),
            "SegmentationEvalOptions::bev = true: must be false without a camera (the grid is in metres on the ground "
            "the camera sees)");
  EXPECT_EQ(message([] { evalBootstrapFromString("middle"); }),
            "bootstrap \"middle\": expected trapezoid or labels-first-frame");
}

// The table reads the options as JSON, the trapezoid's and the grid's under their prefixed names.
TEST(SegmentationEvaluation, TheOptionsTableNamesTheComponentsFieldsWithTheirPrefix) {
  EXPECT_NO_THROW(SegmentationEvalOptions{}.validate());
  const SegmentationEvalOptions o = segmentationEvalOptionTable().parse(
      R"({"bootstrap": "labels-first-frame", "trapezoid_top": 0.6, "bev_cell_m": 0.1, "camera": "c.json", "bev": true})",
      {}, "test");
  EXPECT_EQ(o.bootstrap, EvalBootstrap::LabelsFirstFrame);
  EXPECT_DOUBLE_EQ(o.trapezoid.top, 0.6);
  EXPECT_DOUBLE_EQ(o.bev_grid.cell_m, 0.1);
  EXPECT_TRUE(o.bev);
  EXPECT_THROW(segmentationEvalOptionTable().parse(R"({"trapezoid_top": 0.99})", {}, "test"), InvalidInput);
  EXPECT_THROW(segmentationEvalOptionTable().parse(R"({"bev_x_max_m": -20})", {}, "test"), InvalidInput);
}

}  // namespace
}  // namespace mapnav
