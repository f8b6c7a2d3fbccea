#pragma once
// Limits that stop a small file (hostile, corrupt or mistaken) from claiming more memory than the
// machine has, checked before anything is allocated (docs/reliability.md §6). Each is raised through
// the environment. Light header.

#include <cstdint>

namespace vdbappear {

// The voxels that the active tiles of one grid may cover. A tile costs a few bytes in a file and a
// voxel's memory per voxel it covers once voxelised (validation, majorants, views), so one root
// tile of a hand-edited file claims 4096^3 voxels. Default 2^31 (a dense block of 1290^3);
// VDBAPPEAR_MAX_TILE_VOXELS sets another. Throws MediumError when the variable is not a positive
// integer.
std::uint64_t maxTileVoxels();

// The bytes one render may hold for its image, variance, AOVs and gradient images. Default: the
// machine's physical memory; VDBAPPEAR_MAX_RENDER_BYTES sets another. Throws MediumError when the
// variable is not a positive integer.
std::uint64_t maxRenderBytes();

}  // namespace vdbappear
