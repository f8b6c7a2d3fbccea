#pragma once
// downsampleMultiLobe (lobes/multi_lobe_downsample.h) in stages over parts of a medium, so that a
// medium read in slabs of whole coarse leaves (lobes/streamed_multi_lobe.h) gives the whole read's
// result bit for bit, and the whole read is the same stages on one part:
//   1. coarsePart then fitPart, on each part of the fine medium: its naive coarse part (Eq. 5-6) and
//      every coarse voxel's lobes (§5, Eq. 10), unordered and unweighted; it keeps each coarse
//      leaf's fit statistics and adds the part's (jittered) albedos to a table of distinct albedos;
//   2. cluster, once every part is fitted: K-means on that table (§6.2);
//   3. pickReferences, on each fitted part: each cluster's reference voxel (Eq. 13's "arbitrary
//      voxel") and its lobes;
//   4. orderPart, on each fitted part: the cluster grid, each voxel's lobes ordered against its
//      cluster's reference (Eq. 13) and weighed (Eq. 11), the slots no voxel uses dropped;
//   5. result, on the whole of the ordered parts.
// Everything global (K-means' input, the references, the statistics' sums) is gathered in a form that
// does not depend on the parts' order or the thread count. Internal header: includes OpenVDB.

#include "libvdbappear/io/medium.h"
#include "libvdbappear/lobes/distinct_albedo_table.h"
#include "libvdbappear/lobes/multi_lobe_downsample.h"
#include "libvdbappear/lobes/ndf_quadrature.h"

#include <openvdb/openvdb.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace vdbappear {

class ProgressBar;

// A coarse voxel as a reference for its cluster: the one with the most lobes (so that every voxel's
// lobes find slots), among those the densest (the largest share of the cluster's look), then the
// first in the tree's order.
struct ReferenceCandidate {
  int lobes = 0;
  float density = -1.0f;
  openvdb::Coord ijk;
};

class MultiLobeStages {
 public:
  // Throws std::invalid_argument for options out of range (the factor included).
  explicit MultiLobeStages(const MultiLobeOptions& options);

  // The lobe slots every part gets (the forced lobe count, or the cap), each four grids (lobe{j}_*).
  int slotCount() const { return slot_count_; }

  // 1. The naive coarse part (count-weighted S). Throws MediumError as downsampleNaive does, for a
  // medium without SGGX grids and for one that already has lobes or clusters.
  MediumPtr coarsePart(const Medium& fine_part);
  // Adds lobe slot grids lobe{j}_* for every slot the options allow to the coarse part, with every
  // voxel's lobes fitted to its children in the fine part. `progress` advances once per coarse leaf.
  void fitPart(const Medium& fine_part, Medium& coarse_part, ProgressBar* progress = nullptr);

  // 2. After the last fitPart.
  void cluster();

  // 3. After cluster(), on every fitted part, in any order.
  void pickReferences(const Medium& fitted_part);

  // 4. After pickReferences on every part. `progress` advances once per coarse leaf.
  void orderPart(Medium& fitted_part, ProgressBar* progress = nullptr) const;

  // 5. The whole of the ordered parts with its metadata (lobe_count, cluster_count), the fit
  // statistics summed in the tree's order, the clusters and the warnings.
  MultiLobeResult result(MediumPtr whole) const;

  // The bytes of the distinct-albedo table, and its size.
  std::uint64_t tableBytes() const { return table_.bytes(); }
  std::size_t distinctAlbedos() const { return table_.size(); }

 private:
  MultiLobeOptions options_;
  int slot_count_;
  std::vector<std::string> warnings_;
  std::vector<std::pair<openvdb::Coord, LobeFitStatistics>> leaf_statistics_;  // per coarse leaf, by origin
  DistinctAlbedoTable table_;
  // After cluster():
  std::vector<int> label_;  // each table entry's cluster
  std::vector<VoxelCluster> clusters_;
  struct Reference {
    ReferenceCandidate voxel;
    std::vector<NdfSamples> ndfs;  // of its lobes
  };
  std::vector<Reference> references_;  // per cluster

  int clusterOf(const openvdb::Vec3s& albedo, const openvdb::Coord& ijk) const;
  int lobeCount() const;  // m: the most lobes of a reference
};

// Whether coarse coordinate a comes before b in an OpenVDB tree (5-4-3) of any grid: by root node
// (lexicographically), then by child index in each internal node, then by voxel offset in the leaf.
bool beforeInTreeOrder(const openvdb::Coord& a, const openvdb::Coord& b);

}  // namespace vdbappear
