#include "convert.h"

#include <cmath>
#include <cstring>

#include "mapnav/core/error.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/navigator/road_position.h"

namespace mapnav::python {

namespace {

std::string shapeText(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) text += (i > 0 ? ", " : "") + std::to_string(a.shape(i));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

// Throws unless `a` is a C-contiguous uint8 array of `ndim_min`..3 dimensions (the third, when
// there, of `channels_max` or fewer).
void checkUint8(const py::array& a, const std::string& what, const char* expected, bool grey_allowed) {
  if (!py::isinstance<py::array_t<std::uint8_t>>(a)) {
    throw py::type_error(what + ": expected a numpy array of dtype uint8, got dtype " + py::str(a.dtype()).cast<std::string>());
  }
  const bool rgb = a.ndim() == 3 && a.shape(2) == 3;
  if (!(rgb || (grey_allowed && a.ndim() == 2)) || a.shape(0) <= 0 || a.shape(1) <= 0) {
    throw InvalidInput(what + ": expected shape " + expected + ", got " + shapeText(a));
  }
  if ((a.flags() & py::array::c_style) == 0) {
    throw InvalidInput(what + ": the array is not C-contiguous (a slice or a transposed view); "
                              "numpy.ascontiguousarray() makes a contiguous copy");
  }
}

}  // namespace

RgbView rgbView(const py::array& image, const std::string& what) {
  checkUint8(image, what, "(H, W, 3)", false);
  return {static_cast<int>(image.shape(1)), static_cast<int>(image.shape(0)), static_cast<const std::uint8_t*>(image.data())};
}

Image toImage(const py::array& array, const std::string& what) {
  checkUint8(array, what, "(H, W) or (H, W, 3)", true);
  Image image(static_cast<int>(array.shape(1)), static_cast<int>(array.shape(0)), array.ndim() == 3 ? 3 : 1);
  std::memcpy(image.data.data(), array.data(), image.data.size());
  return image;
}

py::array toArray(Image image) {
  std::vector<py::ssize_t> shape{image.height, image.width};
  if (image.channels > 1) shape.push_back(image.channels);
  auto* owned = new Image(std::move(image));
  py::capsule free(owned, [](void* p) { delete static_cast<Image*>(p); });
  return py::array(py::dtype::of<std::uint8_t>(), shape, owned->data.data(), free);
}

py::array toArray(const std::vector<Vec2>& points) {
  py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{2}});
  auto view = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i) {
    view(static_cast<py::ssize_t>(i), 0) = points[i].x();
    view(static_cast<py::ssize_t>(i), 1) = points[i].y();
  }
  return out;
}

std::vector<Vec2> toPoints(const py::handle& points, const std::string& what) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(points);
  if (!a) throw py::type_error(what + ": expected an N x 2 array of numbers");
  if (a.ndim() != 2 || a.shape(1) != 2) throw InvalidInput(what + ": expected shape (N, 2), got " + shapeText(a));
  std::vector<Vec2> out;
  const auto view = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    if (!std::isfinite(view(i, 0)) || !std::isfinite(view(i, 1))) {
      throw InvalidInput(what + ": point " + std::to_string(i) + " (" + strprintf("%g, %g", view(i, 0), view(i, 1)) +
                         ") is not finite");
    }
    out.emplace_back(view(i, 0), view(i, 1));
  }
  return out;
}

Pose2 toPose(const Map& map, const py::handle& pose) {
  if (py::isinstance<py::str>(pose)) return toPose(map, parseRoadPosition(pose.cast<std::string>()));
  std::vector<double> v;
  try {
    v = pose.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    throw py::type_error("pose: expected (x, y, heading_rad) or a road position such as \"R1@I1+3\"");
  }
  if (v.size() != 3) throw InvalidInput("pose: expected (x, y, heading_rad) or a road position such as \"R1@I1+3\"");
  if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
    throw InvalidInput(strprintf("pose (%g, %g, %g): x, y and heading must be finite", v[0], v[1], v[2]));
  }
  return Pose2(v[0], v[1], v[2]);
}

py::tuple fromPose(const Pose2& pose) { return py::make_tuple(pose.x(), pose.y(), pose.heading()); }

py::object fromJson(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

std::string optionsText(const py::object& options) {
  if (options.is_none()) return "{}";
  if (py::isinstance<py::str>(options)) return options.cast<std::string>();
  return py::module_::import("json").attr("dumps")(options).cast<std::string>();
}

}  // namespace mapnav::python
