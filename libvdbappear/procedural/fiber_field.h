#pragma once
// A field of fibers (yarns of a weave, velvet pile, fur): what fiber, if any, passes through a point.
// sampleFiberVoxel() turns it into voxels: density from supersampled fiber occupancy, S from the
// fiber tangent (fiber-like SGGX: flake normals perpendicular to the fiber).

#include "libvdbappear/math/vector.h"
#include "libvdbappear/procedural/voxel_sample.h"

#include <optional>

namespace vdbappear {

// The fiber at a point: its unit tangent and material.
struct FiberPoint {
  Vec3 tangent;
  Vec3 albedo;
  double density;    // flake density rho inside the fiber, 1/world unit
  double roughness;  // SGGX fiber roughness: S has eigenvalue roughness^2 along the fiber
};

class FiberField {
 public:
  virtual ~FiberField() = default;
  // Must be thread-safe and deterministic.
  virtual std::optional<FiberPoint> fiberAt(const Vec3& p) const = 0;
};

// Supersamples the cube of side `voxel_size` around `centre` on an n^3 grid: density is the mean
// of the fiber densities over the subsamples (0 outside fibers); S and albedo are those of the hit
// nearest the centre. Nullopt when no subsample lies in a fiber.
std::optional<VoxelSample> sampleFiberVoxel(const FiberField& field, const Vec3& centre, double voxel_size,
                                            int supersample = 2);

}  // namespace vdbappear
