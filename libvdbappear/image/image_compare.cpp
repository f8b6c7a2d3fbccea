#include "libvdbappear/image/image_compare.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {

namespace {

double pixelMean(const RgbImage& image, std::size_t i) {
  return (double(image.pixels[3 * i]) + image.pixels[3 * i + 1] + image.pixels[3 * i + 2]) / 3;
}

double srgbToLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

}  // namespace

void checkSameSize(const RgbImage& a, const RgbImage& b) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                                " and " + std::to_string(b.width) + "x" + std::to_string(b.height));
}

ImageComparison compareImages(const RgbImage& reference, const RgbImage& test, const std::vector<bool>& mask) {
  checkSameSize(reference, test);
  ImageComparison c;
  const std::size_t all = std::size_t(reference.width) * reference.height;
  if (!mask.empty() && mask.size() != all) throw std::invalid_argument("mask and image differ in size");
  std::size_t pixels = 0;
  for (std::size_t i = 0; i < all; ++i) pixels += mask.empty() || mask[i];
  if (pixels == 0) throw std::invalid_argument("the mask selects no pixel");
  double squares = 0;
  for (std::size_t i = 0; i < all; ++i) {
    if (!mask.empty() && !mask[i]) continue;
    c.mean_reference += pixelMean(reference, i) / pixels;
    c.mean_test += pixelMean(test, i) / pixels;
    for (int k = 0; k < 3; ++k) {
      const double e = double(test.pixels[3 * i + k]) - reference.pixels[3 * i + k];
      squares += e * e;
      c.max_abs_error = std::max(c.max_abs_error, std::abs(e));
    }
  }
  c.rmse = std::sqrt(squares / (3.0 * pixels));
  const double floor = std::abs(c.mean_reference);
  for (std::size_t i = 0; i < all; ++i) {
    if (!mask.empty() && !mask[i]) continue;
    const double ref = pixelMean(reference, i), scale = std::max(std::abs(ref), floor);
    if (scale > 0) c.worst_relative_error = std::max(c.worst_relative_error, std::abs(pixelMean(test, i) - ref) / scale);
  }
  c.mean_relative_error = c.mean_reference != 0 ? (c.mean_test - c.mean_reference) / c.mean_reference : 0;
  c.relative_rmse = c.mean_reference != 0 ? c.rmse / std::abs(c.mean_reference) : 0;
  return c;
}

RgbImage relativeErrorMap(const RgbImage& reference, const RgbImage& test, double range) {
  checkSameSize(reference, test);
  const double floor = 0.01 * std::abs(compareImages(reference, reference).mean_reference) + 1e-12;
  RgbImage map(reference.width, reference.height);
  for (std::size_t i = 0; i < std::size_t(reference.width) * reference.height; ++i) {
    const double ref = pixelMean(reference, i);
    const double e = std::clamp((pixelMean(test, i) - ref) / std::max(std::abs(ref), floor) / range, -1.0, 1.0);
    // Diverging blue - white - red, in display (sRGB) values.
    const double r = e < 0 ? 1 + e : 1, g = 1 - std::abs(e), b = e > 0 ? 1 - e : 1;
    map.pixels[3 * i] = float(srgbToLinear(r));
    map.pixels[3 * i + 1] = float(srgbToLinear(g));
    map.pixels[3 * i + 2] = float(srgbToLinear(b));
  }
  return map;
}

RgbImage tileMeans(const RgbImage& image, int tile) {
  if (tile < 1) throw std::invalid_argument("tile size below 1");
  if (tile > image.width || tile > image.height)
    throw std::invalid_argument("tile size " + std::to_string(tile) + " larger than the image");
  RgbImage out(image.width / tile, image.height / tile);
  std::vector<double> row(std::size_t(out.width) * 3);
  for (int ty = 0; ty < out.height; ++ty) {
    std::fill(row.begin(), row.end(), 0.0);
    for (int y = ty * tile; y < (ty + 1) * tile; ++y)
      for (int x = 0; x < out.width * tile; ++x)
        for (int c = 0; c < 3; ++c) row[std::size_t(x / tile) * 3 + c] += image.at(x, y)[c];
    for (std::size_t k = 0; k < row.size(); ++k) out.at(0, ty)[k] = float(row[k] / (double(tile) * tile));
  }
  return out;
}

std::vector<bool> tileMask(const std::vector<bool>& mask, int width, int height, int tile) {
  if (tile < 1) throw std::invalid_argument("tile size below 1");
  if (mask.empty()) return {};
  const int w = width / tile, h = height / tile;
  std::vector<int> count(std::size_t(w) * h, 0);
  for (int y = 0; y < h * tile; ++y)
    for (int x = 0; x < w * tile; ++x) count[std::size_t(y / tile) * w + x / tile] += mask[std::size_t(y) * width + x];
  std::vector<bool> out(count.size());
  for (std::size_t i = 0; i < count.size(); ++i) out[i] = 2 * count[i] > tile * tile;
  return out;
}

RgbImage sideBySide(const std::vector<const RgbImage*>& images, int gap) {
  int width = 0;
  for (const RgbImage* image : images) {
    if (image->height != images.front()->height) throw std::invalid_argument("side by side: heights differ");
    width += image->width;
  }
  width += gap * int(images.size() - 1);
  RgbImage out(width, images.front()->height);
  int x0 = 0;
  for (const RgbImage* image : images) {
    for (int y = 0; y < image->height; ++y)
      std::copy(image->at(0, y), image->at(0, y) + 3 * image->width, out.at(x0, y));
    x0 += image->width + gap;
  }
  return out;
}

}  // namespace vdbappear
