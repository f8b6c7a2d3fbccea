#pragma once
// Height maps as image files (docs/displacement.md §1): the first channel, (n + 1) x (m + 1) pixels
// for n x m bilinear cells, pixel (column c, row r from the top) = vertex (c, m - r).

#include "libvdbappear/image/image_file.h"
#include "libvdbappear/surface/height_field.h"

#include <string>

namespace vdbappear {

// One channel "Y": the heights divided by height_scale.
ImageChannels heightMapImage(const HeightField& field, double height_scale = 1);
// As a 32-bit float EXR, atomically.
void writeHeightMap(const HeightField& field, const std::string& path, double height_scale = 1);
// In world units: a map `size` wide, heights times height_scale. Throws MediumError naming the file
// (and the pixel of a height that is not finite).
HeightField readHeightMap(const std::string& path, double size = 1, double height_scale = 1);

}  // namespace vdbappear
