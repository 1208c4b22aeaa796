// The rendered road mask against an independent, forward construction: the paved regions that
// predictView clips to the camera's footprint (geometry/clip.h), projected into the image
// by the camera model and filled exactly (a pixel is road when its centre is inside a projected
// region: an even-odd scanline fill; an anti-aliased picture rasteriser would spread a pixel past
// every edge). Compared inside the footprint, where both methods claim to know the answer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "mapnav/geometry/polygon.h"
#include "mapnav/map/predict.h"
#include "mapnav/sim/world.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

std::unique_ptr<Camera> camera(LensModel model) {
  CameraIntrinsics in;
  in.width = in.height = 512;
  in.cx = in.cy = 255.5;
  CameraMount mount;
  mount.height_m = 1.5;
  if (model == LensModel::Pinhole) {
    in.fx = in.fy = 600;
    mount.tilt_rad = degToRad(22);
  } else {
    in.fx = in.fy = 257;
    mount.tilt_rad = degToRad(20);
  }
  return createCamera(model, in, mount);
}

// Marks the pixels whose centres (integer coordinates) lie inside `polygon` (pixel coordinates).
void fillCentres(const std::vector<Vec2>& polygon, int width, int height, std::vector<std::uint8_t>& out) {
  const std::size_t n = polygon.size();
  for (int v = 0; v < height; ++v) {
    std::vector<double> xs;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 &a = polygon[i], &b = polygon[(i + 1) % n];
      if ((a.y() <= v) != (b.y() <= v)) xs.push_back(a.x() + (v - a.y()) * (b.x() - a.x()) / (b.y() - a.y()));
    }
    std::sort(xs.begin(), xs.end());
    for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
      for (int u = std::max(0, static_cast<int>(std::ceil(xs[k]))); u < width && u < xs[k + 1]; ++u) {
        out[static_cast<std::size_t>(v) * width + u] = 1;
      }
    }
  }
}

double forwardIoU(const Map& map, const World& world, const Camera& cam, const Pose2& pose) {
  PredictOptions options;
  options.near_m = 1.0;
  options.far_m = 15.0;  // the predicted view's default range
  const Prediction p = predictView(map, pose, cam, options);
  std::vector<std::uint8_t> forward(static_cast<std::size_t>(cam.width()) * cam.height(), 0);
  for (const PredictedRegion& region : p.view.regions) {
    for (const Polygon2& ring : region.vehicle) {
      std::vector<Vec2> pixels;
      for (std::size_t i = 0; i < ring.size(); ++i) {
        const Vec2 a = ring[i], b = ring[(i + 1) % ring.size()];
        const int steps = std::max(1, static_cast<int>((b - a).norm() / 0.02));
        for (int k = 0; k < steps; ++k) {
          if (const auto px = cam.projectGround(a + (b - a) * (k / double(steps)))) pixels.push_back(*px);
        }
      }
      fillCentres(pixels, cam.width(), cam.height(), forward);
    }
  }
  const Frame frame = world.render(cam, pose, 0.0);
  std::size_t both = 0, either = 0;
  for (int v = 0; v < cam.height(); ++v) {
    for (int u = 0; u < cam.width(); ++u) {
      const auto ground = cam.backproject(Vec2(u, v));
      if (!ground || !contains(p.view.footprint, *ground)) continue;  // outside what the prediction covers
      const bool a = forward[static_cast<std::size_t>(v) * cam.width() + u] != 0, b = frame.mask.pixel(u, v)[0] == 255;
      both += a && b;
      either += a || b;
    }
  }
  return either == 0 ? 1.0 : static_cast<double>(both) / static_cast<double>(either);
}

TEST(RenderedMask, AgreesWithTheForwardProjectionOfTheRoadPolygons) {
  const Map& map = testing::campusMap();
  const World world(map);
  for (const LensModel model : {LensModel::Pinhole, LensModel::PaperFisheye}) {
    const auto cam = camera(model);
    for (const Pose2& pose : {Pose2(53, 40, 0), Pose2(50.4, 55, kPi / 2), Pose2(91, 79, 0.3)}) {
      const double iou = forwardIoU(map, world, *cam, pose);
      std::printf("IoU %s %.5f\n", std::string(toString(model)).c_str(), iou);
      EXPECT_GE(iou, 0.99) << toString(model) << " at (" << pose.x() << ", " << pose.y() << ")";
      RecordProperty(std::string(toString(model)) + "_" + std::to_string(static_cast<int>(pose.x())), std::to_string(iou));
    }
  }
}

}  // namespace
}  // namespace mapnav
