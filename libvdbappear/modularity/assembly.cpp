#include "libvdbappear/modularity/assembly.h"

#include "libvdbappear/modularity/block_moves.h"
#include "libvdbappear/modularity/exemplar_set.h"

#include "libvdbappear/util/error.h"
#include "libvdbappear/util/system_memory.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace vdbappear {

using openvdb::Coord;

namespace {

openvdb::Int32Grid::Ptr layoutGrid(const ExemplarLayout& layout, const openvdb::math::Transform::Ptr& transform) {
  auto grid = openvdb::Int32Grid::create(0);
  grid->setName(grid_names::kExemplarLayout);
  grid->setTransform(transform);
  auto accessor = grid->getAccessor();
  for (int k = 0; k < layout.depth; ++k)
    for (int j = 0; j < layout.height; ++j)
      for (int i = 0; i < layout.width; ++i)
        if (layout.at(i, j, k) != ExemplarLayout::kEmpty) accessor.setValueOn(Coord(i, j, k), layout.at(i, j, k));
  return grid;
}

// Bytes a built model's grids take: per active voxel, every voxel grid's value, plus a quarter for
// the trees (leaf masks, nodes). The placed exemplars' active voxels are counted from the density.
double builtModelBytes(const Medium& blocks, const BlockMoves& moves) {
  std::map<Coord, std::uint64_t> voxels = activeVoxelsPerBlock(*blocks.density, moves.block);
  double placed = 0;
  for (const auto& [block, copies] : moves.destinations) placed += double(voxels[block]) * double(copies.size());
  double bytes_per_voxel = 0;
  for (const auto& grid : blocks.grids())
    if (!isBlockIndexedGridName(grid->getName()) && grid->getName() != grid_names::kPhaseTable)
      bytes_per_voxel += grid->valueType() == "vec3s" ? 12 : 4;
  return placed * bytes_per_voxel * 1.25;
}

void checkModelFits(const Medium& blocks, const BlockMoves& moves) {
  const double needed = builtModelBytes(blocks, moves), available = physicalMemoryBytes();
  if (available > 0 && needed > 0.8 * available)
    throw MediumError(fmt::format("{}: the model would take about {:.1f} GB in memory, more than 80% of this machine's "
                                  "{:.1f} GB: assemble it with --instanced (vdb_render renders it through the layout)",
                                  blocks.source, needed / 1e9, available / 1e9));
}

void replaceLayout(Medium& medium, const ExemplarLayout& layout) {
  removeOtherGrid(medium, grid_names::kExemplarLayout);
  medium.other_grids.push_back(layoutGrid(layout, medium.density->transformPtr()));
}

}  // namespace

void checkLayoutMedium(const Medium& layout_medium, const Medium& blocks) {
  const auto count = layout_medium.metadata.getMetadata<openvdb::Int32Metadata>(metadata_names::kExemplarCount);
  const auto block = layout_medium.metadata.getMetadata<openvdb::Vec3IMetadata>(metadata_names::kExemplarBlock);
  if (!count || !block) return;  // a layout grid alone: its ids are checked against the set
  const ExemplarSet set = readExemplarSet(blocks, ExemplarKind::Blocks);
  if (count->value() != set.count)
    throw MediumError(fmt::format("{}: a layout of {} exemplars; the block set {} holds {}", layout_medium.source,
                                  count->value(), blocks.source, set.count));
  // World size of a block: exemplar_block counts voxels of exemplar_voxel_size, else of the medium's own.
  const auto original = layout_medium.metadata.getMetadata<openvdb::Vec3DMetadata>(metadata_names::kExemplarVoxelSize);
  const openvdb::Vec3d voxel = original ? original->value() : layout_medium.transform().voxelSize();
  const openvdb::Vec3d theirs(block->value().x() * voxel.x(), block->value().y() * voxel.y(), block->value().z() * voxel.z());
  const openvdb::Vec3d here = blocks.transform().voxelSize();
  const openvdb::Vec3d ours(set.block.x() * here.x(), set.block.y() * here.y(), set.block.z() * here.z());
  for (int a = 0; a < 3; ++a)
    if (!(std::abs(theirs[a] - ours[a]) <= 1e-6 * std::max(theirs[a], ours[a])))
      throw MediumError(fmt::format("{}: its blocks measure {:g} x {:g} x {:g} world units; those of the block set {} "
                                    "measure {:g} x {:g} x {:g}: not a layout of these blocks", layout_medium.source,
                                    theirs.x(), theirs.y(), theirs.z(), blocks.source, ours.x(), ours.y(), ours.z()));
}

MediumPtr assembleModel(const Medium& blocks, const ExemplarLayout& layout) {
  const ExemplarSet set = readExemplarSet(blocks, ExemplarKind::Blocks);
  checkLayoutIds(layout, set.count, blocks.source);
  BlockMoves moves{set.block, {}};
  for (int e = 0; e < set.count; ++e) moves.destinations[Coord(e, 0, 0)];  // every exemplar, used or not
  for (int k = 0; k < layout.depth; ++k)
    for (int j = 0; j < layout.height; ++j)
      for (int i = 0; i < layout.width; ++i)
        if (layout.at(i, j, k) != ExemplarLayout::kEmpty)
          moves.destinations[Coord(layout.at(i, j, k), 0, 0)].push_back(Coord(i, j, k));
  checkModelFits(blocks, moves);
  MediumPtr model = moveBlocks(blocks, moves);
  replaceLayout(*model, layout);
  writeExemplarSet(*model, {set.count, set.block, ExemplarKind::Model, 1,
                            set.name.empty() ? exemplarSetName(blocks) : set.name});
  return model;
}

MediumPtr instancedModel(const Medium& blocks, const ExemplarLayout& layout) {
  const ExemplarSet set = readExemplarSet(blocks, ExemplarKind::Blocks);
  checkLayoutIds(layout, set.count, blocks.source);
  auto model = std::make_shared<Medium>(blocks);  // shares the grids
  replaceLayout(*model, layout);
  model->metadata = blocks.metadata;
  writeExemplarSet(*model, {set.count, set.block, ExemplarKind::Instanced, 1,
                            set.name.empty() ? exemplarSetName(blocks) : set.name});
  return model;
}

}  // namespace vdbappear
