#pragma once
// Random sparse media for tests and fuzzing: random active topology (negative coordinates
// included), densities with exact zeros, RGB albedo, and random SPD S from near-isotropic to
// near-degenerate fibers and flakes. Deterministic under the seed.

#include "libvdbappear/io/medium_file.h"

#include <cstdint>

namespace vdbappear {

struct RandomMediumParams {
  int extent = 48;              // voxels per side of an index box centred on the origin
  std::uint64_t seed = 1;
  double block_fill = 0.5;      // fraction of 8^3 blocks that hold active voxels
  double voxel_fill = 0.6;      // fraction of active voxels in such a block
  double zero_density = 0.1;    // fraction of active voxels whose density is exactly 0
  double max_density = 10;      // density is uniform in (0, max_density]
  double min_eigenvalue = 1e-3; // eigenvalues of S are log-uniform in [min_eigenvalue, 1]
  double voxel_size = 0.1;
  bool albedo = true;
  bool sggx = true;
  bool hg_g = false;
};

MediumPtr makeRandomMedium(const RandomMediumParams& params);

}  // namespace vdbappear
