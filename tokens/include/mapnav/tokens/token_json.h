#pragma once
// Each blackboard token as JSON, written in this one place and read by everything that prints one:
// the trace's payloads (mission/trace.h), `mapnav detect --json` and `predict --json`, Python's
// to_json(). Numbers are rounded to fixed steps, so that the bytes do not depend on the last bits of
// a computation that is itself deterministic: metres to 0.1 mm, pixels to 0.01 px, degrees to
// 1e-4, scores to 1e-4; covariances and standard deviations to six significant digits. Frames are
// the tokens' own: vehicle axes (x forward, y left, metres) and image pixels (x right, y down).
// The layouts are docs/trace-format.md's "Prediction", "Detection" and "CurrentPosition" payloads.
#include "mapnav/core/json.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/tokens/current_position.h"
#include "mapnav/tokens/detected_object.h"
#include "mapnav/tokens/predicted_object.h"

namespace mapnav {

/// The predicted view: footprint, regions, interest segments, relations, landmarks, pose covariance.
Json toJson(const PredictedObject& view);
/// What Vision found: status, reason, confidence, lines, region outline (pixels), centre line,
/// landmarks, measured step.
Json toJson(const DetectedObject& detection);
/// The pose, its covariance and its standard deviations across and along the heading, what was
/// observed and why.
Json toJson(const CurrentPosition& position);

/// The rounding and the small pieces the tokens are written with, for the other records of the trace.
namespace token_json {

double metres(double x);          ///< 0.1 mm
double pixels(double x);          ///< 0.01 px
double degrees(double radians);   ///< the angle in degrees, to 1e-4
double significant(double x);     ///< six significant digits
/// {"x", "y", "heading_deg"}: metres and degrees.
Json pose(const Pose2& pose);
/// [x, y], each rounded with `round`.
Json point(const Vec2& p, double (*round)(double));
/// [[ax, ay], [bx, by]]
Json segment(const Segment2& s, double (*round)(double));
/// [[x, y], ...]
Json points(const std::vector<Vec2>& ps, double (*round)(double));
/// A symmetric 3 x 3 matrix as its upper triangle [00, 01, 02, 11, 12, 22], six significant digits.
Json upperTriangle(const Mat3& c);

}  // namespace token_json

}  // namespace mapnav
