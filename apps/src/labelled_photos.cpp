#include "labelled_photos.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <system_error>

#include "mapnav/core/error.h"
#include "mapnav/image/png.h"
#include "command_support.h"

namespace mapnav::cli {

namespace fs = std::filesystem;

std::vector<LabelledPhoto> readLabelledPhotos(const fs::path& images, const fs::path& labels, bool same_size) {
  for (const auto& [option, dir] : {std::pair{"--images", images}, std::pair{"--labels", labels}}) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw IoError(std::string(option) + " " + dir.string() + ": no such folder");
  }
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::directory_iterator it(images, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code type_ec;
    if (it->is_regular_file(type_ec) && it->path().extension() == ".png") files.push_back(it->path());
  }
  if (ec) throw IoError(images.string() + ": cannot list the folder: " + ec.message());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InvalidInput(images.string() + ": no .png images in the folder");
  std::vector<LabelledPhoto> set;
  for (const fs::path& f : files) {
    LabelledPhoto s;
    s.image_file = f;
    s.label_file = labels / (f.stem().string() + ".png");
    if (std::error_code label_ec; !fs::is_regular_file(s.label_file, label_ec))
      throw InvalidInput(f.string() + ": no label " + s.label_file.string() + " (labels are matched by file stem)");
    s.image = readPng(f);
    s.label = readPng(s.label_file);
    if (s.image.channels != 3) throw InvalidInput(f.string() + ": expected an RGB photo");
    if (s.label.channels != 1) throw InvalidInput(s.label_file.string() + ": expected a 1-channel PNG of class indices");
    if (s.label.width != s.image.width || s.label.height != s.image.height)
      throw InvalidInput(s.label_file.string() + ": the label is " + std::to_string(s.label.width) + "x" +
                         std::to_string(s.label.height) + " but its image is " + std::to_string(s.image.width) + "x" +
                         std::to_string(s.image.height));
    if (same_size && !set.empty() &&
        (s.image.width != set.front().image.width || s.image.height != set.front().image.height))
      throw InvalidInput(f.string() + ": every image must have the size of the first (" +
                         std::to_string(set.front().image.width) + "x" + std::to_string(set.front().image.height) + ")");
    set.push_back(std::move(s));
  }
  return set;
}

std::vector<int> parseLabelValues(const std::string& option, const std::string& text) {
  std::vector<int> out;
  if (text.empty()) return out;
  for (double v : parseNumbers(option, text, 1, 256, "label values V[,V...] (0-255)")) {
    if (v != std::floor(v)) throw InvalidInput(option + " \"" + text + "\": label values are whole numbers");
    out.push_back(static_cast<int>(v));
  }
  return out;
}

}  // namespace mapnav::cli
