// An example mapnav vision plug-in, built outside the library: it registers one pipeline,
// "example-lower-half", which calls the lower half of the image road. Build it against an installed
// mapnav (see CMakeLists.txt beside this file) and load it with `mapnav pipelines --plugin
// ./libmapnav_example_plugin.so`.
#include <string>

#include "mapnav/vision_iface/pipeline.h"

namespace {

class LowerHalf : public mapnav::VisionPipeline {
 public:
  std::string name() const override { return "example-lower-half"; }
  void configure(const std::string&) override {}
  mapnav::DetectedObject detect(const mapnav::VisionFrame& frame, const mapnav::PredictedObject&) override {
    if (frame.width <= 0 || frame.height <= 0) return mapnav::DetectedObject::failed("empty frame");
    mapnav::DetectedObject d;
    d.timestamp = frame.timestamp;
    d.confidence = 0.5;
    const double w = frame.width - 0.5, h = frame.height - 0.5, mid = frame.height / 2.0;
    d.region_image = {{-0.5, mid}, {w, mid}, {w, h}, {-0.5, h}};
    return d;
  }
  void reset() override {}
};

}  // namespace

extern "C" int mapnav_register_pipelines() {
  mapnav::registerPipeline({"example-lower-half", "Example plug-in: the lower half of the image is road",
                            {}, [] { return std::make_unique<LowerHalf>(); }});
  return 1;
}
