#include "libvdbappear/lobes/multi_lobe_downsample.h"

#include "libvdbappear/downsample/naive_downsample.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/lobes/lobe_order.h"
#include "libvdbappear/math/sggx.h"
#include "libvdbappear/util/error.h"
#include "libvdbappear/util/hash_random.h"
#include "libvdbappear/util/progress.h"

#include <fmt/format.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace vdbappear {

namespace {

using openvdb::Coord;
using openvdb::Index;
using openvdb::Vec3s;
using FloatLeaf = openvdb::FloatTree::LeafNodeType;
using Vec3sLeaf = openvdb::Vec3STree::LeafNodeType;
using CoarseLeaves = openvdb::tree::LeafManager<const openvdb::FloatTree>;

std::uint64_t voxelKey(std::uint64_t seed, const Coord& ijk) { return hashKeys(seed, {ijk.x(), ijk.y(), ijk.z()}); }

template <typename GridT>
typename GridT::Ptr gridOverDensity(const Medium& coarse, const std::string& name,
                                    const typename GridT::ValueType& background) {
  auto grid = GridT::create(background);
  grid->setName(name);
  grid->setTransform(coarse.density->transformPtr());
  grid->tree().topologyUnion(coarse.density->tree());
  return grid;
}

// The grids of lobe slot j (docs/medium.md, section 5). They start with the coarse density's
// topology; where a voxel has no lobe in the slot, the slot's voxel is off in all four.
struct LobeSlotGrids {
  openvdb::Vec3SGrid::Ptr diag, offdiag, weight;
  openvdb::FloatGrid::Ptr fraction;

  LobeSlotGrids(const Medium& coarse, int j)
      : diag(gridOverDensity<openvdb::Vec3SGrid>(coarse, fmt::format("lobe{}_diag", j), defaults::kSggxDiag)),
        offdiag(gridOverDensity<openvdb::Vec3SGrid>(coarse, fmt::format("lobe{}_offdiag", j), defaults::kSggxOffdiag)),
        weight(gridOverDensity<openvdb::Vec3SGrid>(coarse, fmt::format("lobe{}_weight", j), Vec3s(0.0f))),
        fraction(gridOverDensity<openvdb::FloatGrid>(coarse, fmt::format("lobe{}_fraction", j), 0.0f)) {}
};

// One leaf of every slot's grids at one origin. Leaves of distinct origins may be written by
// distinct threads at once.
struct SlotLeaves {
  Vec3sLeaf *diag, *offdiag, *weight;
  FloatLeaf* fraction;
};

std::vector<SlotLeaves> slotLeaves(const std::vector<LobeSlotGrids>& slots, const Coord& origin) {
  std::vector<SlotLeaves> leaves;
  for (const LobeSlotGrids& slot : slots)
    leaves.push_back({slot.diag->tree().probeLeaf(origin), slot.offdiag->tree().probeLeaf(origin),
                      slot.weight->tree().probeLeaf(origin), slot.fraction->tree().probeLeaf(origin)});
  return leaves;
}

// The lobes in a voxel's slots, fraction 0 where a slot is empty.
std::vector<SggxLobe> readSlots(const std::vector<SlotLeaves>& leaves, Index n) {
  std::vector<SggxLobe> lobes(leaves.size(), SggxLobe{Mat3::Identity(), 0.0});
  for (std::size_t j = 0; j < leaves.size(); ++j)
    if (leaves[j].fraction->isValueOn(n))
      lobes[j] = {sggxMatrix(toVec3(leaves[j].diag->getValue(n)), toVec3(leaves[j].offdiag->getValue(n))),
                  leaves[j].fraction->getValue(n)};
  return lobes;
}

// Writes lobes[j] into slot j (off where its fraction is 0), with weight albedo * fraction (Eq. 11).
void writeSlots(const std::vector<SlotLeaves>& leaves, Index n, const std::vector<SggxLobe>& lobes, const Vec3s& albedo) {
  for (std::size_t j = 0; j < leaves.size(); ++j) {
    const SlotLeaves& leaf = leaves[j];
    if (j < lobes.size() && lobes[j].fraction > 0) {
      const float fraction = float(lobes[j].fraction);
      leaf.diag->setValueOn(n, toVec3s(sggxDiagonal(lobes[j].S)));
      leaf.offdiag->setValueOn(n, toVec3s(sggxOffDiagonal(lobes[j].S)));
      leaf.fraction->setValueOn(n, fraction);
      leaf.weight->setValueOn(n, albedo * fraction);  // Eq. (11): W_ij = albedo_i |V(i,j)| / |V(i)|
    } else {
      leaf.diag->setValueOff(n, defaults::kSggxDiag);
      leaf.offdiag->setValueOff(n, defaults::kSggxOffdiag);
      leaf.fraction->setValueOff(n, 0.0f);
      leaf.weight->setValueOff(n, Vec3s(0.0f));
    }
  }
}

int lobesIn(const std::vector<SggxLobe>& slots) {
  return int(std::count_if(slots.begin(), slots.end(), [](const SggxLobe& l) { return l.fraction > 0; }));
}

// The fine grids around one coarse voxel: the S of its children with density > 0 (the set V(i)
// of Eq. 5, the same children downsampleNaive averages).
class Children {
 public:
  Children(const Medium& fine, int factor) : density_(fine.density->getConstAccessor()), factor_(factor) {
    if (fine.sggx_diag) diag_.emplace(fine.sggx_diag->getConstAccessor());
    if (fine.sggx_offdiag) offdiag_.emplace(fine.sggx_offdiag->getConstAccessor());
  }

  std::vector<Mat3> sggxOf(const Coord& coarse) {
    std::vector<Mat3> S;
    const Coord base(coarse.x() * factor_, coarse.y() * factor_, coarse.z() * factor_);
    for (int a = 0; a < factor_; ++a)
      for (int b = 0; b < factor_; ++b)
        for (int c = 0; c < factor_; ++c) {
          const Coord ijk = base.offsetBy(a, b, c);
          float rho = 0;
          if (!density_.probeValue(ijk, rho) || !(rho > 0)) continue;
          S.push_back(sggxMatrix(toVec3(diag_ ? diag_->getValue(ijk) : defaults::kSggxDiag),
                                 toVec3(offdiag_ ? offdiag_->getValue(ijk) : defaults::kSggxOffdiag)));
        }
    return S;
  }

 private:
  openvdb::FloatGrid::ConstAccessor density_;
  std::optional<openvdb::Vec3SGrid::ConstAccessor> diag_, offdiag_;
  int factor_;
};

void addFit(const LobeFit& fit, LobeFitStatistics& stats) {
  stats.voxels += 1;
  stats.voxels_exact_with_one_lobe += fit.error_by_lobes[0] == 0;
  stats.voxels_with_lobes[fit.lobes.size() - 1] += 1;
  for (std::size_t m = 0; m < stats.squared_error.size(); ++m) {
    const double e = fit.error_by_lobes[std::min(m, fit.error_by_lobes.size() - 1)];
    stats.squared_error[m] += e * e;
  }
  stats.squared_target += fit.target_norm * fit.target_norm;
}

void addStatistics(const LobeFitStatistics& part, LobeFitStatistics& total) {
  total.voxels += part.voxels;
  total.voxels_exact_with_one_lobe += part.voxels_exact_with_one_lobe;
  for (std::size_t m = 0; m < total.squared_error.size(); ++m) {
    total.voxels_with_lobes[m] += part.voxels_with_lobes[m];
    total.squared_error[m] += part.squared_error[m];
  }
  total.squared_target += part.squared_target;
}

LobeFitStatistics emptyStatistics(int slots) {
  LobeFitStatistics stats;
  stats.voxels_with_lobes.assign(slots, 0);
  stats.squared_error.assign(slots, 0.0);
  return stats;
}

// §5: every coarse voxel's lobes, in slots by decreasing fraction; weights are written later.
LobeFitStatistics fitLobesOfEveryVoxel(const Medium& fine, const CoarseLeaves& coarse_leaves,
                                       const MultiLobeOptions& options, const std::vector<LobeSlotGrids>& slots,
                                       ProgressBar* progress) {
  const std::size_t leaf_count = coarse_leaves.leafCount();
  std::vector<LobeFitStatistics> per_leaf(leaf_count, emptyStatistics(int(slots.size())));
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaf_count, 1), [&](const auto& range) {
    Children children(fine, options.factor);
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const FloatLeaf& leaf = coarse_leaves.leaf(i);
      const std::vector<SlotLeaves> out = slotLeaves(slots, leaf.origin());
      for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
        const std::vector<Mat3> S = children.sggxOf(voxel.getCoord());
        if (S.empty()) throw std::logic_error("multi-lobe downsampling: an occupied coarse voxel without children");
        const LobeFit fit = fitLobes(S, options.fit, voxelKey(options.clustering.seed, voxel.getCoord()));
        writeSlots(out, voxel.pos(), fit.lobes, Vec3s(0.0f));
        addFit(fit, per_leaf[i]);
      }
      if (progress) progress->advance();
    }
  });
  LobeFitStatistics total = emptyStatistics(int(slots.size()));
  for (const LobeFitStatistics& part : per_leaf) addStatistics(part, total);  // in leaf order: deterministic
  return total;
}

// The coarse albedo of one leaf's voxels (the contract's default where the medium has none).
class LeafAlbedo {
 public:
  LeafAlbedo(const Medium& coarse, const FloatLeaf& leaf)
      : leaf_(coarse.albedo ? coarse.albedo->tree().probeConstLeaf(leaf.origin()) : nullptr) {}
  Vec3s operator[](Index n) const { return leaf_ ? leaf_->getValue(n) : defaults::kAlbedo; }

 private:
  const Vec3sLeaf* leaf_;  // downsampleNaive writes an albedo leaf wherever a density leaf is
};

// §6.2: K-means on the downsampled albedos; writes the cluster grid.
VoxelClustering clusterByAlbedo(const Medium& coarse, const CoarseLeaves& coarse_leaves,
                                const VoxelClusterOptions& options, openvdb::Int32Grid& cluster_grid) {
  std::vector<Vec3> albedo;
  std::vector<std::uint64_t> key;
  for (std::size_t i = 0; i < coarse_leaves.leafCount(); ++i) {
    const FloatLeaf& leaf = coarse_leaves.leaf(i);
    const LeafAlbedo leaf_albedo(coarse, leaf);
    for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
      albedo.push_back(toVec3(leaf_albedo[voxel.pos()]));
      key.push_back(voxelKey(0, voxel.getCoord()));
    }
  }
  VoxelClustering clustering = clusterVoxels(albedo, key, options);
  std::size_t k = 0;
  for (std::size_t i = 0; i < coarse_leaves.leafCount(); ++i) {
    const FloatLeaf& leaf = coarse_leaves.leaf(i);
    auto* ids = cluster_grid.tree().probeLeaf(leaf.origin());
    for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) ids->setValueOn(voxel.pos(), clustering.cluster[k++]);
  }
  return clustering;
}

// Eq. (13)'s reference voxel of each cluster (the paper's "arbitrary voxel"): one with the most
// lobes, so that every voxel's lobes find slots; among those the densest (the most mass, so the
// largest share of the cluster's look); then the first in tree order.
std::vector<VoxelCluster> pickReferences(const CoarseLeaves& coarse_leaves, const VoxelClustering& clustering,
                                         const openvdb::Int32Grid& cluster_grid, const std::vector<LobeSlotGrids>& slots) {
  std::vector<VoxelCluster> clusters(clustering.centres.size());
  std::vector<float> reference_density(clusters.size(), -1.0f);
  for (std::size_t c = 0; c < clusters.size(); ++c) clusters[c].albedo = clustering.centres[c];
  for (std::size_t i = 0; i < coarse_leaves.leafCount(); ++i) {
    const FloatLeaf& leaf = coarse_leaves.leaf(i);
    const std::vector<SlotLeaves> slot_leaves = slotLeaves(slots, leaf.origin());
    const auto* ids = cluster_grid.tree().probeConstLeaf(leaf.origin());
    for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
      const int c = ids->getValue(voxel.pos());
      VoxelCluster& cluster = clusters[c];
      cluster.voxels += 1;
      int lobes = 0;
      for (const SlotLeaves& slot : slot_leaves) lobes += slot.fraction->isValueOn(voxel.pos());
      if (lobes > cluster.reference_lobes || (lobes == cluster.reference_lobes && *voxel > reference_density[c])) {
        const Coord ijk = voxel.getCoord();
        cluster.reference = {ijk.x(), ijk.y(), ijk.z()};
        cluster.reference_lobes = lobes;
        reference_density[c] = *voxel;
      }
    }
  }
  return clusters;
}

// D of each lobe at the quadrature points (lobes with fraction 0 are skipped).
std::vector<NdfSamples> ndfOfLobes(const std::vector<SggxLobe>& lobes) {
  std::vector<NdfSamples> D;
  for (const SggxLobe& lobe : lobes)
    if (lobe.fraction > 0) D.push_back(sampleNdf(lobe.S));
  return D;
}

// Eq. (13) in every cluster, then the naive weights (Eq. 11) of the ordered lobes.
void orderLobesAndWeigh(const Medium& coarse, const CoarseLeaves& coarse_leaves, const openvdb::Int32Grid& cluster_grid,
                        const std::vector<VoxelCluster>& clusters, const std::vector<LobeSlotGrids>& slots,
                        ProgressBar* progress) {
  std::vector<std::vector<NdfSamples>> reference;
  for (const VoxelCluster& cluster : clusters) {
    const Coord ijk(cluster.reference[0], cluster.reference[1], cluster.reference[2]);
    const FloatLeaf* leaf = coarse.density->tree().probeConstLeaf(ijk);
    reference.push_back(ndfOfLobes(readSlots(slotLeaves(slots, leaf->origin()), FloatLeaf::coordToOffset(ijk))));
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, coarse_leaves.leafCount(), 1), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const FloatLeaf& leaf = coarse_leaves.leaf(i);
      const std::vector<SlotLeaves> out = slotLeaves(slots, leaf.origin());
      const auto* ids = cluster_grid.tree().probeConstLeaf(leaf.origin());
      const LeafAlbedo albedo(coarse, leaf);
      for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
        const Index n = voxel.pos();
        std::vector<SggxLobe> lobes = readSlots(out, n);
        lobes.resize(lobesIn(lobes));  // fits fill slots 0..k-1
        const std::vector<int> slot = matchLobeSlots(reference[ids->getValue(n)], ndfOfLobes(lobes));
        std::vector<SggxLobe> ordered(slots.size(), SggxLobe{Mat3::Identity(), 0.0});
        for (std::size_t j = 0; j < lobes.size(); ++j) ordered[slot[j]] = lobes[j];
        writeSlots(out, n, ordered, albedo[n]);
      }
      if (progress) progress->advance();
    }
  });
}

void checkOptions(const MultiLobeOptions& options) {
  const LobeFitOptions& fit = options.fit;
  if (fit.max_lobes < 1 || fit.max_lobes > kMaxOrderedLobes || fit.forced_lobes < 0 || fit.forced_lobes > kMaxOrderedLobes)
    throw std::invalid_argument(fmt::format("lobe count outside 1..{}", kMaxOrderedLobes));
  if (options.clustering.clusters < 1) throw std::invalid_argument("cluster count below 1");
  if (!(options.clustering.jitter >= 0)) throw std::invalid_argument("negative or NaN cluster jitter");
}

// A medium that already has lobes or clusters is a result of this function, not an input to it.
void checkFullResolution(const Medium& fine) {
  for (const auto& grid : fine.other_grids) {
    const std::string name = grid->getName();
    if (isLobeGridName(name) || name == grid_names::kCluster)
      throw MediumError(fmt::format("{}: grid '{}': the medium is already multi-lobe; fit lobes to the "
                                    "full-resolution medium instead", fine.source, name));
  }
}

}  // namespace

double LobeFitStatistics::relativeError(int m) const {
  return squared_target > 0 ? std::sqrt(squared_error.at(m - 1) / squared_target) : 0.0;
}

int LobeFitStatistics::ruleLobeCount(double keep_ratio) const {
  int m = 1;
  while (m < int(squared_error.size()) && squared_error[m - 1] > 0 &&
         std::sqrt(squared_error[m]) <= keep_ratio * std::sqrt(squared_error[m - 1]))
    ++m;
  return m;
}

MultiLobeResult downsampleMultiLobe(const Medium& fine, const MultiLobeOptions& options, ProgressBar* progress) {
  checkOptions(options);
  checkFullResolution(fine);
  if (!fine.hasSggx())
    throw MediumError(fmt::format("{}: no 'sggx_diag' or 'sggx_offdiag' grid: every voxel has the same (isotropic) "
                                  "flakes, so there are no lobes to fit; vdb_sggx_downsample gives the naive medium",
                                  fine.source));
  DownsampleResult naive = downsampleNaive(fine, {options.factor, SggxWeighting::Count});
  MultiLobeResult result;
  result.medium = naive.medium;
  result.warnings = std::move(naive.warnings);
  Medium& coarse = *result.medium;

  const int slot_count = options.fit.forced_lobes > 0 ? options.fit.forced_lobes : options.fit.max_lobes;
  std::vector<LobeSlotGrids> slots;
  for (int j = 0; j < slot_count; ++j) slots.emplace_back(coarse, j);
  auto cluster_grid = gridOverDensity<openvdb::Int32Grid>(coarse, grid_names::kCluster, 0);

  const CoarseLeaves coarse_leaves(coarse.density->tree());
  if (progress) progress->setTotal(2 * coarse_leaves.leafCount());
  result.statistics = fitLobesOfEveryVoxel(fine, coarse_leaves, options, slots, progress);
  const VoxelClustering clustering = clusterByAlbedo(coarse, coarse_leaves, options.clustering, *cluster_grid);
  result.clusters = pickReferences(coarse_leaves, clustering, *cluster_grid, slots);
  orderLobesAndWeigh(coarse, coarse_leaves, *cluster_grid, result.clusters, slots, progress);

  for (const VoxelCluster& cluster : result.clusters) result.lobe_count = std::max(result.lobe_count, cluster.reference_lobes);
  slots.erase(slots.begin() + result.lobe_count, slots.end());  // slots no voxel uses
  for (const LobeSlotGrids& slot : slots) {  // leaves with no voxel on become background tiles
    openvdb::tools::pruneInactive(slot.diag->tree());
    openvdb::tools::pruneInactive(slot.offdiag->tree());
    openvdb::tools::pruneInactive(slot.fraction->tree());
    openvdb::tools::pruneInactive(slot.weight->tree());
    coarse.other_grids.insert(coarse.other_grids.end(), {slot.diag, slot.offdiag, slot.fraction, slot.weight});
  }
  coarse.other_grids.push_back(cluster_grid);
  coarse.metadata.insertMeta("lobe_count", openvdb::Int32Metadata(result.lobe_count));
  coarse.metadata.insertMeta("cluster_count", openvdb::Int32Metadata(int(result.clusters.size())));
  if (int(result.clusters.size()) < options.clustering.clusters)
    result.warnings.push_back(fmt::format("{} clusters asked for, {} made: {}", options.clustering.clusters,
                                          result.clusters.size(),
                                          clustering.distinct_albedos < std::size_t(options.clustering.clusters)
                                              ? fmt::format("the voxels hold only {} distinct albedos", clustering.distinct_albedos)
                                              : std::string("K-means left a cluster empty")));
  return result;
}

}  // namespace vdbappear
