#pragma once
// File I/O with the project's guarantees: errors name the file, and outputs are written to a
// temporary name in the same folder and renamed, so that a failure leaves no half-written file.
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace mapnav {

/// The whole file as bytes. Throws IoError naming the file when it cannot be read (missing, a
/// folder, no permission).
std::string readFile(const std::filesystem::path& path);

/// Writes `bytes` to `path` atomically. Throws IoError naming the file.
void writeFileAtomic(const std::filesystem::path& path, std::string_view bytes);

/// Calls `write(tmp)` to produce the file at a temporary path (same folder, same extension, so that
/// writers that pick the format by extension work), then renames it to `path`. If `write` throws,
/// the temporary file is removed and the exception propagates.
void writeFileAtomic(const std::filesystem::path& path,
                     const std::function<void(const std::filesystem::path& tmp)>& write);

}  // namespace mapnav
