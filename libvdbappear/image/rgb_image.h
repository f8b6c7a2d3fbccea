#pragma once
// A linear RGB float image, row-major, row 0 at the top.

#include <cstddef>
#include <vector>

namespace vdbappear {

struct RgbImage {
  RgbImage(int width, int height) : width(width), height(height), pixels(std::size_t(width) * height * 3, 0.0f) {}

  float* at(int x, int y) { return &pixels[(std::size_t(y) * width + x) * 3]; }
  const float* at(int x, int y) const { return &pixels[(std::size_t(y) * width + x) * 3]; }

  int width, height;
  std::vector<float> pixels;
};

}  // namespace vdbappear
