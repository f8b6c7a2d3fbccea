#include "libvdbappear/procedural/voxel_filler.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <memory>
#include <vector>

namespace vdbappear {

namespace {

using openvdb::Coord;
using openvdb::CoordBBox;
using openvdb::Vec3s;
using FloatLeaf = openvdb::FloatTree::LeafNodeType;
using Vec3sLeaf = openvdb::Vec3STree::LeafNodeType;

struct BlockLeaves {
  std::unique_ptr<FloatLeaf> density, hg_g;
  std::unique_ptr<Vec3sLeaf> albedo, sggx_diag, sggx_offdiag;
};

Vec3s toVec3s(double x, double y, double z) { return Vec3s(float(x), float(y), float(z)); }

void fillBlock(const ProceduralLayout& layout, const CoordBBox& block, const VoxelFunction& sample, BlockLeaves& out) {
  for (auto ijk = block.begin(); ijk; ++ijk) {
    const std::optional<VoxelSample> voxel = sample(*ijk);
    if (!voxel) continue;
    if (!out.density) {
      const Coord origin = block.min();
      out.density = std::make_unique<FloatLeaf>(origin, 0.0f);
      if (layout.albedo) out.albedo = std::make_unique<Vec3sLeaf>(origin, Vec3s(1.0f));
      if (layout.sggx) {
        out.sggx_diag = std::make_unique<Vec3sLeaf>(origin, Vec3s(1.0f));
        out.sggx_offdiag = std::make_unique<Vec3sLeaf>(origin, Vec3s(0.0f));
      }
      if (layout.hg_g) out.hg_g = std::make_unique<FloatLeaf>(origin, 0.0f);
    }
    const openvdb::Index n = FloatLeaf::coordToOffset(*ijk);
    out.density->setValueOn(n, voxel->density);
    if (out.albedo) out.albedo->setValueOn(n, toVec3s(voxel->albedo.x(), voxel->albedo.y(), voxel->albedo.z()));
    if (out.sggx_diag) {
      const Mat3& S = voxel->S;
      out.sggx_diag->setValueOn(n, toVec3s(S(0, 0), S(1, 1), S(2, 2)));
      out.sggx_offdiag->setValueOn(n, toVec3s(S(0, 1), S(0, 2), S(1, 2)));
    }
    if (out.hg_g) out.hg_g->setValueOn(n, voxel->hg_g);
  }
}

template <typename GridT>
typename GridT::Ptr makeGrid(const char* name, typename GridT::ValueType background,
                             const openvdb::math::Transform::Ptr& transform) {
  auto grid = GridT::create(background);
  grid->setName(name);
  grid->setTransform(transform);
  return grid;
}

template <typename GridPtrT, typename LeafT>
void adopt(const GridPtrT& grid, std::unique_ptr<LeafT>& leaf) {
  if (grid && leaf) grid->tree().addLeaf(leaf.release());
}

}  // namespace

MediumPtr fillMedium(const ProceduralLayout& layout, const BlockTest& may_be_occupied, const VoxelFunction& sample) {
  openvdb::initialize();
  constexpr int kDim = FloatLeaf::DIM;
  auto alignDown = [](int v) { return v & ~(kDim - 1); };  // two's complement: rounds toward -inf
  const Coord first(alignDown(layout.bounds.min().x()), alignDown(layout.bounds.min().y()),
                    alignDown(layout.bounds.min().z()));
  std::vector<CoordBBox> blocks;
  for (int x = first.x(); x <= layout.bounds.max().x(); x += kDim)
    for (int y = first.y(); y <= layout.bounds.max().y(); y += kDim)
      for (int z = first.z(); z <= layout.bounds.max().z(); z += kDim) {
        CoordBBox block(Coord(x, y, z), Coord(x, y, z).offsetBy(kDim - 1));
        block.intersect(layout.bounds);
        blocks.push_back(block);
      }

  std::vector<BlockLeaves> leaves(blocks.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size()), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      if (may_be_occupied(blocks[i])) fillBlock(layout, blocks[i], sample, leaves[i]);
  });

  auto transform = openvdb::math::Transform::createLinearTransform(layout.voxel_size);
  auto medium = std::make_shared<Medium>();
  medium->source = "procedural";
  medium->density = makeGrid<openvdb::FloatGrid>(grid_names::kDensity, 0.0f, transform);
  medium->density->setGridClass(openvdb::GRID_FOG_VOLUME);
  if (layout.albedo) medium->albedo = makeGrid<openvdb::Vec3SGrid>(grid_names::kAlbedo, Vec3s(1.0f), transform);
  if (layout.sggx) {
    medium->sggx_diag = makeGrid<openvdb::Vec3SGrid>(grid_names::kSggxDiag, Vec3s(1.0f), transform);
    medium->sggx_offdiag = makeGrid<openvdb::Vec3SGrid>(grid_names::kSggxOffdiag, Vec3s(0.0f), transform);
  }
  if (layout.hg_g) medium->hg_g = makeGrid<openvdb::FloatGrid>(grid_names::kHgG, 0.0f, transform);
  for (auto& block : leaves) {
    adopt(medium->density, block.density);
    adopt(medium->albedo, block.albedo);
    adopt(medium->sggx_diag, block.sggx_diag);
    adopt(medium->sggx_offdiag, block.sggx_offdiag);
    adopt(medium->hg_g, block.hg_g);
  }
  medium->metadata.insertMeta(metadata_names::kSchema, openvdb::Int32Metadata(metadata_names::kSchemaVersion));
  return medium;
}

}  // namespace vdbappear
