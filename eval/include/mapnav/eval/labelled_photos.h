#pragma once
// A folder of photos and a folder of their per-pixel labels, matched by file stem: what `mapnav eval
// segmentation` scores (segmentation_evaluation.h) and `mapnav train segmentation` trains on.
#include <filesystem>
#include <vector>

#include "mapnav/image/image.h"

namespace mapnav {

struct LabelledPhoto {
  std::filesystem::path image_file, label_file;
  Image image;  ///< RGB
  Image label;  ///< 1 channel class indices, the image's size
};

/// Every .png of `images` (in file-name order) with the .png of the same stem in `labels`, read and
/// checked before anything runs: IoError naming the folder for a missing one ("DIR: no such folder
/// (the images)"); InvalidInput naming the file for an image without its label, a label that is not
/// 1-channel or not its image's size, a photo that is not RGB, a corrupt PNG, no photos; with
/// `same_size`, a photo of another size than the first.
std::vector<LabelledPhoto> readLabelledPhotos(const std::filesystem::path& images, const std::filesystem::path& labels,
                                              bool same_size);

}  // namespace mapnav
