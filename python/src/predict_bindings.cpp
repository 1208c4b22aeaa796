// mapnav.predict and its Prediction (the Map -> Vision token), mapnav.route and its Route.

#include "convert.h"
#include "mapnav/core/error.h"
#include "mapnav/navigator/road_position.h"
#include "mapnav/navigator/route.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav::python {

namespace {

py::array segmentArray(const Segment2& s) { return toArray(std::vector<Vec2>{s.a, s.b}); }
py::tuple pair(const Vec2& v) { return py::make_tuple(v.x(), v.y()); }

void bindTokens(py::module_& m) {
  py::class_<PredictedRegion>(m, "PredictedRegion", "A road or intersection in view.")
      .def_readonly("id", &PredictedRegion::id)
      .def_readonly("kind", &PredictedRegion::kind, "\"straight road\", \"curve\", \"cross intersection\", ...")
      .def_readonly("surface", &PredictedRegion::surface)
      .def_property_readonly("vehicle", [](const PredictedRegion& r) {
        py::list parts;
        for (const Polygon2& part : r.vehicle) parts.append(toArray(part));
        return parts;
      }, "Its paved area inside the view footprint: a list of N x 2 polygons, vehicle frame, m.")
      .def_readonly("segments", &PredictedRegion::segments, "The ids of its interest segments.")
      .def("__repr__", [](const PredictedRegion& r) { return "<PredictedRegion " + r.kind + " " + r.id + ">"; });
  py::class_<InterestSegment>(m, "InterestSegment", "A primary straight edge the camera should see.")
      .def_readonly("id", &InterestSegment::id, "stable across views: \"R1.left.0\", \"I14.corner.2\"")
      .def_readonly("owner", &InterestSegment::owner)
      .def_readonly("side", &InterestSegment::side)
      .def_property_readonly("vehicle", [](const InterestSegment& s) { return segmentArray(s.vehicle); }, "2 x 2, m")
      .def_property_readonly("image", [](const InterestSegment& s) { return segmentArray(s.image); }, "2 x 2, pixels")
      .def_readonly("left_surface", &InterestSegment::left_surface)
      .def_readonly("right_surface", &InterestSegment::right_surface)
      .def("__repr__", [](const InterestSegment& s) { return "<InterestSegment " + s.id + ">"; });
  py::class_<SegmentRelation>(m, "SegmentRelation", "Two interest segments parallel, or crossing.")
      .def_property_readonly("type", [](const SegmentRelation& r) {
        return r.type == SegmentRelation::Type::Parallel ? "parallel" : "crossing";
      })
      .def_readonly("a", &SegmentRelation::a)
      .def_readonly("b", &SegmentRelation::b)
      .def_readonly("separation_m", &SegmentRelation::separation_m, "parallel: the distance between the lines")
      .def_readonly("angle_rad", &SegmentRelation::angle_rad, "crossing: the angle between the lines")
      .def_property_readonly("point", [](const SegmentRelation& r) { return pair(r.point); }, "crossing: vehicle frame");
  py::class_<PredictedLandmark>(m, "PredictedLandmark", "A landmark the camera should see.")
      .def_readonly("id", &PredictedLandmark::id)
      .def_readonly("kind", &PredictedLandmark::kind)
      .def_property_readonly("vehicle", [](const PredictedLandmark& l) { return pair(l.vehicle); })
      .def_property_readonly("image_base", [](const PredictedLandmark& l) { return pair(l.image_base); })
      .def_property_readonly("image_top", [](const PredictedLandmark& l) { return pair(l.image_top); })
      .def_readonly("width_px", &PredictedLandmark::width_px);
}

void bindPrediction(py::module_& m) {
  py::class_<PyPrediction, std::shared_ptr<PyPrediction>>(m, "Prediction",
                                                          "A predicted view: what the camera should see from a pose.")
      .def_property_readonly("objects", [](const PyPrediction& p) { return p.prediction.view.regions; },
                             "The roads and intersections in view (list[PredictedRegion]).")
      .def_property_readonly("segments", [](const PyPrediction& p) { return p.prediction.view.segments; })
      .def_property_readonly("relations", [](const PyPrediction& p) { return p.prediction.view.relations; })
      .def_property_readonly("landmarks", [](const PyPrediction& p) { return p.prediction.view.landmarks; })
      .def_property_readonly("footprint", [](const PyPrediction& p) { return toArray(p.prediction.view.footprint); },
                             "The ground in view, N x 2, vehicle frame (x forward, y left), m.")
      .def_property_readonly("pose", [](const PyPrediction& p) { return fromPose(p.prediction.pose); })
      .def_property_readonly("camera", [](const PyPrediction& p) { return std::const_pointer_cast<Camera>(p.camera); })
      .def_property_readonly("empty", [](const PyPrediction& p) { return p.prediction.empty(); })
      .def_property_readonly(
          "road_mask", [](const PyPrediction& p) {
            const Image mask = predictedRoadMask(p.prediction.view, *p.camera);
            return toArray(mask.empty() ? Image(p.camera->width(), p.camera->height(), 1) : mask);
          },
          "The predicted road in the image: H x W uint8, 255 on the road regions, 0 elsewhere.")
      .def("to_json", [](const PyPrediction& p) { return predictionToJson(p.prediction); },
           "The prediction as `mapnav predict --json` prints it (str).");
  m.def(
      "predict",
      [](std::shared_ptr<const Map> map, std::shared_ptr<const Camera> camera, const py::object& pose, double near,
         double far) {
        PredictOptions options;
        options.near_m = near;
        options.far_m = far;
        Prediction p = predictView(*map, toPose(*map, pose), *camera, options);
        return std::make_shared<PyPrediction>(PyPrediction{std::move(p), std::move(camera), std::move(map)});
      },
      py::arg("map"), py::arg("camera"), py::arg("pose"), py::arg("near") = 1.0, py::arg("far") = 15.0,
      "What `camera` on a vehicle at `pose` (a road position \"R1@I1+3\" or (x, y, heading_rad)) should see of "
      "`map`, as `mapnav predict`.");
}

struct PyRoute {
  Route route;
};

void bindRoute(py::module_& m) {
  py::class_<PyRoute>(m, "Route", "A route across intersections, as `mapnav route` plans it.")
      .def_property_readonly("start", [](const PyRoute& r) { return toString(r.route.from); })
      .def_property_readonly("goal", [](const PyRoute& r) { return toString(r.route.to); })
      .def_property_readonly("length_m", [](const PyRoute& r) { return r.route.length_m; })
      .def_property_readonly("cost", [](const PyRoute& r) { return r.route.cost; })
      .def_property_readonly("legs", [](const PyRoute& r) { return py::object(fromJson(toJson(r.route))["legs"]); },
                             "The motion commands as dicts, as in `mapnav route --json`.")
      .def_property_readonly("roads", [](const PyRoute& r) { return r.route.roads; })
      .def_property_readonly("intersections", [](const PyRoute& r) { return r.route.intersections; })
      .def_property_readonly("line", [](const PyRoute& r) { return toArray(r.route.line.points()); },
                             "The centre line driven, start to goal: N x 2, world frame, m.")
      .def_property_readonly("dialogue", [](const PyRoute& r) { return toDialogue(r.route); })
      .def("to_json", [](const PyRoute& r) { return toJson(r.route); }, "`mapnav route --json`'s text.");
  m.def(
      "route",
      [](const Map& map, const std::string& from, const std::string& to, const std::vector<std::string>& block) {
        RouteOptions options;
        options.blocked = block;
        RoadGraph graph(map);
        RouteResult result = graph.route(parseRoadPosition(from), parseRoadPosition(to), options);
        if (!result.route) throw NotFound("no route: " + result.reason);
        return PyRoute{std::move(*result.route)};
      },
      py::arg("map"), py::arg("from_"), py::arg("to"), py::arg("block") = std::vector<std::string>{},
      "The cheapest route between two road positions (\"R1@I1+3\"), avoiding the roads and intersections in "
      "`block`. Raises NotFound (\"no route: ...\") when there is none.");
}

}  // namespace

void bindPredict(py::module_& m) {
  bindTokens(m);
  bindPrediction(m);
  bindRoute(m);
}

}  // namespace mapnav::python
