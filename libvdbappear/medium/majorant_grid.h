#pragma once
// The hierarchical majorant of a medium's extinction (internal header: includes OpenVDB).
//
// Extinction toward w is sigma_t(w) = rho sqrt(w^T S w) (docs/medium.md §4), and
// w^T S w <= lambda_max(S) for every unit w, so rho sqrt(lambda_max(S)) bounds it in all
// directions. The majorant grid holds one value per 8^3 leaf node of `density`: majorant voxel a
// covers density voxels 8a .. 8a+7, i.e. the index-space box [8a - 1/2, 8a + 7.5) of their cells.
// In "majorant space" m = (index + 1/2) / 8, majorant voxel a is the unit cube [a, a+1), the
// convention of OpenVDB's DDA. Its tree (leaves of 8^3 majorant voxels, internal nodes above) lets
// a ray skip empty space node by node (medium/majorant_traversal.h).

#include "libvdbappear/medium/interpolation.h"

#include <openvdb/openvdb.h>

namespace vdbappear {

struct Medium;

// kNearest: the maximum of rho sqrt(lambda_max(S)) over the leaf's voxels.
// kTrilinear: a trilinear lookup mixes a voxel with its neighbours, and the density-weighted S is
// not bounded by the corner maxima of rho sqrt(lambda_max), so the value is
// max(rho) * sqrt(max lambda_max over voxels with rho > 0), then the maximum over the 27 leaves
// around (a lookup reads voxels up to one away, which may lie in a neighbouring leaf).
openvdb::FloatGrid::Ptr buildMajorantGrid(const Medium& medium, Interpolation interpolation);

}  // namespace vdbappear
