#pragma once
// Reading and writing `mapnav-camera/1` JSON files (docs/camera-format.md): a lens model, its
// intrinsics and its mount on the vehicle. Angles are degrees in the file and radians in
// CameraMount. As the map readers, the reader either throws or, given an issue list, collects every
// problem (with its JSON Pointer) and goes on.
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include "mapnav/core/issue.h"
#include "mapnav/geometry/camera.h"

namespace mapnav {

inline constexpr std::string_view kCameraFormat = "mapnav-camera/1";

/// The camera a document's text describes; nullptr (and issues: `json.syntax`, `schema.*`,
/// `camera.distortion_count`) when it is not a valid camera. When `name` is given it receives the
/// document's "name" ("" when absent).
std::unique_ptr<Camera> parseCamera(std::string_view text, Issues& issues, std::string* name = nullptr);

/// parseCamera on a file. Throws ValidationError (with every issue) or IoError.
std::unique_ptr<Camera> loadCamera(const std::filesystem::path& path);

/// The document's text (2-space indented, doubles that read back to the same bits; angles written in
/// degrees such that they read back to the same radians whenever such a decimal exists). `name` is
/// written when not empty.
std::string cameraToJson(const Camera& camera, std::string_view name = {});

}  // namespace mapnav
