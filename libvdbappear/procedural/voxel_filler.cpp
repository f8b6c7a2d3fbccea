#include "libvdbappear/procedural/voxel_filler.h"

#include "libvdbappear/io/medium_block.h"
#include "libvdbappear/math/sggx.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <vector>

namespace vdbappear {

namespace {

using openvdb::Coord;
using openvdb::CoordBBox;

void fillBlock(const Medium& medium, const ProceduralLayout& layout, const CoordBBox& block,
               const VoxelFunction& sample, MediumBlock& out) {
  for (auto ijk = block.begin(); ijk; ++ijk) {
    const Vec3 centre = layout.origin + layout.voxel_size * Vec3((*ijk).x(), (*ijk).y(), (*ijk).z());
    const std::optional<VoxelSample> voxel = sample(*ijk, centre);
    if (!voxel) continue;
    if (out.empty()) out.allocate(medium, block.min() & ~7);
    const Mat3& S = voxel->S;
    out.setVoxel(openvdb::FloatTree::LeafNodeType::coordToOffset(*ijk), voxel->density, toVec3s(voxel->albedo),
                 toVec3s(sggxDiagonal(S)), toVec3s(sggxOffDiagonal(S)), voxel->hg_g);
  }
}

// The 8^3 leaf blocks that overlap `bounds`, each clipped to it.
std::vector<CoordBBox> leafBlocks(const CoordBBox& bounds) {
  constexpr int kDim = openvdb::FloatTree::LeafNodeType::DIM;
  const Coord first = bounds.min() & ~(kDim - 1);  // two's complement: rounds toward -infinity
  std::vector<CoordBBox> blocks;
  for (int x = first.x(); x <= bounds.max().x(); x += kDim)
    for (int y = first.y(); y <= bounds.max().y(); y += kDim)
      for (int z = first.z(); z <= bounds.max().z(); z += kDim) {
        CoordBBox block(Coord(x, y, z), Coord(x, y, z).offsetBy(kDim - 1));
        block.intersect(bounds);
        blocks.push_back(block);
      }
  return blocks;
}

}  // namespace

int voxelsToCover(double extent, double voxel_size) { return int(std::ceil(extent / voxel_size - 1e-9)); }

ProceduralLayout cornerLayout(const Coord& voxels, double voxel_size) {
  ProceduralLayout layout;
  layout.bounds = {Coord(0), voxels.offsetBy(-1)};
  layout.voxel_size = voxel_size;
  layout.origin = Vec3::Constant(0.5 * voxel_size);
  return layout;
}

ProceduralLayout centredLayout(const Coord& voxels, double voxel_size) {
  ProceduralLayout layout = cornerLayout(voxels, voxel_size);
  layout.origin = Vec3(-0.5 * voxels.x() + 0.5, -0.5 * voxels.y() + 0.5, -0.5 * voxels.z() + 0.5) * voxel_size;
  return layout;
}

MediumPtr fillMedium(const ProceduralLayout& layout, const BlockTest& may_be_occupied, const VoxelFunction& sample) {
  openvdb::initialize();
  auto transform = openvdb::math::Transform::createLinearTransform(layout.voxel_size);
  transform->postTranslate(openvdb::Vec3d(layout.origin.x(), layout.origin.y(), layout.origin.z()));
  const MediumPtr medium = makeEmptyMedium({layout.albedo, layout.sggx, layout.hg_g}, transform);
  medium->source = "procedural";
  const std::vector<CoordBBox> blocks = leafBlocks(layout.bounds);
  std::vector<MediumBlock> leaves(blocks.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size()), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      if (may_be_occupied(blocks[i])) fillBlock(*medium, layout, blocks[i], sample, leaves[i]);
  });
  for (auto& block : leaves) block.adoptInto(*medium);
  return medium;
}

}  // namespace vdbappear
