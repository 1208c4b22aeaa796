// mapnav.Issue, mapnav.Map, mapnav.validate and mapnav.Camera.

#include <cmath>

#include "convert.h"
#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/map/geojson.h"
#include "mapnav/map/info.h"
#include "mapnav/map/map_io.h"
#include "mapnav/map/validation.h"
#include "mapnav/vision/segmentation_eval.h"

namespace mapnav::python {

namespace {

std::optional<GeoOrigin> toOrigin(const std::optional<std::vector<double>>& origin) {
  if (!origin) return std::nullopt;
  const std::vector<double>& v = *origin;
  if (v.size() < 2 || v.size() > 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || std::abs(v[0]) > 90 ||
      std::abs(v[1]) > 180) {
    throw InvalidInput("origin: expected (lat, lon) or (lat, lon, alt), latitude in [-90, 90], longitude in [-180, 180]");
  }
  return GeoOrigin{v[0], v[1], v.size() == 3 ? v[2] : 0.0};
}

// A map file in either format, or ValidationError with every issue (pointers into the file).
std::shared_ptr<Map> loadMapFile(const std::string& path, const std::optional<GeoJsonImportOptions>& geojson) {
  Issues issues;
  auto map = readMapFile(path, issues, geojson);
  if (!map) throw ValidationError(path, issues);
  return std::make_shared<Map>(std::move(*map));
}

std::vector<std::string> idsOf(const auto& items) {
  std::vector<std::string> ids;
  for (const auto& item : items) ids.push_back(item.id);
  return ids;
}

void bindIssue(py::module_& m) {
  py::class_<Issue>(m, "Issue", "One problem found in a file: severity, check, JSON Pointer, message.")
      .def_property_readonly("severity", [](const Issue& i) { return std::string(toString(i.severity)); },
                             "\"error\" or \"warning\"")
      .def_readonly("check", &Issue::check, "the dotted check name, e.g. \"roads.unknown_intersection\"")
      .def_readonly("pointer", &Issue::where, "JSON Pointer (RFC 6901) into the file; \"\" is the whole document")
      .def_readonly("message", &Issue::message, "what is wrong, for a person")
      .def_readonly("line", &Issue::line, "1-based line of a syntax error, else 0")
      .def("format", [](const Issue& i, const std::string& file) { return formatIssue(i, file); }, py::arg("file"),
           "The line `mapnav map validate` prints: FILE:/pointer: severity: check: message")
      .def("__repr__", [](const Issue& i) { return "<Issue " + formatIssue(i, "") + ">"; });
}

void bindMapClass(py::module_& m) {
  py::class_<Map, std::shared_ptr<Map>>(m, "Map", "A validated map (docs/map-format.md).")
      .def_static("load", [](const std::string& path) { return loadMapFile(path, std::nullopt); }, py::arg("path"),
                  "Reads a mapnav-map/1 JSON file, or GeoJSON by its .geojson extension. Raises ValidationError "
                  "(with .issues) when it is not a valid map, IoError when it cannot be read.")
      .def_static(
          "import_geojson",
          [](const std::string& path, const std::optional<std::vector<double>>& origin, double snap_tolerance_m) {
            GeoJsonImportOptions options;
            options.origin = toOrigin(origin);
            options.snap_tolerance_m = snap_tolerance_m;
            return loadMapFile(path, options);
          },
          py::arg("path"), py::arg("origin") = py::none(), py::arg("snap_tolerance_m") = 1.0,
          "Imports a GeoJSON FeatureCollection (QGIS, geojson.io) as `mapnav map import-geojson` does; "
          "origin (lat, lon[, alt]) is the local frame's, default the file's or the data's centroid.")
      .def_property_readonly("name", &Map::name)
      .def_property_readonly("road_ids", [](const Map& map) { return idsOf(map.roads()); })
      .def_property_readonly("intersection_ids", [](const Map& map) { return idsOf(map.intersections()); })
      .def_property_readonly("landmark_ids", [](const Map& map) { return idsOf(map.landmarks()); })
      .def_property_readonly("warnings", &Map::warnings, "The warnings validation found (list[Issue]).")
      .def("validate", [](const Map& map) { return validateMap(map.data()); },
           "Every issue of the map (warnings: a loaded map has no errors), pointers into its mapnav-map/1 JSON.")
      .def("info", [](const Map& map) { return fromJson(toJson(describeMap(map))); },
           "Counts by kind, length, bounds, components: `mapnav map info --json` as a dict.")
      .def("pose_at", [](const Map& map, const py::object& at) { return fromPose(toPose(map, at)); }, py::arg("position"),
           "The world pose (x, y, heading_rad) of a road position such as \"R1@I1+3\".")
      .def("to_json", [](const Map& map) { return mapToJson(map.data()); }, "The mapnav-map/1 document's text.")
      .def("save", [](const Map& map, const std::string& path) { saveMap(map.data(), path); }, py::arg("path"),
           "Writes the mapnav-map/1 JSON file (atomically: a temporary name, then renamed).")
      .def(
          "export_geojson",
          [](const Map& map, const std::optional<std::string>& path, const std::optional<std::vector<double>>& origin) {
            const std::string text = exportGeoJson(map.data(), toOrigin(origin));
            if (path) writeFileAtomic(*path, text);
            return text;
          },
          py::arg("path") = py::none(), py::arg("origin") = py::none(),
          "The map as GeoJSON in lon/lat (written to `path` when given), as `mapnav map export-geojson`.")
      .def("__repr__", [](const Map& map) {
        return strprintf("<Map %s: %zu roads, %zu intersections, %zu landmarks>", map.name().c_str(), map.roads().size(),
                         map.intersections().size(), map.landmarks().size());
      });
  m.def(
      "validate",
      [](const std::string& path) {
        Issues issues;
        readMapFile(path, issues);
        return issues;
      },
      py::arg("path"),
      "Every problem of a map file (list[Issue], pointers into the file), as `mapnav map validate`; "
      "empty for a map without warnings. Raises IoError when it cannot be read.");
}

py::object pixelOrNone(const std::optional<Vec2>& p) {
  return p ? py::object(py::make_tuple(p->x(), p->y())) : py::object(py::none());
}

Vec2 toPixel(const std::vector<double>& v, const char* what) {
  if (v.size() != 2 || !std::isfinite(v[0]) || !std::isfinite(v[1])) {
    throw InvalidInput(std::string(what) + ": expected 2 finite numbers");
  }
  return {v[0], v[1]};
}

Vec3 toPoint3(const std::vector<double>& v) {
  if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
    throw InvalidInput("point: expected 3 finite numbers (x forward, y left, z up; m)");
  }
  return {v[0], v[1], v[2]};
}

// project() for an N x 3 array: N x 2 pixels, NaN where the camera cannot image the point.
py::array projectPoints(const Camera& camera, const py::array_t<double, py::array::c_style | py::array::forcecast>& points) {
  if (points.ndim() != 2 || points.shape(1) != 3) throw InvalidInput("points: expected shape (N, 3)");
  py::array_t<double> out({points.shape(0), py::ssize_t{2}});
  auto o = out.mutable_unchecked<2>();
  const auto p = points.unchecked<2>();
  for (py::ssize_t i = 0; i < points.shape(0); ++i) {
    const auto pixel = camera.project(Vec3(p(i, 0), p(i, 1), p(i, 2)));
    o(i, 0) = pixel ? pixel->x() : std::nan("");
    o(i, 1) = pixel ? pixel->y() : std::nan("");
  }
  return out;
}

void bindCamera(py::module_& m) {
  using CameraPtr = std::shared_ptr<Camera>;
  py::class_<Camera, CameraPtr>(m, "Camera", "A camera: lens model, intrinsics and mount on the vehicle (docs/camera-format.md).")
      .def_static("load", [](const std::string& path) { return CameraPtr(loadCamera(path)); }, py::arg("path"),
                  "Reads a mapnav-camera/1 file; ValidationError or IoError.")
      .def_static("assumed_photo", [](int w, int h) { return CameraPtr(assumedPhotoCamera(w, h)); }, py::arg("width"),
                  py::arg("height"), "The level pin-hole `mapnav eval` assumes for photos of that size (docs/eval.md).")
      .def_property_readonly("width", &Camera::width)
      .def_property_readonly("height", &Camera::height)
      .def_property_readonly("model", [](const Camera& c) { return std::string(toString(c.model())); })
      .def("project", [](const Camera& c, const std::vector<double>& p) { return pixelOrNone(c.project(toPoint3(p))); },
           py::arg("point"),
           "A vehicle-frame point (x forward, y left, z up, m) to its pixel (u right, v down), or None.")
      .def("project_points", &projectPoints, py::arg("points"), "project() for an N x 3 array: N x 2, NaN where not imaged.")
      .def("backproject",
           [](const Camera& c, const std::vector<double>& pixel) { return pixelOrNone(c.backproject(toPixel(pixel, "pixel"))); },
           py::arg("pixel"), "The ground point (x, y) of the vehicle frame a pixel sees, or None above the horizon.")
      .def("in_image", [](const Camera& c, const std::vector<double>& pixel) { return c.inImage(toPixel(pixel, "pixel")); },
           py::arg("pixel"))
      .def("to_json", [](const Camera& c) { return cameraToJson(c); }, "The mapnav-camera/1 document's text.")
      .def("__repr__", [](const Camera& c) {
        return strprintf("<Camera %s %dx%d>", std::string(toString(c.model())).c_str(), c.width(), c.height());
      });
}

}  // namespace

void bindMap(py::module_& m) {
  bindIssue(m);
  bindMapClass(m);
  bindCamera(m);
}

}  // namespace mapnav::python
