#pragma once
// Blocks of voxels by index: block b covers index [b*block, (b+1)*block) per axis, so voxels left
// of or below the origin lie in negative blocks (floor division). A coarse voxel of a downsampling
// by F, a majorant block and an exemplar block are all such blocks. Inline: instanced renders call
// blockOf at every lookup. Includes OpenVDB's Coord.

#include <openvdb/math/Coord.h>

namespace vdbappear {

inline int floorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

inline openvdb::Coord blockOf(const openvdb::Coord& ijk, const openvdb::Coord& block) {
  return openvdb::Coord(floorDiv(ijk.x(), block.x()), floorDiv(ijk.y(), block.y()), floorDiv(ijk.z(), block.z()));
}

// The blocks that the voxels of `voxels` lie in.
inline openvdb::CoordBBox blocksOf(const openvdb::CoordBBox& voxels, const openvdb::Coord& block) {
  return openvdb::CoordBBox(blockOf(voxels.min(), block), blockOf(voxels.max(), block));
}

}  // namespace vdbappear
