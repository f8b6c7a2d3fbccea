#pragma once
// Voxel clustering (§6.2 of the downsampling paper): K-means on the downsampled albedos, so that
// one set of lobe-weight factors serves every voxel of a cluster (Eq. 12). Optional jitter of the
// albedos blurs cluster boundaries where albedo varies smoothly, against seams (Fig. 12).
// Light header: Eigen only.

#include "libvdbappear/math/vector.h"

#include <cstdint>
#include <vector>

namespace vdbappear {

struct VoxelClusterOptions {
  int clusters = 1;     // K
  double jitter = 0;    // standard deviation of the Gaussian added to each albedo channel
  std::uint64_t seed = 0;
};

struct VoxelClustering {
  std::vector<int> cluster;   // per voxel, in 0..centres.size()-1
  std::vector<Vec3> centres;  // the clusters' mean (jittered) albedos, by increasing channel sum
  std::size_t distinct_albedos = 0;  // distinct (jittered) albedos among the voxels
};

// Voxel i has albedo[i]; its jitter is drawn from (seed, jitter_key[i]) alone (give each voxel a
// key of its own, e.g. a hash of its coordinate), so a voxel's cluster input does not depend on the
// order of the voxels or the thread count. Fewer than K clusters come out when the (jittered)
// albedos hold fewer distinct values, or (rarely) when K-means leaves a cluster empty.
VoxelClustering clusterVoxels(const std::vector<Vec3>& albedo, const std::vector<std::uint64_t>& jitter_key,
                              const VoxelClusterOptions& options);

}  // namespace vdbappear
