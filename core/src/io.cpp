#include "mapnav/core/io.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "mapnav/core/error.h"
#include "mapnav/core/interrupt.h"

namespace mapnav {
namespace fs = std::filesystem;

std::string readFile(const fs::path& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw IoError(path.string() + ": is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path.string() + ": cannot open: " + std::strerror(errno));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw IoError(path.string() + ": cannot read");
  return std::move(buffer).str();
}

namespace {
fs::path temporaryPathFor(const fs::path& path) {
  static std::atomic<unsigned> counter{0};
  // Same folder (so that rename is atomic), same extension (so that format-by-extension writers work).
  const std::string name = "." + path.stem().string() + ".tmp" + std::to_string(::getpid()) + "-" +
                           std::to_string(counter++) + path.extension().string();
  return path.parent_path() / name;
}
}  // namespace

void writeFileAtomic(const fs::path& path, const std::function<void(const fs::path& tmp)>& write) {
  const fs::path tmp = temporaryPathFor(path);
  try {
    write(tmp);
    throwIfInterrupted();  // Ctrl-C while writing: the previous file stays
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) throw IoError(path.string() + ": cannot write: " + ec.message());
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
}

void writeFileAtomic(const fs::path& path, std::string_view bytes) {
  writeFileAtomic(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw IoError(path.string() + ": cannot write: " + std::strerror(errno));
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw IoError(path.string() + ": cannot write (disk full?)");
  });
}

}  // namespace mapnav
