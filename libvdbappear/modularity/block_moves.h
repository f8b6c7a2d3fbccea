#pragma once
// Moving whole blocks of voxels: stacking exemplars into one volume, cutting a stacked volume back
// into blocks and assembling a model from blocks are each "every voxel of source block b goes to
// the same place in each destination block of b". Includes OpenVDB (library code only).

#include "libvdbappear/io/medium.h"
#include "libvdbappear/math/block_index.h"

#include <cstdint>
#include <map>
#include <vector>

namespace vdbappear {

// Block b covers index [b*block, (b+1)*block) per axis, in source and destination alike.
struct BlockMoves {
  openvdb::Coord block;                                                  // voxels per block side
  std::map<openvdb::Coord, std::vector<openvdb::Coord>> destinations;  // source block -> its copies (none: dropped)
};

// Active voxels of a float grid (the density, a majorant) per block (tiles counted whole, in the
// block of their first voxel).
std::map<openvdb::Coord, std::uint64_t> activeVoxelsPerBlock(const openvdb::FloatGrid& density,
                                                             const openvdb::Coord& block);

// `source` with every voxel-indexed grid's active values moved as `moves` says, bit for bit;
// block-indexed grids (exemplar_layout, exemplar_stacking), the phase table and the metadata are
// copied as they are. Throws MediumError naming the file and the grid for an active voxel in a block
// that `moves` does not list.
MediumPtr moveBlocks(const Medium& source, const BlockMoves& moves);

}  // namespace vdbappear
