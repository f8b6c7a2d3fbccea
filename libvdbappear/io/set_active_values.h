#pragma once
// Setting every active value of a grid from a function of its voxel, in parallel leaf by leaf and
// then tile by tile: deterministic whatever the thread count. (openvdb::tools::foreach over a tree's
// ValueOnIter with per-thread copies of accessors left active voxels unset in about one run in
// three, measured on a blackbody grid of 10808 voxels.) Internal header: includes OpenVDB.

#include <openvdb/openvdb.h>
#include <openvdb/tree/LeafManager.h>

namespace vdbappear {

// value_of(ijk, current) gives the new value of the active value at ijk (a tile's: its first
// voxel's); it may read other trees only through thread-safe calls (Tree::getValue, probeConstLeaf).
template <typename GridT, typename ValueOf>
void setActiveValues(GridT& grid, const ValueOf& value_of) {
  using TreeT = typename GridT::TreeType;
  openvdb::tree::LeafManager<TreeT> leaves(grid.tree());
  leaves.foreach([&](typename TreeT::LeafNodeType& leaf, std::size_t) {
    for (auto v = leaf.beginValueOn(); v; ++v) v.setValue(value_of(v.getCoord(), *v));
  });
  auto tile = grid.tree().beginValueOn();
  tile.setMaxDepth(TreeT::ValueOnIter::LEAF_DEPTH - 1);
  for (; tile; ++tile) tile.setValue(value_of(tile.getCoord(), *tile));
}

}  // namespace vdbappear
