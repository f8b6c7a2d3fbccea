#pragma once
// Checks a medium against the contract of docs/medium.md. Every failure throws MediumError naming
// the file (`source`) and the grid; where values are at fault, the first bad voxel in (x,y,z)
// order is named, so the message does not depend on the thread count.

#include <string>

#include <openvdb/version.h>

namespace openvdb {
OPENVDB_USE_VERSION_NAMESPACE
namespace OPENVDB_VERSION_NAME {
class GridBase;
}
}  // namespace openvdb

namespace vdbappear {

struct Medium;

// What one grid must satisfy on its own: the value type its name requires; finite values;
// density >= 0 with background 0 and at least one voxel > 0; albedo in [0,1]; hg_g in (-1,1).
// Safe to run as soon as the grid is read, in parallel with reading the others.
void validateGrid(const openvdb::GridBase& grid, const std::string& source);

// validateGrid of a part of a grid (a slab, io/medium_slabs.h): with `whole` false, an empty density
// passes; the reader calls failEmptyDensity when no part held a voxel > 0.
void validateGridPart(const openvdb::GridBase& grid, const std::string& source, bool whole);
[[noreturn]] void failEmptyDensity(const std::string& source);

// What holds across grids: a density grid exists; all grids share its transform, which is linear;
// sggx_offdiag comes with sggx_diag; wherever density > 0, the values the tools will use there
// (active or not in their own grids) are valid: albedo in [0,1], S symmetric positive definite,
// hg_g in (-1,1); the schema and hg_g metadata are understood.
void validateAcrossGrids(const Medium& medium, const std::string& source);

// Both of the above, for every grid of the medium.
void validateMedium(const Medium& medium, const std::string& source);

}  // namespace vdbappear
