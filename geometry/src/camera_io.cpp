#include "mapnav/geometry/camera_io.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/core/json.h"
#include "mapnav/core/strprintf.h"

namespace mapnav {

namespace {

constexpr double kMaxImageSide = 1e6;  // pixels

/// An integer in [min, max] (as JSON Schema, 512.0 is an integer): `schema.type` for anything else,
/// `schema.range` outside.
std::optional<int> readInteger(const Json* value, const std::string& pointer, Issues& issues, double min, double max) {
  if (value == nullptr) return std::nullopt;
  const double x = value->is_number() ? value->get<double>() : 0.5;
  if (!value->is_number() || !std::isfinite(x) || std::floor(x) != x) {
    addIssue(issues, Severity::Error, "schema.type", pointer,
             "expected an integer, got " + (value->is_number() ? numberText(x) : std::string(jsonTypeName(*value))));
    return std::nullopt;
  }
  if (x < min || x > max) {
    addIssue(issues, Severity::Error, "schema.range", pointer,
             "integer " + numberText(x) + " is outside [" + numberText(min) + ", " + numberText(max) + "]");
    return std::nullopt;
  }
  return static_cast<int>(x);
}

/// A number that must be > 0 (`schema.range` otherwise).
std::optional<double> readPositive(const Json& value, const std::string& pointer, Issues& issues) {
  const auto x = readNumber(value, pointer, issues);
  if (!x) return std::nullopt;
  if (!(*x > 0.0)) {
    addIssue(issues, Severity::Error, "schema.range", pointer, "number " + numberText(*x) + " must be > 0");
    return std::nullopt;
  }
  return x;
}

/// [a, b]: two numbers, both > 0 when `positive`.
std::optional<Vec2> readPair(const Json* value, const std::string& pointer, Issues& issues, bool positive,
                             std::string_view shape) {
  if (value == nullptr) return std::nullopt;
  if (!value->is_array() || value->size() != 2) {
    addIssue(issues, Severity::Error, "schema.type", pointer,
             "expected " + std::string(shape) + ", got " +
                 (value->is_array() ? "an array of " + std::to_string(value->size()) : std::string(jsonTypeName(*value))));
    return std::nullopt;
  }
  std::array<std::optional<double>, 2> xy;
  for (std::size_t k = 0; k < 2; ++k) {
    const std::string at = pointerJoin(pointer, k);
    xy[k] = positive ? readPositive((*value)[k], at, issues) : readNumber((*value)[k], at, issues);
  }
  if (!xy[0] || !xy[1]) return std::nullopt;
  return Vec2(*xy[0], *xy[1]);
}

std::optional<std::vector<double>> readCoefficients(const Json* value, const std::string& pointer, Issues& issues) {
  if (value == nullptr) return std::vector<double>{};
  if (!value->is_array()) {
    addIssue(issues, Severity::Error, "schema.type", pointer,
             "expected an array of distortion coefficients, got " + std::string(jsonTypeName(*value)));
    return std::nullopt;
  }
  std::vector<double> out;
  bool ok = true;
  for (std::size_t k = 0; k < value->size(); ++k) {
    const auto x = readNumber((*value)[k], pointerJoin(pointer, k), issues);
    if (x) out.push_back(*x);
    ok = ok && x.has_value();
  }
  if (!ok) return std::nullopt;
  return out;
}

/// The distortion coefficient counts a model takes, and how to say so.
bool distortionCountOk(LensModel model, std::size_t n) {
  switch (model) {
    case LensModel::Pinhole:
      return n == 0 || n == 4 || n == 5;
    case LensModel::PaperFisheye:
      return n == 0;
    case LensModel::EquidistantFisheye:
      return n == 0 || n == 4;
  }
  return false;
}

std::string_view distortionCounts(LensModel model) {
  switch (model) {
    case LensModel::Pinhole:
      return "0, 4 (k1 k2 p1 p2) or 5 (k1 k2 p1 p2 k3)";
    case LensModel::PaperFisheye:
      return "none";
    case LensModel::EquidistantFisheye:
      return "0 or 4 (k1 k2 k3 k4)";
  }
  return "none";
}

std::optional<CameraMount> readMount(const Json& value, const std::string& pointer, Issues& issues) {
  JsonObject object(value, pointer, issues);
  if (!object.isObject()) return std::nullopt;
  const auto x = object.number("x", false);
  const auto y = object.number("y", false);
  std::optional<double> height;
  if (const Json* h = object.member("height_m", true)) height = readPositive(*h, object.pointer("height_m"), issues);
  const auto tilt = object.number("tilt_deg", true, -90.0, 90.0);
  const auto roll = object.number("roll_deg", false, -180.0, 180.0);
  const auto yaw = object.number("yaw_deg", false, -180.0, 180.0);
  object.rejectUnknownMembers();
  const bool optional_ok = (x || !object.has("x")) && (y || !object.has("y")) && (roll || !object.has("roll_deg")) &&
                           (yaw || !object.has("yaw_deg"));
  if (!height || !tilt || !optional_ok) return std::nullopt;
  CameraMount mount;
  mount.offset = Vec2(x.value_or(0.0), y.value_or(0.0));
  mount.height_m = *height;
  mount.tilt_rad = degToRad(*tilt);
  mount.roll_rad = degToRad(roll.value_or(0.0));
  mount.yaw_rad = degToRad(yaw.value_or(0.0));
  return mount;
}


}  // namespace

std::unique_ptr<Camera> parseCamera(std::string_view text, Issues& issues, std::string* name) {
  const std::size_t before = countSeverity(issues, Severity::Error);
  const auto json = parseJson(text, issues);
  if (!json) return nullptr;
  JsonObject top(*json, "", issues);
  if (!top.isObject()) return nullptr;

  if (const auto format = top.string("format")) {
    if (*format != kCameraFormat) {
      addIssue(issues, Severity::Error, "schema.format", "/format",
               "unknown format \"" + *format + "\"; expected \"" + std::string(kCameraFormat) + "\"");
    }
  }
  if (const Json* schema = top.member("$schema", false); schema != nullptr && !schema->is_string()) {
    addIssue(issues, Severity::Error, "schema.type", "/$schema", "expected a string");
  }
  const auto document_name = top.string("name", false);
  std::optional<LensModel> model;
  if (const auto model_text = top.string("model")) {
    model = lensModelFromString(*model_text);
    if (!model) {
      addIssue(issues, Severity::Error, "schema.enum", "/model",
               "unknown camera model \"" + *model_text + "\"; expected one of pinhole, fisheye-orthographic, "
               "fisheye-equidistant");
    }
  }

  CameraIntrinsics intrinsics;
  bool intrinsics_ok = true;
  if (const Json* image_json = top.member("image", true)) {
    JsonObject image(*image_json, "/image", issues);
    const auto width = readInteger(image.member("width", true), image.pointer("width"), issues, 1, kMaxImageSide);
    const auto height = readInteger(image.member("height", true), image.pointer("height"), issues, 1, kMaxImageSide);
    image.rejectUnknownMembers();
    intrinsics_ok = width && height;
    if (intrinsics_ok) {
      intrinsics.width = *width;
      intrinsics.height = *height;
    }
  } else {
    intrinsics_ok = false;
  }
  const auto focal = readPair(top.member("focal_px", true), "/focal_px", issues, true, "[fx, fy]");
  const auto principal = readPair(top.member("principal_point", true), "/principal_point", issues, false, "[cx, cy]");
  const auto distortion = readCoefficients(top.member("distortion", false), "/distortion", issues);
  if (model && distortion && !distortionCountOk(*model, distortion->size())) {
    addIssue(issues, Severity::Error, "camera.distortion_count", "/distortion",
             std::to_string(distortion->size()) + " distortion coefficients for a " + std::string(toString(*model)) +
                 " camera; it takes " + std::string(distortionCounts(*model)));
  }
  std::optional<CameraMount> mount;
  if (const Json* mount_json = top.member("mount", true)) mount = readMount(*mount_json, "/mount", issues);
  top.rejectUnknownMembers();

  if (countSeverity(issues, Severity::Error) != before || !model || !intrinsics_ok || !focal || !principal ||
      !distortion || !mount) {
    return nullptr;
  }
  intrinsics.fx = focal->x();
  intrinsics.fy = focal->y();
  intrinsics.cx = principal->x();
  intrinsics.cy = principal->y();
  intrinsics.distortion = *distortion;
  try {
    auto camera = createCamera(*model, intrinsics, *mount);
    if (name != nullptr) *name = document_name.value_or("");
    return camera;
  } catch (const InvalidInput& e) {  // every check above should have caught it first
    addIssue(issues, Severity::Error, "camera.invalid", "", e.what());
    return nullptr;
  }
}

std::unique_ptr<Camera> loadCamera(const std::filesystem::path& path) {
  const std::string text = readFile(path);
  Issues issues;
  auto camera = parseCamera(text, issues);
  if (!camera) throw ValidationError(path.string(), std::move(issues));
  return camera;
}

std::string cameraToJson(const Camera& camera, std::string_view name) {
  const CameraIntrinsics& in = camera.intrinsics();
  const CameraMount& m = camera.mount();
  if (!(std::abs(m.tilt_rad) <= 0.5 * kPi)) {
    throw InvalidInput("cameraToJson: CameraMount::tilt_rad = " + numberText(m.tilt_rad) +
                       ": the format holds tilts within ±90 degrees");
  }
  // Roll and yaw are written within ±180 degrees (the same rotation).
  auto wrapped = [](double radians) { return std::abs(radians) <= kPi ? radians : normalizeAngle(radians); };
  Json doc = Json::object();
  doc["format"] = kCameraFormat;
  if (!name.empty()) doc["name"] = name;
  doc["model"] = toString(camera.model());
  doc["image"] = {{"width", in.width}, {"height", in.height}};
  doc["focal_px"] = Json::array({in.fx, in.fy});
  doc["principal_point"] = Json::array({in.cx, in.cy});
  Json distortion = Json::array();
  for (double k : in.distortion) distortion.push_back(k);
  doc["distortion"] = std::move(distortion);
  doc["mount"] = {{"x", m.offset.x()},
                  {"y", m.offset.y()},
                  {"height_m", m.height_m},
                  {"tilt_deg", std::clamp(degreesFor(m.tilt_rad), -90.0, 90.0)},
                  {"roll_deg", std::clamp(degreesFor(wrapped(m.roll_rad)), -180.0, 180.0)},
                  {"yaw_deg", std::clamp(degreesFor(wrapped(m.yaw_rad)), -180.0, 180.0)}};
  return dumpJson(doc);
}

}  // namespace mapnav
