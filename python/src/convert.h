#pragma once
// What the binding files share: numpy arrays to and from the library's types (checked, and without
// copies where the library allows), poses, JSON as Python objects, and the Python Prediction.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>  // in every file: the casters must agree across them

#include <memory>
#include <string>
#include <vector>

#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/types.h"
#include "mapnav/image/image.h"
#include "mapnav/map/map.h"
#include "mapnav/map/predict.h"

namespace mapnav::python {

namespace py = pybind11;

/// A predicted view with what keeps it meaningful: the camera it was predicted for (detect() needs
/// it) and the map its landmarks point into (none for a view made from an image region).
struct PyPrediction {
  Prediction prediction;
  std::shared_ptr<const Camera> camera;
  std::shared_ptr<const Map> map;
};

/// A camera frame handed in from Python, read in place: an H x W x 3 uint8 C-contiguous array.
/// Throws TypeError for another type or dtype, InvalidInput for another shape or a strided view;
/// the messages start with `what`.
struct RgbView {
  int width = 0, height = 0;
  const std::uint8_t* data = nullptr;
};
RgbView rgbView(const py::array& image, const std::string& what);

/// The image as a numpy array (H x W, or H x W x C), owning its pixels: no copy.
py::array toArray(Image image);
/// An H x W or H x W x 3 uint8 array copied into an Image (checked as rgbView).
Image toImage(const py::array& array, const std::string& what);

/// Points as an N x 2 float64 array, and back (N x 2, finite; InvalidInput naming `what`).
py::array toArray(const std::vector<Vec2>& points);
std::vector<Vec2> toPoints(const py::handle& points, const std::string& what);

/// A pose given as a road position "R1@I1+3" (on `map`) or as (x, y, heading in radians).
Pose2 toPose(const Map& map, const py::handle& pose);
py::tuple fromPose(const Pose2& pose);

/// JSON text as Python objects (json.loads), and an options argument (dict or JSON text) as text.
py::object fromJson(const std::string& text);
std::string optionsText(const py::object& options);

void bindErrors(py::module_& m);
void bindMap(py::module_& m);
void bindPredict(py::module_& m);
void bindVision(py::module_& m);
void bindMission(py::module_& m);
void bindSuite(py::module_& m);
void bindEval(py::module_& m);

}  // namespace mapnav::python
