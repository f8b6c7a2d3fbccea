#include "libvdbappear/downsample/naive_downsample.h"

#include "libvdbappear/downsample/coarse_transform.h"
#include "libvdbappear/downsample/emission_downsample.h"
#include "libvdbappear/io/leaf_values.h"
#include "libvdbappear/io/medium_block.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/math/block_index.h"
#include "libvdbappear/util/error.h"
#include "libvdbappear/util/progress.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>
#include <optional>

namespace vdbappear {

namespace {

using openvdb::Coord;
using openvdb::Index;
using openvdb::Vec3s;
using FloatLeaf = openvdb::FloatTree::LeafNodeType;

constexpr int kLeafDim = FloatLeaf::DIM;          // 8 voxels per leaf edge
constexpr Index kLeafVoxels = FloatLeaf::SIZE;    // 512

Coord scaled(const Coord& c, int s) { return Coord(c.x() * s, c.y() * s, c.z() * s); }

// Sums over the children of the 512 voxels of one coarse leaf (double precision).
struct CoarseLeafSums {
  std::array<double, kLeafVoxels> density{};                  // sum rho
  std::array<std::array<double, 3>, kLeafVoxels> albedo{};    // sum rho * albedo
  std::array<std::array<double, 6>, kLeafVoxels> S{};         // sum w * S (xx yy zz xy xz yz)
  std::array<double, kLeafVoxels> S_weight{};                 // sum w
  std::array<double, kLeafVoxels> g_scatter{}, scatter{};     // sum sigma_s * g, sum sigma_s
  std::array<double, kLeafVoxels> g_density{};                // sum rho * g

  void clear() { std::memset(static_cast<void*>(this), 0, sizeof(*this)); }  // all doubles: zero bits are 0.0
};

// The fine values of one 8^3 block, every base grid; absent grids read as the contract's defaults
// (albedo 1, S = I, g = 0): their sums are computed but not written.
struct FineBlock {
  LeafValues<openvdb::FloatTree> density;
  LeafValues<openvdb::Vec3STree> albedo, sggx_diag, sggx_offdiag;
  LeafValues<openvdb::FloatTree> hg_g;
};

class NaiveDownsampler {
 public:
  NaiveDownsampler(const Medium& fine, const DownsampleOptions& options)
      : fine_(fine), factor_(options.factor), weighting_(options.s_weighting) {
    for (int i = 0; i < kLeafDim * factor_; ++i) coarse_local_[i] = i / factor_;
  }

  // Coarse leaf origins covered by the fine density's active values, sorted and unique.
  std::vector<Coord> coarseLeafOrigins() const;

  // Accessors to the fine grids, one set per task (they cache tree paths and are not thread-safe).
  struct Accessors {
    openvdb::FloatGrid::ConstAccessor density;
    std::optional<openvdb::Vec3SGrid::ConstAccessor> albedo, sggx_diag, sggx_offdiag;
    std::optional<openvdb::FloatGrid::ConstAccessor> hg_g;
  };
  Accessors accessors() const;

  // One coarse leaf at `origin`, built into `out` (left empty when none of its voxels is active).
  void buildLeaf(const Coord& origin, Accessors& acc, CoarseLeafSums& sums, const Medium& coarse,
                 MediumBlock& out) const;

 private:
  static FineBlock fineBlock(Accessors& acc, const Coord& origin, const LeafValues<openvdb::FloatTree>& density);
  void accumulateBlock(Accessors& acc, const Coord& fine_origin, const Coord& block_index,
                       CoarseLeafSums& sums) const;
  void accumulateVoxel(const FineBlock& fine, Index n, float rho, Index coarse, CoarseLeafSums& sums) const;
  void finish(const Coord& origin, const CoarseLeafSums& sums, const Medium& coarse, MediumBlock& out) const;

  const Medium& fine_;
  int factor_;
  SggxWeighting weighting_;
  std::array<int, kLeafDim * kMaxDownsampleFactor> coarse_local_{};  // fine coordinate in a coarse leaf -> coarse
};

std::vector<Coord> NaiveDownsampler::coarseLeafOrigins() const {
  const int span = kLeafDim * factor_;  // fine voxels per coarse leaf edge
  std::vector<Coord> origins;
  const auto& tree = fine_.density->tree();
  origins.reserve(tree.leafCount());
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf)
    origins.push_back(scaled(blockOf(leaf->origin(), Coord(span)), kLeafDim));
  auto tile = tree.cbeginValueOn();
  tile.setMaxDepth(openvdb::FloatTree::ValueOnCIter::LEAF_DEPTH - 1);  // tiles only
  for (; tile; ++tile) {
    openvdb::CoordBBox box;
    tile.getBoundingBox(box);
    const Coord lo = blockOf(box.min(), Coord(span)), hi = blockOf(box.max(), Coord(span));
    for (int x = lo.x(); x <= hi.x(); ++x)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int z = lo.z(); z <= hi.z(); ++z) origins.push_back(scaled(Coord(x, y, z), kLeafDim));
  }
  std::sort(origins.begin(), origins.end());
  origins.erase(std::unique(origins.begin(), origins.end()), origins.end());
  return origins;
}

NaiveDownsampler::Accessors NaiveDownsampler::accessors() const {
  Accessors acc{fine_.density->getConstAccessor(), {}, {}, {}, {}};
  if (fine_.albedo) acc.albedo.emplace(fine_.albedo->getConstAccessor());
  if (fine_.sggx_diag) acc.sggx_diag.emplace(fine_.sggx_diag->getConstAccessor());
  if (fine_.sggx_offdiag) acc.sggx_offdiag.emplace(fine_.sggx_offdiag->getConstAccessor());
  if (fine_.hg_g) acc.hg_g.emplace(fine_.hg_g->getConstAccessor());
  return acc;
}

void NaiveDownsampler::buildLeaf(const Coord& origin, Accessors& acc, CoarseLeafSums& sums, const Medium& coarse,
                                 MediumBlock& out) const {
  sums.clear();
  const Coord fine_origin = scaled(origin, factor_);  // a multiple of 8: exactly F^3 fine leaves
  for (int a = 0; a < factor_; ++a)
    for (int b = 0; b < factor_; ++b)
      for (int c = 0; c < factor_; ++c)
        accumulateBlock(acc, fine_origin + scaled(Coord(a, b, c), kLeafDim), Coord(a, b, c), sums);
  finish(origin, sums, coarse, out);
}

FineBlock NaiveDownsampler::fineBlock(Accessors& acc, const Coord& origin,
                                      const LeafValues<openvdb::FloatTree>& density) {
  using V1 = LeafValues<openvdb::FloatTree>;
  using V3 = LeafValues<openvdb::Vec3STree>;
  return {density, acc.albedo ? V3(*acc.albedo, origin) : V3(defaults::kAlbedo),
          acc.sggx_diag ? V3(*acc.sggx_diag, origin) : V3(defaults::kSggxDiag),
          acc.sggx_offdiag ? V3(*acc.sggx_offdiag, origin) : V3(defaults::kSggxOffdiag),
          acc.hg_g ? V1(*acc.hg_g, origin) : V1(defaults::kHgG)};
}

void NaiveDownsampler::accumulateBlock(Accessors& acc, const Coord& fine_origin, const Coord& block_index,
                                       CoarseLeafSums& sums) const {
  const LeafValues<openvdb::FloatTree> density(acc.density, fine_origin);
  if (density.empty()) return;
  const FineBlock fine = fineBlock(acc, fine_origin, density);
  const int* to_coarse_x = &coarse_local_[block_index.x() * kLeafDim];
  const int* to_coarse_y = &coarse_local_[block_index.y() * kLeafDim];
  const int* to_coarse_z = &coarse_local_[block_index.z() * kLeafDim];
  auto visit = [&](Index n, float rho) {
    const Index coarse =
        FloatLeaf::coordToOffset(Coord(to_coarse_x[n >> 6], to_coarse_y[(n >> 3) & 7], to_coarse_z[n & 7]));
    accumulateVoxel(fine, n, rho, coarse, sums);
  };
  if (const FloatLeaf* leaf = fine.density.leaf()) {
    for (auto it = leaf->cbeginValueOn(); it; ++it) visit(it.pos(), *it);
  } else {  // an active tile covers the block
    for (Index n = 0; n < kLeafVoxels; ++n) visit(n, fine.density.constant());
  }
}

void NaiveDownsampler::accumulateVoxel(const FineBlock& fine, Index n, float rho, Index coarse,
                                       CoarseLeafSums& sums) const {
  if (rho <= 0) return;  // empty children count as 0 in every sum
  sums.density[coarse] += rho;
  const Vec3s a = fine.albedo[n], d = fine.sggx_diag[n], o = fine.sggx_offdiag[n];
  const double w = weighting_ == SggxWeighting::Count ? 1.0 : double(rho);
  auto& S = sums.S[coarse];
  for (int c = 0; c < 3; ++c) {
    sums.albedo[coarse][c] += double(rho) * a[c];
    S[c] += w * d[c];
    S[3 + c] += w * o[c];
  }
  sums.S_weight[coarse] += w;
  const double g = fine.hg_g[n], sigma_s = double(rho) * (double(a[0]) + a[1] + a[2]) / 3;
  sums.g_scatter[coarse] += sigma_s * g;
  sums.scatter[coarse] += sigma_s;
  sums.g_density[coarse] += double(rho) * g;
}

void NaiveDownsampler::finish(const Coord& origin, const CoarseLeafSums& sums, const Medium& coarse,
                              MediumBlock& out) const {
  const double children = double(factor_) * factor_ * factor_;
  for (Index n = 0; n < kLeafVoxels; ++n) {
    const double rho_sum = sums.density[n];
    if (rho_sum <= 0) continue;
    if (out.empty()) out.allocate(coarse, origin);
    const auto& a = sums.albedo[n];
    const auto& S = sums.S[n];
    const double w = sums.S_weight[n];
    const double g = sums.scatter[n] > 0 ? sums.g_scatter[n] / sums.scatter[n] : sums.g_density[n] / rho_sum;
    out.setVoxel(n, float(rho_sum / children),                                                          // Eq. (6), left
                 Vec3s(float(a[0] / rho_sum), float(a[1] / rho_sum), float(a[2] / rho_sum)),            // Eq. (6), right
                 Vec3s(float(S[0] / w), float(S[1] / w), float(S[2] / w)),                              // Eq. (5)
                 Vec3s(float(S[3] / w), float(S[4] / w), float(S[5] / w)), float(g));
  }
}

bool isMultiLobeOrClusterGrid(const std::string& name) {
  return isLobeGridName(name) || name == grid_names::kCluster || name == grid_names::kPhaseId;
}

// Grids other than the base grids: pass the phase table and the block-indexed exemplar grids
// through, average the emission (the blackbody light made into emission), refuse what cannot be
// averaged.
void carryOtherGrids(const Medium& fine, int factor, const openvdb::math::Transform::Ptr& transform, Medium& coarse,
                     std::vector<std::string>& warnings) {
  if (auto emission = downsampleEmission(fine, factor, transform)) coarse.other_grids.push_back(emission);
  for (const auto& grid : fine.other_grids) {
    const std::string name = grid->getName();
    if (name == grid_names::kEmission || name == grid_names::kBlackbodyTemperature) {
      continue;  // made into the coarse emission above
    } else if (name == grid_names::kPhaseTable || isBlockIndexedGridName(name)) {  // not indexed by voxel
      auto copy = grid->deepCopyGrid();
      copy->setTransform(transform);
      coarse.other_grids.push_back(copy);
    } else if (isMultiLobeOrClusterGrid(name)) {
      throw MediumError(fmt::format("{}: grid '{}': naive downsampling cannot average multi-lobe, cluster or "
                                    "phase_id grids; downsample the full-resolution medium instead",
                                    fine.source, name));
    } else {
      warnings.push_back(fmt::format("dropped grid '{}': not part of the medium contract, so it was not downsampled",
                                     name));
    }
  }
}

// exemplar_block counts the fine medium's voxels: say so, once (docs/medium.md, section 6b).
void pinExemplarVoxelSize(const Medium& fine, Medium& coarse) {
  if (!fine.metadata[metadata_names::kExemplarBlock] || fine.metadata[metadata_names::kExemplarVoxelSize]) return;
  coarse.metadata.insertMeta(metadata_names::kExemplarVoxelSize, openvdb::Vec3DMetadata(fine.transform().voxelSize()));
}

}  // namespace

DownsampleResult downsampleNaive(const Medium& fine, const DownsampleOptions& options, ProgressBar* progress) {
  if (options.factor < 2 || options.factor > kMaxDownsampleFactor)
    throw std::invalid_argument(fmt::format("downsampling factor {} outside 2..{}", options.factor, kMaxDownsampleFactor));
  const auto transform = coarseTransform(fine.transform(), options.factor, fine.source);

  DownsampleResult result;
  const MediumPtr coarse = makeEmptyMedium({bool(fine.albedo), fine.hasSggx(), bool(fine.hg_g)}, transform);
  coarse->metadata = fine.metadata;
  pinExemplarVoxelSize(fine, *coarse);
  coarse->source = fine.source;
  carryOtherGrids(fine, options.factor, transform, *coarse, result.warnings);

  const NaiveDownsampler downsampler(fine, options);
  const std::vector<Coord> origins = downsampler.coarseLeafOrigins();
  std::vector<MediumBlock> leaves(origins.size());
  if (progress) progress->setTotal(origins.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, origins.size(), 16), [&](const auto& range) {
    auto sums = std::make_unique<CoarseLeafSums>();
    auto accessors = downsampler.accessors();
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      downsampler.buildLeaf(origins[i], accessors, *sums, *coarse, leaves[i]);
    if (progress) progress->advance(range.size());
  });
  for (auto& leaf : leaves) leaf.adoptInto(*coarse);
  result.medium = coarse;
  return result;
}

}  // namespace vdbappear
