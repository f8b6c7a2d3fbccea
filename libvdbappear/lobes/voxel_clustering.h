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

// The albedo that voxel clustering sees for a voxel: its albedo plus its jitter, drawn from
// (options.seed, jitter_key) alone, so that a voxel's input does not depend on the order of the voxels
// or on the thread count. A zero is +0 (so that equal inputs are equal bits).
Vec3 clusteringInput(const Vec3& albedo, std::uint64_t jitter_key, const VoxelClusterOptions& options);

// K-means on distinct (jittered) albedos, each counted as often as voxels hold it: `albedo` sorted
// lexicographically with no value twice, count[i] > 0. label[i] is albedo[i]'s cluster. A table of
// distinct albedos gathered over parts of a medium in any order gives the clusters of the whole.
struct DistinctAlbedoClusters {
  std::vector<int> label;
  std::vector<Vec3> centres;  // by increasing channel sum (then channels), as VoxelClustering's
};
DistinctAlbedoClusters clusterDistinctAlbedos(const std::vector<Vec3>& albedo, const std::vector<double>& count,
                                              const VoxelClusterOptions& options);

// Voxel i has albedo[i]; its jitter is drawn from (seed, jitter_key[i]) alone (give each voxel a
// key of its own, e.g. a hash of its coordinate), so a voxel's cluster input does not depend on the
// order of the voxels or the thread count. Fewer than K clusters come out when the (jittered)
// albedos hold fewer distinct values, or (rarely) when K-means leaves a cluster empty.
VoxelClustering clusterVoxels(const std::vector<Vec3>& albedo, const std::vector<std::uint64_t>& jitter_key,
                              const VoxelClusterOptions& options);

}  // namespace vdbappear
