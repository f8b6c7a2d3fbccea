#include "libvdbappear/modularity/assembly.h"

#include "libvdbappear/modularity/block_moves.h"
#include "libvdbappear/modularity/exemplar_set.h"

#include <algorithm>

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

void replaceLayout(Medium& medium, const ExemplarLayout& layout) {
  auto& grids = medium.other_grids;
  grids.erase(std::remove_if(grids.begin(), grids.end(),
                             [](const auto& g) { return g->getName() == grid_names::kExemplarLayout; }),
              grids.end());
  grids.push_back(layoutGrid(layout, medium.density->transformPtr()));
}

}  // namespace

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
