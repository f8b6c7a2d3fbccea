#include "support/image_footprint.h"

#include "libvdbappear/image/image_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace vdbappear::test {

Footprint footprintOf(const std::string& exr) {
  const ImageChannels image = readImageChannels(exr);
  const int alpha = image.find("A");
  EXPECT_GE(alpha, 0);
  const std::size_t stride = image.names.size();
  auto at = [&](int x, int y, int c) {
    return double(image.values[(std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * stride + std::size_t(c)]);
  };
  auto luminance = [&](int x, int y) { return (at(x, y, 0) + at(x, y, 1) + at(x, y, 2)) / 3; };
  double inside = 0, n_inside = 0, outside = 0, n_outside = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const bool in = at(x, y, alpha) > 0.5;
      (in ? inside : outside) += luminance(x, y);
      (in ? n_inside : n_outside) += 1;
    }
  Footprint f;
  f.coverage = n_inside / (n_inside + n_outside);
  if (n_inside == 0 || n_outside == 0) return f;
  f.contrast = std::abs(inside / n_inside - outside / n_outside) / (outside / n_outside);
  std::vector<double> tiles;
  for (int ty = 0; ty + 4 <= image.height; ty += 4)
    for (int tx = 0; tx + 4 <= image.width; tx += 4) {
      double sum = 0;
      bool all_inside = true;
      for (int y = ty; y < ty + 4; ++y)
        for (int x = tx; x < tx + 4; ++x) {
          all_inside = all_inside && at(x, y, alpha) > 0.5;
          sum += luminance(x, y);
        }
      if (all_inside) tiles.push_back(sum / 16);
    }
  if (tiles.size() < 2) return f;
  double mean = 0, var = 0;
  for (double t : tiles) mean += t / double(tiles.size());
  for (double t : tiles) var += (t - mean) * (t - mean) / double(tiles.size() - 1);
  f.structure = std::sqrt(var) / mean;
  return f;
}

}  // namespace vdbappear::test
