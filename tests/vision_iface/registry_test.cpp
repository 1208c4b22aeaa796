#include "mapnav/vision_iface/pipeline.h"

#include <gtest/gtest.h>

#include "mapnav/core/error.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

TEST(Plugin, TheExamplePluginIsLoadedFromItsSharedLibraryAndFoundByName) {
  EXPECT_EQ(loadPlugin(MAPNAV_EXAMPLE_PLUGIN), 1);
  auto pipeline = createPipeline("example-lower-half");
  ASSERT_TRUE(pipeline);
  EXPECT_EQ(pipeline->name(), "example-lower-half");
  std::vector<std::uint8_t> pixels(4 * 6 * 3, 0);
  const DetectedObject d = pipeline->detect(VisionFrame{4, 6, pixels.data(), nullptr, 1.5}, PredictedObject{});
  EXPECT_EQ(d.status, DetectedObject::Status::Ok);
  ASSERT_EQ(d.region_image.size(), 4u);
  EXPECT_EQ(d.region_image[0], Vec2(-0.5, 3.0));  // the lower half of a 6-row image starts at v = 3
  bool listed = false;
  for (const PipelineInfo& info : listPipelines()) listed = listed || info.name == "example-lower-half";
  EXPECT_TRUE(listed);
}

TEST(Plugin, AFileThatIsNotAPluginIsANamedError) {
  EXPECT_THROW(loadPlugin("/no/such/libplugin.so"), IoError);
  // A real shared library without the entry point.
  try {
    loadPlugin("libm.so.6");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("mapnav_register_pipelines"), std::string::npos) << e.what();
  }
}

TEST(Registry, AnUnknownPipelineNamesTheOnesThereAre) {
  registerPipeline({"test-nothing", "does nothing", {}, [] { return std::unique_ptr<VisionPipeline>(); }});
  try {
    createPipeline("no-such-pipeline");
    FAIL();
  } catch (const NotFound& e) {
    EXPECT_NE(std::string(e.what()).find("test-nothing"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mapnav
