#pragma once
// A plain-weave fabric of twisted fibers: warp yarns along x, weft yarns along y, crossing over and
// under, each yarn a bundle of helical fibers. Density comes from fiber occupancy (2x2x2
// supersampled), S from the local fiber tangent (fiber-like SGGX), albedo from the yarn set, so
// warp and weft can carry different colours. Layers stack along z. Geometry is in world units
// (yarn spacing 1) and does not change with the resolution.

#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/math/vector.h"

#include <cstdint>

namespace vdbappear {

struct WeaveParams {
  int resolution = 128;          // voxels along the largest side
  std::uint64_t seed = 1;        // fiber placement and per-fiber colour jitter
  int yarns = 4;                 // warp and weft yarns per side
  int layers = 1;                // fabric layers, one world unit apart along z
  double fiber_density = 40;     // rho inside a fiber, 1/world unit
  double roughness = 0.1;        // SGGX fiber roughness: eigenvalue roughness^2 along the fiber
  Vec3 warp_albedo = Vec3(0.85, 0.30, 0.20);
  Vec3 weft_albedo = Vec3(0.25, 0.40, 0.85);
};

MediumPtr makePlainWeave(const WeaveParams& params);

}  // namespace vdbappear
