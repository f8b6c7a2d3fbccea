#include "libvdbappear/surface/height_field_mesh.h"

#include "libvdbappear/util/error.h"

#include <cmath>
#include <string>

namespace vdbappear {

HeightField heightFieldFromImage(const RgbImage& image, double cell_size, const std::string& source) {
  if (image.width < 2 || image.height < 2)
    throw MediumError(source + ": a height map needs at least 2 x 2 pixels (one cell), got " +
                      std::to_string(image.width) + " x " + std::to_string(image.height));
  HeightField field(image.width - 1, image.height - 1, cell_size);
  for (int r = 0; r < image.height; ++r)
    for (int c = 0; c < image.width; ++c) {
      const float h = image.at(c, r)[0];
      if (!std::isfinite(h))
        throw MediumError(source + ": height at pixel (column " + std::to_string(c) + ", row " + std::to_string(r) +
                          " from the top) is not a finite number");
      field.at(c, image.height - 1 - r) = h;
    }
  return field;
}

std::array<Triangle, 2> cellTriangles(const HeightField& field, int i, int j) {
  const auto vertex = [&](int a, int b) -> Vec3 { return Vec3(a, b, field.at(a, b)); };
  const Vec3 p00 = vertex(i, j), p10 = vertex(i + 1, j), p11 = vertex(i + 1, j + 1), p01 = vertex(i, j + 1);
  return {Triangle{p00, p10, p11}, Triangle{p00, p11, p01}};
}

std::vector<Triangle> heightFieldTriangles(const HeightField& field, const HeightFieldPlacement& placement) {
  std::vector<Triangle> triangles;
  triangles.reserve(std::size_t(2) * field.cellsX() * field.cellsY() * placement.tiles_x * placement.tiles_y);
  const double s = field.cellSize();
  for (int b = 0; b < placement.tiles_y; ++b)
    for (int a = 0; a < placement.tiles_x; ++a)
      for (int j = 0; j < field.cellsY(); ++j)
        for (int i = 0; i < field.cellsX(); ++i)
          for (Triangle t : cellTriangles(field, i, j)) {
            for (Vec3& v : t)
              v = placement.origin + Vec3((a * field.cellsX() + v.x()) * s, (b * field.cellsY() + v.y()) * s,
                                          placement.height_scale * v.z());
            triangles.push_back(t);
          }
  return triangles;
}

}  // namespace vdbappear
