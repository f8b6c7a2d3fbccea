#include "libvdbappear/surface/patch_ndf.h"

#include <stdexcept>

namespace vdbappear {

std::vector<Vec3> patchMicroNormals(const HeightField& field, int i0, int j0, int count, int points_per_side) {
  if (count < 1 || points_per_side < 1 || i0 < 0 || j0 < 0 || i0 + count > field.cellsX() || j0 + count > field.cellsY())
    throw std::invalid_argument("patchMicroNormals: the patch leaves the height field");
  std::vector<Vec3> normals;
  normals.reserve(std::size_t(count) * count * points_per_side * points_per_side);
  for (int j = j0; j < j0 + count; ++j)
    for (int i = i0; i < i0 + count; ++i)
      for (int b = 0; b < points_per_side; ++b)
        for (int a = 0; a < points_per_side; ++a) {
          const Point2 g = field.gradient(i, j, (a + 0.5) / points_per_side, (b + 0.5) / points_per_side);
          normals.push_back(Vec3(-g.x(), -g.y(), 1).normalized());
        }
  return normals;
}

VmfMixture fitPatchNdf(const std::vector<Vec3>& micro_normals, const VmfFitSettings& settings) {
  std::vector<double> weights;
  weights.reserve(micro_normals.size());
  double mass = 0;  // E_p[1 / cos theta_m] = int D dw
  for (const Vec3& n : micro_normals) {
    weights.push_back(1 / n.z());
    mass += 1 / n.z();
  }
  mass /= double(micro_normals.size());
  VmfMixture ndf = fitVmfMixture(micro_normals, weights, settings);
  for (VmfLobe& lobe : ndf.lobes) lobe.amplitude *= mass;
  return ndf;
}

}  // namespace vdbappear
