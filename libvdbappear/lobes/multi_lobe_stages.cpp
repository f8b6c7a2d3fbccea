#include "libvdbappear/lobes/multi_lobe_stages.h"

#include "libvdbappear/downsample/naive_downsample.h"
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
#include <tuple>

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

std::string slotGridName(int j, const char* quantity) { return fmt::format("lobe{}_{}", j, quantity); }

// The grids of lobe slot j (docs/medium.md, section 5). They start with the coarse density's
// topology; where a voxel has no lobe in the slot, the slot's voxel is off in all four.
struct LobeSlotGrids {
  openvdb::Vec3SGrid::Ptr diag, offdiag, weight;
  openvdb::FloatGrid::Ptr fraction;

  static LobeSlotGrids made(const Medium& coarse, int j) {
    return {gridOverDensity<openvdb::Vec3SGrid>(coarse, slotGridName(j, "diag"), defaults::kSggxDiag),
            gridOverDensity<openvdb::Vec3SGrid>(coarse, slotGridName(j, "offdiag"), defaults::kSggxOffdiag),
            gridOverDensity<openvdb::Vec3SGrid>(coarse, slotGridName(j, "weight"), Vec3s(0.0f)),
            gridOverDensity<openvdb::FloatGrid>(coarse, slotGridName(j, "fraction"), 0.0f)};
  }
  // Those of a part that fitPart made.
  static LobeSlotGrids found(const Medium& fitted, int j) {
    LobeSlotGrids slot{findOtherGrid<openvdb::Vec3SGrid>(fitted, slotGridName(j, "diag")),
                       findOtherGrid<openvdb::Vec3SGrid>(fitted, slotGridName(j, "offdiag")),
                       findOtherGrid<openvdb::Vec3SGrid>(fitted, slotGridName(j, "weight")),
                       findOtherGrid<openvdb::FloatGrid>(fitted, slotGridName(j, "fraction"))};
    if (!slot.diag || !slot.offdiag || !slot.weight || !slot.fraction)
      throw std::logic_error(fmt::format("multi-lobe downsampling: a fitted part of {} without lobe slot {}", fitted.source, j));
    return slot;
  }
  // In the order the grids are written: diag, offdiag, fraction, weight.
  openvdb::GridPtrVec grids() const { return {diag, offdiag, fraction, weight}; }
};

std::vector<LobeSlotGrids> slotsOf(const Medium& fitted, int count) {
  std::vector<LobeSlotGrids> slots;
  for (int j = 0; j < count; ++j) slots.push_back(LobeSlotGrids::found(fitted, j));
  return slots;
}

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

// §5: every coarse voxel's lobes, in slots by decreasing fraction; weights are written later. The
// statistics of each coarse leaf, in the leaves' order.
std::vector<LobeFitStatistics> fitLobesOfEveryVoxel(const Medium& fine, const CoarseLeaves& coarse_leaves,
                                                    const MultiLobeOptions& options,
                                                    const std::vector<LobeSlotGrids>& slots, ProgressBar* progress) {
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
  return per_leaf;
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

// D of each lobe at the quadrature points (lobes with fraction 0 are skipped).
std::vector<NdfSamples> ndfOfLobes(const std::vector<SggxLobe>& lobes) {
  std::vector<NdfSamples> D;
  for (const SggxLobe& lobe : lobes)
    if (lobe.fraction > 0) D.push_back(sampleNdf(lobe.S));
  return D;
}

void checkOptions(const MultiLobeOptions& options) {
  if (options.factor < 2 || options.factor > kMaxDownsampleFactor)
    throw std::invalid_argument(fmt::format("downsampling factor {} outside 2..{}", options.factor, kMaxDownsampleFactor));
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

void checkFitInput(const Medium& fine) {
  checkFullResolution(fine);
  if (!fine.hasSggx())
    throw MediumError(fmt::format("{}: no 'sggx_diag' or 'sggx_offdiag' grid: every voxel has the same (isotropic) "
                                  "flakes, so there are no lobes to fit; vdb_sggx_downsample gives the naive medium",
                                  fine.source));
}

bool better(const ReferenceCandidate& a, const ReferenceCandidate& b) {
  if (a.lobes != b.lobes) return a.lobes > b.lobes;
  if (a.density != b.density) return a.density > b.density;
  return beforeInTreeOrder(a.ijk, b.ijk);
}

// §6.2's clustering input of every voxel of a fitted coarse part.
std::vector<Vec3> clusteringInputsOf(const Medium& coarse, const CoarseLeaves& coarse_leaves,
                                     const VoxelClusterOptions& options) {
  std::vector<Vec3> inputs;
  for (std::size_t i = 0; i < coarse_leaves.leafCount(); ++i) {
    const FloatLeaf& leaf = coarse_leaves.leaf(i);
    const LeafAlbedo albedo(coarse, leaf);
    for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel)
      inputs.push_back(clusteringInput(toVec3(albedo[voxel.pos()]), voxelKey(0, voxel.getCoord()), options));
  }
  return inputs;
}

// Drops the lobe and cluster grids of other_grids; appends those given, in order.
void replaceLobeGrids(Medium& medium, const openvdb::GridPtrVec& grids) {
  auto& other = medium.other_grids;
  other.erase(std::remove_if(other.begin(), other.end(),
                             [](const openvdb::GridBase::Ptr& g) {
                               return isLobeGridName(g->getName()) || g->getName() == grid_names::kCluster;
                             }),
              other.end());
  other.insert(other.end(), grids.begin(), grids.end());
}

}  // namespace

bool beforeInTreeOrder(const Coord& a, const Coord& b) {
  // The root's table is sorted by its children's origins; each internal node and leaf indexes its
  // children x-major (offset = x << 2 log2dim | y << log2dim | z), so per level the order is that of
  // the floored coordinates, coarsest level first: 4096^3, 128^3, 8^3, voxel.
  for (const int shift : {12, 7, 3, 0}) {
    const auto ka = std::make_tuple(a.x() >> shift, a.y() >> shift, a.z() >> shift);
    const auto kb = std::make_tuple(b.x() >> shift, b.y() >> shift, b.z() >> shift);
    if (ka != kb) return ka < kb;
  }
  return false;
}

MultiLobeStages::MultiLobeStages(const MultiLobeOptions& options)
    : options_(options),
      slot_count_(options.fit.forced_lobes > 0 ? options.fit.forced_lobes : options.fit.max_lobes) {
  checkOptions(options);
}

MediumPtr MultiLobeStages::coarsePart(const Medium& fine) {
  checkFitInput(fine);
  DownsampleResult naive = downsampleNaive(fine, {options_.factor, SggxWeighting::Count});
  for (const std::string& warning : naive.warnings)
    if (std::find(warnings_.begin(), warnings_.end(), warning) == warnings_.end()) warnings_.push_back(warning);
  return naive.medium;
}

void MultiLobeStages::fitPart(const Medium& fine, Medium& coarse, ProgressBar* progress) {
  std::vector<LobeSlotGrids> slots;
  for (int j = 0; j < slot_count_; ++j) slots.push_back(LobeSlotGrids::made(coarse, j));
  const CoarseLeaves coarse_leaves(coarse.density->tree());

  std::vector<LobeFitStatistics> statistics = fitLobesOfEveryVoxel(fine, coarse_leaves, options_, slots, progress);
  for (std::size_t i = 0; i < statistics.size(); ++i)
    leaf_statistics_.emplace_back(coarse_leaves.leaf(i).origin(), std::move(statistics[i]));
  std::vector<Vec3> inputs = clusteringInputsOf(coarse, coarse_leaves, options_.clustering);
  table_.add(inputs);

  openvdb::GridPtrVec grids;
  for (const LobeSlotGrids& slot : slots) {
    const openvdb::GridPtrVec four = slot.grids();
    grids.insert(grids.end(), four.begin(), four.end());
  }
  replaceLobeGrids(coarse, grids);
}

void MultiLobeStages::cluster() {
  DistinctAlbedoClusters clustering = clusterDistinctAlbedos(table_.albedo(), table_.voxels(), options_.clustering);
  label_ = std::move(clustering.label);
  clusters_.assign(clustering.centres.size(), VoxelCluster{});
  for (std::size_t c = 0; c < clusters_.size(); ++c) clusters_[c].albedo = clustering.centres[c];
  for (std::size_t i = 0; i < table_.size(); ++i) clusters_[label_[i]].voxels += std::uint64_t(table_.voxels()[i]);
  references_.assign(clusters_.size(), Reference{});
}

int MultiLobeStages::clusterOf(const Vec3s& albedo, const Coord& ijk) const {
  return label_[table_.find(clusteringInput(toVec3(albedo), voxelKey(0, ijk), options_.clustering))];
}

void MultiLobeStages::pickReferences(const Medium& fitted) {
  const std::vector<LobeSlotGrids> slots = slotsOf(fitted, slot_count_);
  for (auto leaf = fitted.density->tree().cbeginLeaf(); leaf; ++leaf) {
    const LeafAlbedo albedo(fitted, *leaf);
    const std::vector<SlotLeaves> slot_leaves = slotLeaves(slots, leaf->origin());
    for (auto voxel = leaf->cbeginValueOn(); voxel; ++voxel) {
      const Index n = voxel.pos();
      Reference& reference = references_[clusterOf(albedo[n], voxel.getCoord())];
      int lobes = 0;
      for (const SlotLeaves& slot : slot_leaves) lobes += slot.fraction->isValueOn(n);
      const ReferenceCandidate candidate{lobes, *voxel, voxel.getCoord()};
      if (!better(candidate, reference.voxel)) continue;
      reference.voxel = candidate;
      reference.ndfs = ndfOfLobes(readSlots(slot_leaves, n));
    }
  }
}

void MultiLobeStages::orderPart(Medium& coarse, ProgressBar* progress) const {
  for (std::size_t c = 0; c < references_.size(); ++c)
    if (references_[c].voxel.lobes == 0)
      throw std::logic_error(fmt::format("multi-lobe downsampling: cluster {} has no reference voxel", c));
  const std::vector<LobeSlotGrids> slots = slotsOf(coarse, slot_count_);
  auto cluster_grid = gridOverDensity<openvdb::Int32Grid>(coarse, grid_names::kCluster, 0);
  const CoarseLeaves coarse_leaves(coarse.density->tree());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, coarse_leaves.leafCount(), 1), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const FloatLeaf& leaf = coarse_leaves.leaf(i);
      const std::vector<SlotLeaves> out = slotLeaves(slots, leaf.origin());
      auto* ids = cluster_grid->tree().probeLeaf(leaf.origin());
      const LeafAlbedo albedo(coarse, leaf);
      for (auto voxel = leaf.cbeginValueOn(); voxel; ++voxel) {
        const Index n = voxel.pos();
        const int c = clusterOf(albedo[n], voxel.getCoord());  // §6.2
        ids->setValueOn(n, c);
        // Eq. (13) against the cluster's reference, then the naive weights (Eq. 11).
        std::vector<SggxLobe> lobes = readSlots(out, n);
        lobes.resize(lobesIn(lobes));  // fits fill slots 0..k-1
        const std::vector<int> slot = matchLobeSlots(references_[c].ndfs, ndfOfLobes(lobes));
        std::vector<SggxLobe> ordered(slots.size(), SggxLobe{Mat3::Identity(), 0.0});
        for (std::size_t j = 0; j < lobes.size(); ++j) ordered[slot[j]] = lobes[j];
        writeSlots(out, n, ordered, albedo[n]);
      }
      if (progress) progress->advance();
    }
  });
  openvdb::GridPtrVec grids;
  for (int j = 0, m = lobeCount(); j < m; ++j) {  // the slots no voxel uses are dropped
    const LobeSlotGrids& slot = slots[j];
    openvdb::tools::pruneInactive(slot.diag->tree());  // leaves with no voxel on become background tiles
    openvdb::tools::pruneInactive(slot.offdiag->tree());
    openvdb::tools::pruneInactive(slot.fraction->tree());
    openvdb::tools::pruneInactive(slot.weight->tree());
    const openvdb::GridPtrVec four = slot.grids();
    grids.insert(grids.end(), four.begin(), four.end());
  }
  grids.push_back(cluster_grid);
  replaceLobeGrids(coarse, grids);
}

int MultiLobeStages::lobeCount() const {
  int m = 0;
  for (const Reference& reference : references_) m = std::max(m, reference.voxel.lobes);
  return m;
}

MultiLobeResult MultiLobeStages::result(MediumPtr whole) const {
  MultiLobeResult result;
  result.medium = std::move(whole);
  result.warnings = warnings_;
  result.clusters = clusters_;
  for (std::size_t c = 0; c < clusters_.size(); ++c) {
    const Coord& ijk = references_[c].voxel.ijk;
    result.clusters[c].reference = {ijk.x(), ijk.y(), ijk.z()};
    result.clusters[c].reference_lobes = references_[c].voxel.lobes;
  }
  result.lobe_count = lobeCount();
  // The statistics summed leaf by leaf in the tree's order, whatever the parts were: the same sums.
  std::vector<const std::pair<Coord, LobeFitStatistics>*> leaves;
  for (const auto& leaf : leaf_statistics_) leaves.push_back(&leaf);
  std::sort(leaves.begin(), leaves.end(), [](const auto* a, const auto* b) { return beforeInTreeOrder(a->first, b->first); });
  result.statistics = emptyStatistics(slot_count_);
  for (const auto* leaf : leaves) addStatistics(leaf->second, result.statistics);

  Medium& coarse = *result.medium;
  coarse.metadata.insertMeta("lobe_count", openvdb::Int32Metadata(result.lobe_count));
  coarse.metadata.insertMeta("cluster_count", openvdb::Int32Metadata(int(clusters_.size())));
  if (int(clusters_.size()) < options_.clustering.clusters)
    result.warnings.push_back(fmt::format("{} clusters asked for, {} made: {}", options_.clustering.clusters,
                                          clusters_.size(),
                                          table_.size() < std::size_t(options_.clustering.clusters)
                                              ? fmt::format("the voxels hold only {} distinct albedos", table_.size())
                                              : std::string("K-means left a cluster empty")));
  return result;
}

}  // namespace vdbappear
