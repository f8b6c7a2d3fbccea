#include "libvdbappear/medium/majorant_grid.h"

#include "libvdbappear/io/leaf_values.h"
#include "libvdbappear/io/medium.h"
#include "libvdbappear/math/block_index.h"
#include "libvdbappear/math/sggx.h"
#include "libvdbappear/medium/compact_attributes.h"

#include <Eigen/Eigenvalues>
#include <openvdb/tree/LeafManager.h>
#include <tbb/parallel_for.h>

#include <array>
#include <optional>
#include <stdexcept>
#include <vector>

namespace vdbappear {

Interpolation parseInterpolation(const std::string& name) {
  if (name == "nearest") return Interpolation::kNearest;
  if (name == "trilinear") return Interpolation::kTrilinear;
  throw std::invalid_argument("interpolation '" + name + "': expected nearest or trilinear");
}

const char* interpolationName(Interpolation interpolation) {
  return interpolation == Interpolation::kNearest ? "nearest" : "trilinear";
}

namespace {

double largestEigenvalue(const Mat3& S) {
  Eigen::SelfAdjointEigenSolver<Mat3> solver;
  solver.computeDirect(S, Eigen::EigenvaluesOnly);
  // computeDirect is accurate to a few ulps relative to the norm; pad so the bound stays a bound.
  return solver.eigenvalues().maxCoeff() * (1 + 1e-6) + 1e-12 * S.norm();
}

double largestEigenvalue(const openvdb::Vec3s& diag, const openvdb::Vec3s& offdiag) {
  return largestEigenvalue(sggxMatrix(Vec3(diag[0], diag[1], diag[2]), Vec3(offdiag[0], offdiag[1], offdiag[2])));
}

// Where S comes from: the medium's SGGX grids, or a compact medium's records.
struct SggxSource {
  const Medium& medium;
  const CompactAttributes* records;
  bool anisotropic() const { return medium.hasSggx() || (records && records->hasSggx()); }
};

struct LeafBound {
  float max_rho_sqrt_lambda = 0;  // the nearest-lookup bound (with_lambda only)
  float max_rho = 0;              // > 0: the block holds density
};

constexpr int kBlocksPerLeafAxis = 8 / kMajorantBlock;
constexpr int kBlocksPerLeaf = kBlocksPerLeafAxis * kBlocksPerLeafAxis * kBlocksPerLeafAxis;
using LeafBounds = std::array<LeafBound, kBlocksPerLeaf>;

// The bounds of the majorant blocks of one 8^3 leaf of density (a leaf, or part of a tile).
// with_lambda: compute the nearest-lookup bound (trilinear lookups bound their grown blocks later,
// and only need to know which blocks hold density).
LeafBounds boundsOfLeaf(const SggxSource& sggx, const openvdb::Coord& origin, bool with_lambda) {
  const Medium& medium = sggx.medium;
  std::optional<CompactAttributes::Accessor> records;
  if (sggx.records) records.emplace(*sggx.records);
  const LeafValues<openvdb::FloatTree> rho(medium.density->tree(), origin);
  const auto diag = medium.sggx_diag ? LeafValues<openvdb::Vec3STree>(medium.sggx_diag->tree(), origin)
                                     : LeafValues<openvdb::Vec3STree>(openvdb::Vec3s(1.0f));
  const auto offdiag = medium.sggx_offdiag ? LeafValues<openvdb::Vec3STree>(medium.sggx_offdiag->tree(), origin)
                                           : LeafValues<openvdb::Vec3STree>(openvdb::Vec3s(0.0f));
  LeafBounds bounds;
  const auto* leaf = rho.leaf();  // null for a tile: all voxels active
  for (openvdb::Index i = 0; i < openvdb::FloatTree::LeafNodeType::SIZE; ++i) {
    const double r = rho[i];
    if (!(r > 0) || (leaf && !leaf->isValueOn(i))) continue;  // inactive voxels are empty space
    const double lambda = !with_lambda || !sggx.anisotropic() ? 1.0
                          : records ? largestEigenvalueOf(records->at(*leaf, i)) * (1 + 1e-6)  // a compact medium has no tiles
                                    : largestEigenvalue(diag[i], offdiag[i]);
    // Leaf offsets are x-major: i = 64 x + 8 y + z.
    const int x = int(i >> 6) / kMajorantBlock, y = int((i >> 3) & 7) / kMajorantBlock, z = int(i & 7) / kMajorantBlock;
    LeafBound& bound = bounds[(x * kBlocksPerLeafAxis + y) * kBlocksPerLeafAxis + z];
    bound.max_rho_sqrt_lambda = std::max(bound.max_rho_sqrt_lambda, float(r * std::sqrt(lambda) * (1 + 1e-6)));
    bound.max_rho = std::max(bound.max_rho, float(r));
  }
  return bounds;
}

// The origins of every 8^3 block that holds density: leaves, and the blocks of active tiles.
std::vector<openvdb::Coord> densityBlocks(const openvdb::FloatTree& tree) {
  std::vector<openvdb::Coord> origins;
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) origins.push_back(leaf->origin());
  for (auto tile = tree.cbeginValueOn(); tile; ++tile) {
    if (tile.isVoxelValue()) continue;
    const openvdb::CoordBBox box = tile.getBoundingBox();
    for (int x = box.min().x(); x <= box.max().x(); x += 8)
      for (int y = box.min().y(); y <= box.max().y(); y += 8)
        for (int z = box.min().z(); z <= box.max().z(); z += 8) origins.emplace_back(x, y, z);
  }
  return origins;
}

}  // namespace

namespace {

openvdb::FloatGrid::Ptr buildExtinctionMajorant(const SggxSource& sggx, Interpolation interpolation) {
  const Medium& medium = sggx.medium;
  const std::vector<openvdb::Coord> origins = densityBlocks(medium.density->tree());
  std::vector<LeafBounds> leaf_bounds(origins.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, origins.size(), 16), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) leaf_bounds[i] = boundsOfLeaf(sggx, origins[i], interpolation == Interpolation::kNearest);
  });
  // Flatten to (block coordinate, bound).
  std::vector<openvdb::Coord> blocks;
  std::vector<LeafBound> bounds;
  for (std::size_t i = 0; i < origins.size(); ++i)
    for (int b = 0; b < kBlocksPerLeaf; ++b) {
      if (!(leaf_bounds[i][b].max_rho > 0)) continue;
      const int x = b / (kBlocksPerLeafAxis * kBlocksPerLeafAxis), y = (b / kBlocksPerLeafAxis) % kBlocksPerLeafAxis,
                z = b % kBlocksPerLeafAxis;
      blocks.emplace_back(origins[i].x() / kMajorantBlock + x, origins[i].y() / kMajorantBlock + y,
                          origins[i].z() / kMajorantBlock + z);
      bounds.push_back(leaf_bounds[i][b]);
    }

  auto majorant = openvdb::FloatGrid::create(0.0f);
  majorant->setName("majorant");
  auto accessor = majorant->getAccessor();
  if (interpolation == Interpolation::kNearest) {
    for (std::size_t i = 0; i < blocks.size(); ++i) {
      const openvdb::Coord& a = blocks[i];
      if (bounds[i].max_rho_sqrt_lambda > 0)
        accessor.setValue(a, std::max(bounds[i].max_rho_sqrt_lambda, accessor.getValue(a)));
    }
    return majorant;
  }
  // Trilinear: a point of block a reads voxels B a - 1 .. B a + B (one beyond the block on each
  // side), so the bound is max(rho) * sqrt(max lambda) over that (B+2)^3 region, for every block
  // next to a block with density.
  openvdb::MaskGrid candidates;
  auto mask = candidates.getAccessor();
  for (const openvdb::Coord& a : blocks)
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) mask.setValueOn(a.offsetBy(dx, dy, dz));
  std::vector<openvdb::Coord> regions;
  for (auto it = candidates.cbeginValueOn(); it; ++it) regions.push_back(it.getCoord());
  std::vector<float> values(regions.size(), 0.0f);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, regions.size(), 64), [&](const auto& range) {
    auto rho = medium.density->getConstAccessor();
    std::optional<openvdb::Vec3SGrid::ConstAccessor> diag_values, off_values;
    if (medium.sggx_diag) diag_values = medium.sggx_diag->getConstAccessor();
    if (medium.sggx_offdiag) off_values = medium.sggx_offdiag->getConstAccessor();
    std::optional<CompactAttributes::Accessor> records;
    if (sggx.records) records.emplace(*sggx.records);
    const auto lambdaAt = [&](const openvdb::Coord& ijk) {
      if (!sggx.anisotropic()) return 1.0;
      if (records) {
        const auto* leaf = rho.probeConstLeaf(ijk);  // active: a compact medium has no tiles
        return largestEigenvalueOf(records->at(*leaf, openvdb::FloatTree::LeafNodeType::coordToOffset(ijk))) * (1 + 1e-6);
      }
      const openvdb::Vec3s diag = diag_values ? diag_values->getValue(ijk) : openvdb::Vec3s(1.0f);
      const openvdb::Vec3s off = off_values ? off_values->getValue(ijk) : openvdb::Vec3s(0.0f);
      return largestEigenvalue(diag, off);
    };
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const openvdb::Coord& a = regions[i];
      const openvdb::Coord lo(a.x() * kMajorantBlock - 1, a.y() * kMajorantBlock - 1, a.z() * kMajorantBlock - 1);
      double max_rho = 0, max_lambda = 0;
      for (int x = lo.x(); x <= lo.x() + kMajorantBlock + 1; ++x)
        for (int y = lo.y(); y <= lo.y() + kMajorantBlock + 1; ++y)
          for (int z = lo.z(); z <= lo.z() + kMajorantBlock + 1; ++z) {
            const openvdb::Coord ijk(x, y, z);
            float r = 0;
            if (!rho.probeValue(ijk, r) || !(r > 0)) continue;
            max_rho = std::max(max_rho, double(r));
            max_lambda = std::max(max_lambda, lambdaAt(ijk));
          }
      values[i] = float(max_rho * std::sqrt(max_lambda) * (1 + 1e-6));
    }
  });
  for (std::size_t i = 0; i < regions.size(); ++i)
    if (values[i] > 0) accessor.setValue(regions[i], values[i]);
  return majorant;
}

// The majorant blocks whose lookups read an emitting voxel: its own block (nearest), or the blocks
// within one voxel of it (trilinear; a point reads voxels up to one away).
std::vector<openvdb::Coord> emittingBlocks(const openvdb::Vec3SGrid& emission, Interpolation interpolation) {
  const int reach = interpolation == Interpolation::kNearest ? 0 : 1;
  openvdb::MaskGrid blocks;
  auto mask = blocks.getAccessor();
  for (auto v = emission.cbeginValueOn(); v; ++v) {
    if (!(v->x() > 0 || v->y() > 0 || v->z() > 0)) continue;
    openvdb::CoordBBox box = v.getBoundingBox();
    box.expand(reach);
    for (auto a = blocksOf(box, openvdb::Coord(kMajorantBlock)).begin(); a; ++a) mask.setValueOn(*a);
  }
  std::vector<openvdb::Coord> coords;
  for (auto a = blocks.cbeginValueOn(); a; ++a) {
    if (a.isVoxelValue()) coords.push_back(a.getCoord());
    else for (auto c = a.getBoundingBox().begin(); c; ++c) coords.push_back(*c);
  }
  return coords;
}

}  // namespace

openvdb::FloatGrid::Ptr buildMajorantGrid(const Medium& medium, Interpolation interpolation, const openvdb::Vec3SGrid* emission,
                                          const CompactAttributes* records) {
  openvdb::FloatGrid::Ptr majorant = buildExtinctionMajorant(SggxSource{medium, records}, interpolation);
  if (!emission) return majorant;
  const openvdb::Vec3d h = medium.transform().voxelSize();
  const float floor = float(1 / std::min({h[0], h[1], h[2]}));
  auto accessor = majorant->getAccessor();
  for (const openvdb::Coord& a : emittingBlocks(*emission, interpolation)) accessor.setValue(a, std::max(floor, accessor.getValue(a)));
  return majorant;
}

}  // namespace vdbappear
