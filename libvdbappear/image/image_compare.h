#pragma once
// Comparing a render with a reference: mean intensities (the brightening of Fig. 1, downsampling
// paper), RMSE, and a false-colour map of the signed relative error per pixel.

#include "libvdbappear/image/rgb_image.h"

#include <vector>

namespace vdbappear {

struct ImageComparison {
  double mean_reference = 0, mean_test = 0;  // mean over pixels of (R + G + B) / 3
  double mean_relative_error = 0;            // (mean_test - mean_reference) / mean_reference
  double rmse = 0;                           // over pixels and channels
  double relative_rmse = 0;                  // rmse / mean_reference
  double max_abs_error = 0;
  // max over pixels of |test - ref| / max(|ref|, |mean_reference|), channel means: the worst pixel
  // (the worst tile, on tileMeans), relative to itself where brighter than the mean and to the mean
  // where darker, so that a dim pixel's noise does not dominate.
  double worst_relative_error = 0;
};

// Throws std::invalid_argument when the sizes differ. With a mask (one flag per pixel), only the
// pixels it marks count: the foreground of the paper's mean pixel intensity (§6.3).
void checkSameSize(const RgbImage& a, const RgbImage& b);  // std::invalid_argument when they differ

ImageComparison compareImages(const RgbImage& reference, const RgbImage& test, const std::vector<bool>& mask = {});

// Signed relative error (test - ref) / max(ref, 1% of the reference mean) per pixel (channel mean),
// as colours: blue where the test is darker by `range` or more, white where equal, red where
// brighter by `range` or more. Stored linear, so that the sRGB file shows those colours.
RgbImage relativeErrorMap(const RgbImage& reference, const RgbImage& test, double range);

// The image averaged over tile x tile blocks (a remainder at the right and bottom edges is
// dropped; 1 <= tile <= width and height), and a mask of the tiles whose pixels are mostly (> half) in `mask`. Comparing tile
// means measures the appearance at the scale of a tile, with less Monte Carlo noise per value.
RgbImage tileMeans(const RgbImage& image, int tile);
std::vector<bool> tileMask(const std::vector<bool>& mask, int width, int height, int tile);

// Images of equal height placed left to right with a gap of `gap` black pixels.
RgbImage sideBySide(const std::vector<const RgbImage*>& images, int gap = 4);

}  // namespace vdbappear
