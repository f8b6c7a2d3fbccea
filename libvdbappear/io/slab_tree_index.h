#pragma once
// One grid of a mapped VDB file (io/mapped_vdb_file.h) read a part at a time, in memory that grows
// with the part, not with the grid (docs/scaling.md §5). The grid's topology is walked once, one
// 128^3 node (the tree's lower internal node) at a time, each read and freed: what stays is where
// each node's topology and leaf values lie in the file and which leaves it holds (about 550 bytes a
// node, against some 270 bytes a leaf for OpenVDB's delayed loading, which keeps every leaf's node).
// A part is read from the nodes that cross it, in parallel, through OpenVDB's own node readers:
// each node's topology, then the values of its leaves in the part's x range, each read from the file
// into memory of its own and freed once parsed.
// Internal header: includes OpenVDB.

#include "libvdbappear/io/mapped_vdb_file.h"

#include <openvdb/openvdb.h>
#include <openvdb/util/NodeMasks.h>

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace vdbappear {

class SlabTreeIndex {
 public:
  // Walks the grid's topology and seeks over its leaf values once; the grid must be of one of the
  // types a part holds (SlabGridTypes, io/medium_slabs.h). Throws (std::exception) for a file that
  // ends early or whose grid does not end where the file says.
  SlabTreeIndex(const MappedVdbFile& file, std::size_t grid);

  std::uint64_t leafCount() const { return leaf_count_; }
  std::uint64_t activeVoxelCount() const { return active_voxels_; }
  // Calls `f` with the origin of every leaf, node by node.
  void forEachLeaf(const std::function<void(const openvdb::Coord&)>& f) const;
  // The tiles above the leaf level that are active or differ from the background, as a grid of
  // their own (null if none): few, so a part cuts them to itself.
  const openvdb::GridBase::ConstPtr& tiles() const { return tiles_; }
  // What the index holds in memory.
  std::uint64_t memoryBytes() const;

  // The grid (its metadata, transform and background) with its leaves in `box`, read from the file
  // now; `box` holds whole leaves. Tiles are not included: addTiles cuts them to the part.
  openvdb::GridBase::Ptr readLeaves(const openvdb::CoordBBox& box) const;
  // Fills `part` (this grid's type) with tiles() cut to `box`.
  void addTiles(openvdb::GridBase& part, const openvdb::CoordBBox& box) const;
  // The whole grid: every leaf and tile.
  openvdb::GridBase::Ptr readWhole() const;

 private:
  // A lower internal node: 16^3 leaves of 8^3 voxels, its leaves' values in the file in the order of
  // their slots, x slowest (InternalNode::writeBuffers), so that the leaves of an x range lie together.
  struct Node {
    openvdb::Coord origin;
    std::streamoff topology_position = 0, topology_end = 0;
    std::array<std::streamoff, 17> slice_position{};  // where the values of leaves at local x >= i begin
    openvdb::util::NodeMask<4> leaves;                // the node's child mask
  };
  template <typename GridT>
  void walk(const GridT& header);
  template <typename GridT>
  openvdb::GridBase::Ptr readLeavesOf(const GridT& header, const openvdb::CoordBBox& box) const;

  const MappedVdbFile* file_;
  std::size_t grid_;
  std::vector<Node> nodes_;
  openvdb::GridBase::ConstPtr tiles_;
  std::uint64_t leaf_count_ = 0;
  std::uint64_t active_voxels_ = 0;
};

}  // namespace vdbappear
