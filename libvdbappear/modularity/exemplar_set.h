#pragma once
// What a medium says of its exemplar blocks (docs/medium.md, section 6b): how many, how big, how
// they are arranged, and by what factor the medium was reduced since the blocks were made.
// Includes OpenVDB (library code only).

#include "libvdbappear/io/medium.h"

#include <string>

namespace vdbappear {

enum class ExemplarKind { Blocks, Stacked, Model, Instanced };

const char* exemplarKindName(ExemplarKind kind);

struct ExemplarSet {
  int count = 0;              // N
  openvdb::Coord block;       // voxels per block side at this medium's resolution
  ExemplarKind kind = ExemplarKind::Blocks;
  int factor = 1;             // this medium's voxels are `factor` of the blocks' original voxels per side
  std::string name;           // metadata exemplar_set, if any
};

// Reads the metadata; throws MediumError naming the medium's file when it is missing, malformed, of
// another kind than `expected`, or when the reduction factor does not divide the blocks.
ExemplarSet readExemplarSet(const Medium& medium, ExemplarKind expected);

// Writes count, block (at this resolution), kind and name; removes exemplar_voxel_size (the blocks
// are now counted in this medium's own voxels).
void writeExemplarSet(Medium& medium, const ExemplarSet& set);

// "xxh3:HASH NAME" of a block set (the metadata exemplar_set of what is made from it).
std::string exemplarSetName(const Medium& blocks);

}  // namespace vdbappear
