#include "libvdbappear/procedural/voxel_filler.h"

#include "libvdbappear/io/medium_block.h"
#include "libvdbappear/io/spilled_medium.h"
#include "libvdbappear/math/sggx.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <optional>
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

// Fills `blocks` in parallel and moves their leaves into `medium`; returns how many held a voxel.
std::size_t fillBlocks(Medium& medium, const ProceduralLayout& layout, const std::vector<CoordBBox>& blocks,
                       const BlockTest& may_be_occupied, const VoxelFunction& sample) {
  std::vector<MediumBlock> leaves(blocks.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size()), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      if (may_be_occupied(blocks[i])) fillBlock(medium, layout, blocks[i], sample, leaves[i]);
  });
  std::size_t filled = 0;
  for (auto& block : leaves) {
    filled += !block.empty();
    block.adoptInto(medium);
  }
  return filled;
}

// The bytes of one filled block's leaves, every grid.
std::uint64_t blockBytes(const ProceduralLayout& layout) {
  using FloatLeaf = openvdb::FloatTree::LeafNodeType;
  using Vec3Leaf = openvdb::Vec3STree::LeafNodeType;
  constexpr std::uint64_t kFloat = sizeof(FloatLeaf) + FloatLeaf::SIZE * sizeof(float);
  constexpr std::uint64_t kVec3 = sizeof(Vec3Leaf) + Vec3Leaf::SIZE * sizeof(openvdb::Vec3s);
  return kFloat * (1 + layout.hg_g) + kVec3 * (layout.albedo + 2 * layout.sggx);
}

// fillMedium under a budget: columns of leaves along x, in memory while the medium is small, then
// in slabs moved to scratch files.
MediumPtr fillInSlabs(const ProceduralLayout& layout, const BlockTest& may_be_occupied, const VoxelFunction& sample,
                      const std::function<MediumPtr()>& empty_medium) {
  constexpr int kDim = openvdb::FloatTree::LeafNodeType::DIM;
  const std::uint64_t held_bytes = layout.memory.budget_bytes / 4;
  const std::uint64_t slab_bytes = std::min<std::uint64_t>(layout.memory.budget_bytes / 8, 500'000'000);
  const std::uint64_t block_bytes = blockBytes(layout);
  std::optional<SpilledMedium> spilled;
  MediumPtr part = empty_medium();
  std::uint64_t part_bytes = 0;
  for (int x = layout.bounds.min().x() & ~(kDim - 1); x <= layout.bounds.max().x(); x += kDim) {
    CoordBBox column = layout.bounds;
    column.min().setX(std::max(x, column.min().x()));
    column.max().setX(std::min(x + kDim - 1, column.max().x()));
    part_bytes += fillBlocks(*part, layout, leafBlocks(column), may_be_occupied, sample) * block_bytes;
    if (!spilled && part_bytes > held_bytes) spilled.emplace(layout.memory.scratch_beside);
    const bool last = x + kDim > layout.bounds.max().x();
    if (spilled && part_bytes > 0 && (part_bytes >= slab_bytes || last)) {
      spilled->add(*part, "procedural");
      part = empty_medium();
      part_bytes = 0;
    }
  }
  if (!spilled) return part;
  MediumPtr whole = spilled->medium();
  whole->source = "procedural";
  return whole;
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
  const auto empty_medium = [&] {
    MediumPtr medium = makeEmptyMedium({layout.albedo, layout.sggx, layout.hg_g}, transform);
    medium->source = "procedural";
    return medium;
  };
  if (layout.memory.budget_bytes > 0) return fillInSlabs(layout, may_be_occupied, sample, empty_medium);
  const MediumPtr medium = empty_medium();
  fillBlocks(*medium, layout, leafBlocks(layout.bounds), may_be_occupied, sample);
  return medium;
}

}  // namespace vdbappear
