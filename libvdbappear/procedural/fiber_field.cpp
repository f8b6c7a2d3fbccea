#include "libvdbappear/procedural/fiber_field.h"

#include "libvdbappear/math/sggx.h"

#include <limits>

namespace vdbappear {

std::optional<VoxelSample> sampleFiberVoxel(const FiberField& field, const Vec3& centre, double voxel_size,
                                            int supersample) {
  const double step = voxel_size / supersample;
  const double first = -0.5 * voxel_size + 0.5 * step;
  double density_sum = 0, nearest = std::numeric_limits<double>::infinity();
  std::optional<FiberPoint> chosen;
  for (int i = 0; i < supersample; ++i)
    for (int j = 0; j < supersample; ++j)
      for (int k = 0; k < supersample; ++k) {
        const Vec3 offset(first + i * step, first + j * step, first + k * step);
        const std::optional<FiberPoint> fiber = field.fiberAt(centre + offset);
        if (!fiber) continue;
        density_sum += fiber->density;
        if (offset.squaredNorm() < nearest) {
          nearest = offset.squaredNorm();
          chosen = fiber;
        }
      }
  if (!chosen) return std::nullopt;
  VoxelSample voxel;
  voxel.density = float(density_sum / (supersample * supersample * supersample));
  voxel.albedo = chosen->albedo;
  voxel.S = Sggx::fiberMatrix(chosen->tangent, chosen->roughness);
  return voxel;
}

}  // namespace vdbappear
