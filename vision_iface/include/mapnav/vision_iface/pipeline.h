#pragma once
// The Vision module behind an interface (OpenCV's Algorithm + create...() style): a pipeline is
// configured from JSON options, then turns a camera frame and the Map's prediction into a
// DetectedObject. Pipelines register by name; more come from shared-library plug-ins.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "mapnav/core/option_info.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/tokens/detected_object.h"
#include "mapnav/tokens/predicted_object.h"

namespace mapnav {

/// A camera frame as Vision sees it: 8-bit RGB, row-major, no padding, and the camera that took it.
struct VisionFrame {
  int width = 0, height = 0;
  const std::uint8_t* rgb = nullptr;  ///< width × height × 3 bytes, owned by the caller
  const Camera* camera = nullptr;     ///< for ground-plane coordinates
  double timestamp = 0;
  /// The caller reads the detection's road region (region_image, region_vehicle); when false a
  /// pipeline may leave them empty and save the work (the mission loop when it writes no trace).
  bool want_region = true;
  /// The caller reads the detection's per-pixel road_mask and road_confidence (`mapnav eval`, `mapnav
  /// log track`); a pipeline that can give them then does.
  bool want_masks = false;
};

/// The frame area the pipelines' defaults in pixels were chosen at: 480 × 360 (CamVid's photos; the
/// simulator's 512 × 480 frames are larger).
inline constexpr double kReferenceFramePixels = 480.0 * 360.0;

/// How a pipeline's lengths in pixels scale with the frame: sqrt(width × height /
/// kReferenceFramePixels) on a smaller frame, 1 on one as large or larger. A length in pixels (a
/// block's side, a filter's radius, a tolerance) is multiplied by it and a count of pixels by its
/// square, so that on a small camera's frame every threshold keeps its share of the picture; on a
/// larger frame they stay (what is found is then at least as many pixels across as at the
/// reference). 1 for a frame without pixels.
double pixelScale(int width, int height);

class VisionPipeline {
 public:
  virtual ~VisionPipeline() = default;
  /// The registered name ("color-classifier", "blue-band", ...).
  virtual std::string name() const = 0;
  /// Sets options from a JSON object (members absent keep their defaults). Throws InvalidInput
  /// naming the option and its bad value.
  virtual void configure(const std::string& options_json) = 0;
  /// The frame and the prediction for it → what was found. Never throws for bad image content:
  /// an unusable frame is a DetectedObject with status Failed and a reason.
  virtual DetectedObject detect(const VisionFrame& frame, const PredictedObject& prediction) = 0;
  /// Forgets what was learnt from earlier frames (adaptive colour models).
  virtual void reset() = 0;
};

struct PipelineInfo {
  std::string name;
  std::string description;
  std::vector<OptionInfo> options;
  std::function<std::unique_ptr<VisionPipeline>()> create;
  /// Named option sets, chosen with `"preset": "NAME"` in the options (listed by `mapnav pipelines`).
  std::vector<OptionPreset> presets = {};
};

/// Adds a pipeline to the registry (replacing one of the same name).
void registerPipeline(PipelineInfo info);
/// Everything registered, built-in pipelines first, sorted by name within each origin.
std::vector<PipelineInfo> listPipelines();
/// A new pipeline by name, configured with `options_json`. Throws NotFound listing the names.
std::unique_ptr<VisionPipeline> createPipeline(const std::string& name, const std::string& options_json = "{}");
/// Finds the landmarks a prediction lists in a frame: one DetectedLandmark per
/// PredictedObject::landmarks entry, in its order. The Vision module runs it after the pipeline,
/// unless the pipeline reported landmarks itself.
using LandmarkFinder = std::function<std::vector<DetectedLandmark>(const VisionFrame&, const PredictedObject&)>;
/// Sets the landmark finder (registerBuiltinPipelines sets the built-in one; a plug-in may replace it).
void registerLandmarkFinder(LandmarkFinder finder);
/// The landmark finder registered; empty when none is (landmarks are then not looked for).
LandmarkFinder landmarkFinder();
/// Measures the vehicle's step from the previous frame to the current one against the ground,
/// starting from the Map's predicted motion (DetectedObject::step). The Vision module
/// runs it on every frame after the first, whatever the pipeline.
using StepMeasurer =
    std::function<MeasuredStep(const VisionFrame& previous, const VisionFrame& current, const MotionIncrement& predicted)>;
/// Sets the step measurer (registerBuiltinPipelines sets the built-in one; a plug-in may replace it).
void registerStepMeasurer(StepMeasurer measurer);
/// The step measurer registered; empty when none is (the step is then not measured).
StepMeasurer stepMeasurer();

/// Loads a plug-in: a shared library exporting `extern "C" int mapnav_register_pipelines(void)`
/// (see examples/); returns how many pipelines it registered. Throws IoError / InvalidInput naming
/// the file.
int loadPlugin(const std::string& path);

}  // namespace mapnav
