#pragma once
// Builds a sparse medium from a per-voxel function, 8^3 block by block in parallel, creating leaves
// only for blocks that hold an active voxel. Includes OpenVDB (library code only).

#include "libvdbappear/io/medium.h"
#include "libvdbappear/math/vector.h"
#include "libvdbappear/procedural/fill_memory.h"
#include "libvdbappear/procedural/voxel_sample.h"

#include <functional>
#include <optional>

namespace vdbappear {


struct ProceduralLayout {
  openvdb::CoordBBox bounds;  // index-space box to fill
  double voxel_size = 1;      // world units
  Vec3 origin = Vec3::Zero(); // world position of the centre of voxel (0,0,0)
  bool albedo = true;
  bool sggx = true;
  bool hg_g = false;
  FillMemory memory;          // by default the whole medium in memory
};

// Voxels needed to cover `extent` world units (a hair under a whole number counts as that number).
int voxelsToCover(double extent, double voxel_size);
// Index box [0, voxels) whose voxel (0,0,0) covers the world box [0, voxel_size]^3.
ProceduralLayout cornerLayout(const openvdb::Coord& voxels, double voxel_size);
// Index box [0, voxels) centred on the world origin.
ProceduralLayout centredLayout(const openvdb::Coord& voxels, double voxel_size);

// `may_be_occupied(block)` may skip whole 8^3 blocks quickly; `sample(ijk, centre)` (centre: the
// voxel's world position) returns the voxel, made active whatever its density, or nullopt to leave
// it inactive. Both must be thread-safe and deterministic.
using BlockTest = std::function<bool(const openvdb::CoordBBox&)>;
using VoxelFunction = std::function<std::optional<VoxelSample>(const openvdb::Coord& ijk, const Vec3& centre)>;

// With a memory budget (layout.memory), blocks are filled a column of leaves (8 voxels along x) at a
// time; once the medium holds a quarter of the budget, it moves to scratch files in slabs of at
// most an eighth (0.5 GB at most), and the result is a medium whose values wait on disk (writeMedium
// writes it leaf by leaf). Either way the grids are the same, bit for bit.
MediumPtr fillMedium(const ProceduralLayout& layout, const BlockTest& may_be_occupied, const VoxelFunction& sample);

}  // namespace vdbappear
