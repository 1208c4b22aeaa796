#include "mapnav/vision/region.h"

#include <algorithm>
#include <climits>
#include <tuple>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "binary_morph.h"
#include "cv_view.h"
#include "mapnav/core/error.h"

namespace mapnav {

namespace {

using cvview::view;

Image toImage(const cv::Mat& m) {
  Image out(m.cols, m.rows, 1);
  cv::Mat dst = view(out);
  m.copyTo(dst);
  return out;
}

// Contour i filled (255), inside its bounding box `box` only (a contour lies within it).
cv::Mat filledInBox(const std::vector<std::vector<cv::Point>>& contours, std::size_t i, const cv::Rect& box) {
  cv::Mat one = cv::Mat::zeros(box.height, box.width, CV_8UC1);
  cv::drawContours(one, contours, static_cast<int>(i), cv::Scalar(255), cv::FILLED, cv::LINE_8, cv::noArray(), INT_MAX,
                   -box.tl());
  return one;
}

// Adds to `out` (the main part, filled) the other parts that a line split from it: those within two
// blocks (2 × `block` pixels) of it that score at least `fraction` of its score.
void addSplitParts(const std::vector<std::vector<cv::Point>>& contours, const std::vector<double>& scores,
                   std::size_t main, double fraction, int block, cv::Mat& out) {
  cv::Mat near;
  for (std::size_t i = 0; i < contours.size(); ++i) {
    if (i == main || scores[i] < fraction * scores[main]) continue;
    if (near.empty())
      cv::dilate(out, near, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(4 * block + 1, 4 * block + 1)));
    const cv::Rect box = cv::boundingRect(contours[i]);
    cv::Mat part = filledInBox(contours, i, box);
    cv::bitwise_and(part, near(box), part);
    if (cv::countNonZero(part) > 0) cv::drawContours(out, contours, static_cast<int>(i), cv::Scalar(255), cv::FILLED);
  }
}

// The block grid over a w × h image: bw × bh blocks of bs × bs pixels, the last column and row
// reaching past the image's edge.
struct BlockGrid {
  int w, h, bs, bw, bh;
};

// The road's blocks (255): those with at least options.block_fraction of `road`'s pixels (the image
// padded by replicating its edge), closed then opened options.morph_iterations times (3 × 3).
cv::Mat roadBlocks(const cv::Mat& road, const BlockGrid& g, const RegionOptions& options) {
  cv::Mat padded;
  cv::copyMakeBorder(road, padded, 0, g.bh * g.bs - g.h, 0, g.bw * g.bs - g.w, cv::BORDER_REPLICATE);
  cv::Mat frac;
  cv::resize(padded, frac, cv::Size(g.bw, g.bh), 0, 0, cv::INTER_AREA);
  cv::Mat blocks = frac >= options.block_fraction * 255.0;
  const cv::Mat k3 = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3));
  if (options.morph_iterations > 0) {
    cv::morphologyEx(blocks, blocks, cv::MORPH_CLOSE, k3, cv::Point(-1, -1), options.morph_iterations,
                     cv::BORDER_REPLICATE);
    cv::morphologyEx(blocks, blocks, cv::MORPH_OPEN, k3, cv::Point(-1, -1), options.morph_iterations,
                     cv::BORDER_REPLICATE);
  }
  return blocks;
}

// Of the n - 1 block components in `labels` (1 .. n - 1), the road's: the one overlapping the
// `predicted` road most (when it has any), then the one with most blocks on the bottom row, then
// the largest; the first of equals.
int roadComponent(const cv::Mat& labels, int n, const Image& predicted, const BlockGrid& g) {
  const int w = g.w, h = g.h, bs = g.bs, bw = g.bw, bh = g.bh;
  cv::Mat pred_blocks;
  const bool have_pred = !predicted.empty() && cv::countNonZero(view(predicted)) > 0;
  if (have_pred) {
    cv::Mat pp;
    cv::copyMakeBorder(view(predicted), pp, 0, bh * bs - h, 0, bw * bs - w, cv::BORDER_REPLICATE);
    cv::resize(pp, pred_blocks, cv::Size(bw, bh), 0, 0, cv::INTER_AREA);
  }
  std::vector<double> overlap(static_cast<std::size_t>(n), 0.0), bottom(static_cast<std::size_t>(n), 0.0),
      size(static_cast<std::size_t>(n), 0.0);
  for (int y = 0; y < bh; ++y) {
    for (int x = 0; x < bw; ++x) {
      const int l = labels.at<int>(y, x);
      if (l == 0) continue;
      size[l] += 1;
      if (have_pred) overlap[l] += pred_blocks.at<std::uint8_t>(y, x) / 255.0;
      if (y == bh - 1) bottom[l] += 1;
    }
  }
  int best = 1;
  for (int l = 2; l < n; ++l) {
    const auto key = [&](int i) { return std::make_tuple(have_pred ? overlap[i] : 0.0, bottom[i], size[i]); };
    if (key(l) > key(best)) best = l;
  }
  return best;
}

// A block mask (one value a block) as a mask of the image's pixels.
cv::Mat blockMaskPixels(const cv::Mat& blocks, const BlockGrid& g) {
  cv::Mat px;
  cv::resize(blocks, px, cv::Size(g.bw * g.bs, g.bh * g.bs), 0, 0, cv::INTER_NEAREST);
  return px(cv::Rect(0, 0, g.w, g.h));
}

// The road's pixels (255) within the `allowed` pixels, closed then opened with a disc of radius
// options.pixel_morph_px and then kept to the `valid` pixels (when the radius is > 0).
cv::Mat pixelRegion(const cv::Mat& road, const cv::Mat& allowed, const Image& valid, const RegionOptions& options) {
  cv::Mat px;
  cv::bitwise_and(road, allowed, px);
  if (options.pixel_morph_px > 0) {
    const int k = 2 * options.pixel_morph_px + 1;
    const cv::Mat ke = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(k, k));
    if (options.reference) {
      cv::morphologyEx(px, px, cv::MORPH_CLOSE, ke, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
      cv::morphologyEx(px, px, cv::MORPH_OPEN, ke, cv::Point(-1, -1), 1, cv::BORDER_REPLICATE);
    } else {
      detail::closeOpenBinary(px, ke);
    }
    cv::bitwise_and(px, view(valid) != 0, px);
  }
  return px;
}

// The outer boundary among `contours` that holds most of the chosen block component (label `best`
// of the block `labels`; with one boundary, that one): the main part's index. With more than one,
// each boundary's score (the component's pixels it holds, plus 1e-3 × its area) goes in `scores`.
std::size_t mainPart(const std::vector<std::vector<cv::Point>>& contours, const cv::Mat& labels, int best,
                     const BlockGrid& g, std::vector<double>& scores) {
  std::size_t pick = 0;
  double pick_score = -1;
  cv::Mat core_px;
  if (contours.size() > 1) core_px = blockMaskPixels(labels == best, g);
  for (std::size_t i = 0; contours.size() > 1 && i < contours.size(); ++i) {
    const cv::Rect box = cv::boundingRect(contours[i]);
    cv::Mat both;
    cv::bitwise_and(filledInBox(contours, i, box), core_px(box), both);
    const double score = cv::countNonZero(both) + 1e-3 * cv::contourArea(contours[i]);
    scores[i] = score;
    if (score > pick_score) {
      pick_score = score;
      pick = i;
    }
  }
  return pick;
}

// Fills the holes of `out` (the filled outline: its pixels not in `px`, 4-connected) except those
// larger than `max_hole_fraction` of its area, which stay holes.
void keepLargeHoles(const cv::Mat& px, double max_hole_fraction, cv::Mat& out) {
  cv::Mat holes;
  cv::bitwise_and(out, ~px, holes);
  const double largest = max_hole_fraction * cv::countNonZero(out);
  // No hole is larger than all of them together: where they add up to no more (leaves, cracks,
  // slab gaps: most frames), every hole is filled and there are no components to label.
  if (!(cv::countNonZero(holes) > largest)) return;
  // Labelled within the holes' bounding box (the components are the same as over the frame).
  const cv::Rect box = cv::boundingRect(holes);
  cv::Mat hole_labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(holes(box), hole_labels, stats, centroids, 4, CV_32S);
  for (int v = 0; n > 1 && v < box.height; ++v) {
    const int* lab = hole_labels.ptr<int>(v);
    std::uint8_t* o = out.ptr<std::uint8_t>(box.y + v) + box.x;
    for (int u = 0; u < box.width; ++u)
      if (lab[u] > 0 && stats.at<int>(lab[u], cv::CC_STAT_AREA) > largest) o[u] = 0;
  }
}

}  // namespace

const OptionTable<RegionOptions>& regionOptionTable() {
  using O = RegionOptions;
  static const OptionTable<O> table =
      OptionTable<O>("RegionOptions")
          .field("block_size", &O::block_size, inRange(1, 256), "region reproduction: block side, pixels")
          .field("block_fraction", &O::block_fraction, aboveUpTo(0, 1),
                 "a block is road when at least this fraction of its pixels is")
          .field("morph_iterations", &O::morph_iterations, inRange(0, 10), "block-level closings then openings (3 x 3)")
          .field("refine_margin_blocks", &O::refine_margin_blocks, inRange(0, 10),
                 "pixel region may reach this many blocks beyond the block region")
          .field("pixel_morph_px", &O::pixel_morph_px, inRange(0, 50), "pixel-level closing then opening radius, pixels")
          .field("max_hole_fraction", &O::max_hole_fraction, inRange(0, 1),
                 "fill the region's holes up to this fraction of its area (leaves, cracks, slab gaps); larger "
                 "holes (a car on the road) stay out of the region; 0 = fill none, 1 = fill every hole")
          .field("min_part_fraction", &O::min_part_fraction, inRange(0, 1e6),
                 "where a line (a lane marking, a kerb) splits the road-coloured pixels inside the block region, "
                 "every part within two blocks of the main part holding at least this fraction of what the main "
                 "part holds of the block region joins the mask (the outline stays the main part's); above 1 = the "
                 "main part only")
          .field("reference", &O::reference, "OpenCV's morphology instead of the fast binary one (the same answer)");
  return table;
}

void RegionOptions::validate() const { regionOptionTable().validate(*this); }

Image rasterizePolygon(const Polygon2& ring, int width, int height) {
  cv::Mat m = cv::Mat::zeros(height, width, CV_8UC1);
  if (ring.size() >= 3) {
    std::vector<cv::Point> pts;
    pts.reserve(ring.size());
    for (const Vec2& p : ring) pts.emplace_back(cvRound(p.x()), cvRound(p.y()));
    cv::fillPoly(m, std::vector<std::vector<cv::Point>>{pts}, cv::Scalar(255), cv::LINE_8);
    cv::polylines(m, std::vector<std::vector<cv::Point>>{pts}, true, cv::Scalar(255), 1, cv::LINE_8);
  }
  return toImage(m);
}

RegionResult reproduceRegion(const Image& road_pixels, const Image& valid, const Image& predicted,
                             const RegionOptions& options) {
  options.validate();
  if (road_pixels.channels != 1 || valid.channels != 1 || road_pixels.width != valid.width ||
      road_pixels.height != valid.height)
    throw InvalidInput("reproduceRegion: road_pixels and valid must be 1-channel images of one size");
  const int w = road_pixels.width, h = road_pixels.height;
  RegionResult result;
  result.mask = Image(w, h, 1);
  if (w == 0 || h == 0) return result;

  cv::Mat road;
  cv::bitwise_and(view(road_pixels) != 0, view(valid) != 0, road);  // 0 / 255

  // 8 × 8 blocks with a proportion threshold.
  const int bs = options.block_size;
  const BlockGrid grid{w, h, bs, (w + bs - 1) / bs, (h + bs - 1) / bs};
  const cv::Mat blocks = roadBlocks(road, grid, options);

  // The connected component that is the road.
  cv::Mat labels;
  const int n = cv::connectedComponents(blocks, labels, 8, CV_32S);
  if (n <= 1) return result;
  const int best = roadComponent(labels, n, predicted, grid);
  cv::Mat chosen = labels == best;
  if (options.refine_margin_blocks > 0) {
    const int k = 2 * options.refine_margin_blocks + 1;
    cv::dilate(chosen, chosen, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)));
  }
  const cv::Mat allowed = blockMaskPixels(chosen, grid);

  // Pixel level inside the block region.
  const cv::Mat px = pixelRegion(road, allowed, valid, options);
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(px, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  if (contours.empty()) return result;
  // The outer boundary that holds most of the chosen block component (with one, that one): the main part.
  std::vector<double> scores(contours.size(), 0.0);
  const std::size_t pick = mainPart(contours, labels, best, grid, scores);
  cv::Mat out = cv::Mat::zeros(h, w, CV_8UC1);
  cv::drawContours(out, contours, static_cast<int>(pick), cv::Scalar(255), cv::FILLED);
  addSplitParts(contours, scores, pick, options.min_part_fraction, bs, out);
  // The holes larger than the fraction of the outline's area stay.
  if (options.max_hole_fraction < 1) keepLargeHoles(px, options.max_hole_fraction, out);
  result.mask = toImage(out);
  result.area_px = cv::countNonZero(out);
  result.found = result.area_px > 0;
  result.contour.reserve(contours[pick].size());
  for (const cv::Point& p : contours[pick]) result.contour.emplace_back(p.x, p.y);
  return result;
}

}  // namespace mapnav
