#include "mapnav/eval/labelled_photos.h"

#include <algorithm>
#include <string>
#include <system_error>
#include <utility>

#include "mapnav/core/error.h"
#include "mapnav/image/png.h"

namespace mapnav {

namespace fs = std::filesystem;

namespace {

std::string sizeText(const Image& image) { return std::to_string(image.width) + "x" + std::to_string(image.height); }

}  // namespace

std::vector<LabelledPhoto> readLabelledPhotos(const fs::path& images, const fs::path& labels, bool same_size) {
  for (const auto& [dir, what] : {std::pair{images, "the images"}, std::pair{labels, "the labels"}}) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw IoError(dir.string() + ": no such folder (" + what + ")");
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
      throw InvalidInput(s.label_file.string() + ": the label is " + sizeText(s.label) + " but its image is " +
                         sizeText(s.image));
    if (same_size && !set.empty() &&
        (s.image.width != set.front().image.width || s.image.height != set.front().image.height))
      throw InvalidInput(f.string() + ": every image must have the size of the first (" + sizeText(set.front().image) +
                         ")");
    set.push_back(std::move(s));
  }
  return set;
}

}  // namespace mapnav
