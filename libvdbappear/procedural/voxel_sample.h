#pragma once
// What one procedural voxel holds, before it is written into the medium's grids.

#include "libvdbappear/math/vector.h"

namespace vdbappear {

struct VoxelSample {
  float density = 0;
  Vec3 albedo = Vec3::Ones();
  Mat3 S = Mat3::Identity();  // written only when the medium has SGGX grids
  float hg_g = 0;             // written only when the medium has an hg_g grid
};

}  // namespace vdbappear
