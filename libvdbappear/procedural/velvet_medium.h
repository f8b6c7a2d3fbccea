#pragma once
// Velvet: dense, mostly upright pile fibers over a plain-weave base. The pile leans by a small
// common angle (the brushing direction, +x) plus a per-fiber random tilt. World units: yarn
// spacing 1; the base is one fabric layer centred on z = 0.5, the pile rises from that plane.

#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/math/vector.h"
#include "libvdbappear/procedural/fill_memory.h"

#include <cstdint>

namespace vdbappear {

struct VelvetParams {
  int resolution = 128;         // voxels along the largest side
  std::uint64_t seed = 1;
  int yarns = 4;                // base yarns per side: the patch is yarns x yarns world units
  double pile_height = 1.0;     // height of the pile tips above the base's mid-plane
  double pile_spacing = 0.03;   // pile fibers on a jittered grid of this spacing
  double pile_radius = 0.011;   // covers pi (0.011/0.03)^2 = 42% of the pile's cross-section
  double lean_degrees = 10;     // common lean toward +x
  double tilt_degrees = 8;      // per-fiber random tilt, uniform in a cone of this half-angle
  double pile_density = 60;     // rho inside a pile fiber
  double base_density = 40;     // rho inside a base fiber
  double roughness = 0.15;      // SGGX fiber roughness of pile and base
  Vec3 pile_albedo = Vec3(0.60, 0.06, 0.12);
  Vec3 base_albedo = Vec3(0.30, 0.05, 0.08);
  FillMemory memory;            // by default made whole in memory
};

MediumPtr makeVelvet(const VelvetParams& params);

}  // namespace vdbappear
