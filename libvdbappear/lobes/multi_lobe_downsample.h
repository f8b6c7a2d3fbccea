#pragma once
// The multi-lobe downsampled medium (§5 and §6.2 of the downsampling paper), as vdb_lobe_cluster
// writes it: the naive base grids (Eq. 5-6, count-weighted S), per coarse voxel the SGGX lobes of
// its children (Eq. 10) with naive lobe weights W_ij = albedo_i * fraction_ij (Eq. 11), a voxel
// clustering on albedo, and each cluster's lobes ordered against a reference voxel (Eq. 13).
// Grids and metadata: docs/medium.md, section 5. Light header: no OpenVDB.

#include "libvdbappear/io/medium_file.h"
#include "libvdbappear/lobes/lobe_fit.h"
#include "libvdbappear/lobes/voxel_clustering.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace vdbappear {

class ProgressBar;

struct MultiLobeOptions {
  int factor = 2;                  // F, as for downsampleNaive
  LobeFitOptions fit;              // lobe count rule (§8.1) or forced m
  VoxelClusterOptions clustering;  // K, jitter; its seed also seeds the lobe fits (per voxel)
};

// The fit errors over the whole medium, for the error-against-m report (Fig. 16).
struct LobeFitStatistics {
  std::uint64_t voxels = 0;                      // occupied coarse voxels
  std::uint64_t voxels_exact_with_one_lobe = 0;  // one lobe fits with error 0 (the children share one S)
  std::vector<std::uint64_t> voxels_with_lobes;  // [m-1]: voxels fitted with m lobes
  // [m-1]: sum over voxels of the squared fit error with m lobes (lobeFitError). A voxel whose
  // children hold fewer than m distinct S counts with its exact fit.
  std::vector<double> squared_error;
  double squared_target = 0;  // sum over voxels of the squared norm of the children's mean D

  // sqrt(squared_error / squared_target): the error of the whole medium with m lobes, relative.
  double relativeError(int m) const;
  // The §8.1 rule applied to the whole medium's errors: the m it picks.
  int ruleLobeCount(double keep_ratio) const;
};

struct VoxelCluster {
  Vec3 albedo;                         // the K-means centre
  std::uint64_t voxels = 0;
  std::array<int, 3> reference{};      // the voxel whose lobe order the others follow (Eq. 13)
  int reference_lobes = 0;
};

struct MultiLobeResult {
  MediumPtr medium;
  std::vector<std::string> warnings;
  LobeFitStatistics statistics;
  std::vector<VoxelCluster> clusters;
  int lobe_count = 0;  // m: lobe grids 0..m-1 (metadata lobe_count)
};

// Throws MediumError for media that cannot be downsampled (as downsampleNaive), that have no SGGX
// grids (nothing to fit) or that already have lobe or cluster grids, and
// std::invalid_argument for options out of range (max or forced lobes above kMaxOrderedLobes).
MultiLobeResult downsampleMultiLobe(const Medium& fine, const MultiLobeOptions& options,
                                   ProgressBar* progress = nullptr);

}  // namespace vdbappear
