#pragma once
// SH light grids (lightgrid/sh_light_grid.h, lightgrid/adaptive_sh_grid.h) as VDB files;
// docs/medium.md §11 is the contract. Light header. Node (a, b, c) of the finest lattice is voxel
// (a, b, c) of every grid, whose transform puts it at origin + spacing (a, b, c); only nodes are active:
//   sh_<n>          Vec3s  RGB coefficient n = l (l + 1) + m
//   sh_grad_<c>_<n> Vec3s  (d/dx, d/dy, d/dz) of channel c (r, g or b) of coefficient n
// File metadata: sh_lmax (int), sh_levels (int: 0 for a uniform grid), sh_basis (string), history,
// schema.

#include <memory>
#include <string>

namespace vdbappear {

class ShGridLookup;

void writeShLightGrid(const ShGridLookup& grid, const std::string& path, const std::string& history_line);

// A uniform grid (sh_levels 0) or an adaptive one. Throws MediumError naming the file and the grid.
std::shared_ptr<const ShGridLookup> readShLightGrid(const std::string& path);

}  // namespace vdbappear
