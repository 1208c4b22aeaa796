#pragma once
// An image at another size: photos averaged over the pixels they shrink from (or interpolated when
// enlarged), label and mask images by their nearest pixel so that no class index is made up. What
// `mapnav eval segmentation --resize` and the resolution tests score the pipelines at.
#include "mapnav/image/image.h"

namespace mapnav {

enum class ResizeKind {
  Photo,   ///< area average when shrinking, bilinear when enlarging
  Labels,  ///< nearest pixel: class indices and masks stay what they were
};

/// `image` (1 or 3 channels) at `size`. Throws InvalidInput for an empty image or a size below 1 px
/// or above kMaxImagePixels.
Image resized(const Image& image, ImageSize size, ResizeKind kind);

}  // namespace mapnav
