// The Python module `mapnav` (its compiled part, mapnav._mapnav; python/mapnav/__init__.py
// re-exports it): the library's maps, cameras, predicted views, routes, vision pipelines, replay
// logs, missions and the evaluation on labelled photos, with numpy arrays for images, masks and point lists (docs/python.md).
#include "convert.h"

#include "mapnav/core/error.h"
#include "mapnav/core/issue.h"
#include "mapnav/vision/pipelines.h"

namespace mapnav::python {

namespace {

PyObject* g_error = nullptr;
PyObject* g_invalid = nullptr;
PyObject* g_validation = nullptr;
PyObject* g_io = nullptr;
PyObject* g_not_found = nullptr;

PyObject* addError(py::module_& m, const char* name, const py::object& bases, const char* doc) {
  const std::string full = std::string("mapnav.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(full.c_str(), doc, bases.ptr(), nullptr);
  if (type == nullptr) throw py::error_already_set();
  m.add_object(name, py::handle(type));
  return type;
}

// A ValidationError carries the file and every issue, as the CLI prints them.
void raiseValidation(const ValidationError& e) {
  py::object error = py::reinterpret_borrow<py::object>(g_validation)(e.what());
  error.attr("file") = e.file();
  error.attr("issues") = py::cast(e.issues());
  PyErr_SetObject(g_validation, error.ptr());
}

void translate(std::exception_ptr thrown) {
  try {
    if (thrown) std::rethrow_exception(thrown);
  } catch (const ValidationError& e) {
    raiseValidation(e);
  } catch (const InvalidInput& e) {
    PyErr_SetString(g_invalid, e.what());
  } catch (const IoError& e) {
    PyErr_SetString(g_io, e.what());
  } catch (const NotFound& e) {
    PyErr_SetString(g_not_found, e.what());
  } catch (const Error& e) {
    PyErr_SetString(g_error, e.what());
  }
}

}  // namespace

void bindErrors(py::module_& m) {
  const py::handle exception(PyExc_Exception);
  g_error = addError(m, "Error", py::reinterpret_borrow<py::object>(exception), "Every error mapnav raises.");
  const py::object error = py::reinterpret_borrow<py::object>(g_error);
  g_invalid = addError(m, "InvalidInput", py::make_tuple(error, py::handle(PyExc_ValueError)),
                       "The input was understood and is wrong (the CLI's exit code 1).");
  g_validation = addError(m, "ValidationError", py::make_tuple(py::handle(g_invalid)),
                          "An invalid file, with `file` and every problem found in it as `issues` (list[Issue]).");
  g_io = addError(m, "IoError", py::make_tuple(error, py::handle(PyExc_OSError)),
                  "A file or folder could not be read or written (the CLI's exit code 2).");
  g_not_found = addError(m, "NotFound", py::make_tuple(error, py::handle(PyExc_LookupError)),
                         "An unknown id or name (road, intersection, pipeline), or no route.");
  py::register_exception_translator(translate);
}

}  // namespace mapnav::python

PYBIND11_MODULE(_mapnav, m) {
  using namespace mapnav::python;
  m.doc() = "mapnav: map-based navigation of small vehicles with one camera (docs/python.md).";
  m.attr("__version__") = MAPNAV_VERSION;
  m.attr("_source_dir") = MAPNAV_SOURCE_DIR;  // the shipped maps when not installed (mapnav.distributed)
  mapnav::registerBuiltinPipelines();
  bindErrors(m);
  bindMap(m);
  bindPredict(m);
  bindVision(m);
  bindMission(m);
  bindSuite(m);
  bindEval(m);
}
