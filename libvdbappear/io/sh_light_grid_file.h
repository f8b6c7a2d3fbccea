#pragma once
// SH light grids (lightgrid/sh_light_grid.h) as VDB files; docs/medium.md §11 is the contract.
// Light header. Node (i, j, k) is voxel (i, j, k) of every grid, whose transform puts it at
// origin + spacing (i, j, k):
//   sh_<n>          Vec3s  RGB coefficient n = l (l + 1) + m
//   sh_grad_<c>_<n> Vec3s  (d/dx, d/dy, d/dz) of channel c (r, g or b) of coefficient n
// File metadata: sh_lmax (int), sh_basis (string), history, schema.

#include <string>

namespace vdbappear {

class ShLightGrid;

void writeShLightGrid(const ShLightGrid& grid, const std::string& path, const std::string& history_line);

// Throws MediumError naming the file and the grid at fault.
ShLightGrid readShLightGrid(const std::string& path);

}  // namespace vdbappear
