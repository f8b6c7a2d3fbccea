#pragma once
// A height field as triangles for the renderer: the full-resolution reference of the displacement
// chapter (shared/papers/002_6a636dc24396287c.txt, §4.3, Table 4.3's tiling). Each bilinear cell
// becomes two triangles; their edges are the cell's, so each cell keeps the mean slope of Eq. (4.9).

#include "libvdbappear/image/rgb_image.h"
#include "libvdbappear/math/triangle.h"
#include "libvdbappear/surface/height_field.h"

#include <array>
#include <string>
#include <vector>

namespace vdbappear {

// The first channel of an image as heights: pixel (column c, row r from the top) is vertex
// (c, height - 1 - r), so the map reads upright seen from +z with x to the right and y up.
// An image of (n + 1) x (m + 1) pixels is a field of n x m cells of side cell_size.
// Throws MediumError naming `source` when the image is smaller than 2 x 2 or a height is not finite.
HeightField heightFieldFromImage(const RgbImage& image, double cell_size, const std::string& source);

struct HeightFieldPlacement {
  Vec3 origin = Vec3::Zero();  // where vertex (0, 0) of the first tile sits at height 0
  double height_scale = 1;     // world units per unit of the map
  int tiles_x = 1, tiles_y = 1;  // copies side by side along +x and +y (seamless when the edges match)
};

// The two triangles of cell (i, j) in cell units, vertex (i, j) at (i, j, h(i, j)) (exact integers,
// so that neighbouring cells and tiles share their vertices bit for bit once scaled):
// {p00, p10, p11} where x >= y within the cell, {p00, p11, p01} where x < y; both face +z.
std::array<Triangle, 2> cellTriangles(const HeightField& field, int i, int j);

// Vertex (i, j) of tile (a, b) at origin + ((a n + i) s, (b m + j) s, height_scale h(i, j)),
// s the cell size; the triangles face +z (counter-clockwise seen from above).
std::vector<Triangle> heightFieldTriangles(const HeightField& field, const HeightFieldPlacement& placement);

}  // namespace vdbappear
