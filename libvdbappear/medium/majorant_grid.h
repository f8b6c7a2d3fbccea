#pragma once
// The hierarchical majorant of a medium's extinction (internal header: includes OpenVDB).
//
// Extinction toward w is sigma_t(w) = rho sqrt(w^T S w) (docs/medium.md §4), and
// w^T S w <= lambda_max(S) for every unit w, so rho sqrt(lambda_max(S)) bounds it in all
// directions. The majorant grid holds one value per block of B^3 density voxels (B = kMajorantBlock,
// a divisor of the leaf size 8): majorant voxel a covers density voxels Ba .. Ba+B-1, i.e. the
// index-space box [Ba - 1/2, Ba + B - 1/2) of their cells. In "majorant space" m = (index + 1/2) / B,
// majorant voxel a is the unit cube [a, a+1), the convention of OpenVDB's DDA. Its tree (leaves of
// 8^3 majorant voxels, internal nodes above) lets a ray skip empty space node by node
// (medium/majorant_traversal.h).
//
// B trades null collisions (a block's maximum over-estimates most of its voxels) against DDA steps.
// Measured on 2 cores, 128x128 at 16 spp, time / majorant events: twill --res 128 (fibres a few
// voxels wide) B = 8: 1.30 s / 22.4 M, B = 4: 1.25 s / 16.6 M, B = 2: 1.13 s / 10.4 M; cloud
// --res 128 (smooth) B = 8: 0.94 s / 9.7 M, B = 4: 1.09 s / 7.4 M, B = 2: 1.12 s / 6.1 M. B = 4 is
// the compromise. With the trilinear bound over the block grown by one voxel (rather than over the
// 26 neighbouring blocks), B = 4 and B = 2 measured the same on both media (twill 2.46 / 2.53 s,
// cloud 2.43 / 2.40 s, trilinear, 128x128 at 16 spp).

#include "libvdbappear/medium/interpolation.h"

#include <openvdb/openvdb.h>

namespace vdbappear {

struct Medium;
class CompactAttributes;

// kNearest: the maximum of rho sqrt(lambda_max(S)) over the leaf's voxels.
// kTrilinear: a trilinear lookup mixes a voxel with its neighbours, and the density-weighted S is
// not bounded by the corner maxima of rho sqrt(lambda_max), so the value is
// max(rho) * sqrt(max lambda_max over voxels with rho > 0), with both maxima taken over the block
// grown by one voxel on every side (the voxels a lookup inside the block can read).
inline constexpr int kMajorantBlock = 4;

// emission: an `emission` grid added per unit length whatever the density (docs/medium.md §3b, the
// cycles convention). Over the blocks whose lookups read an emitting voxel the majorant is raised
// to at least 1 / h (h the shortest voxel edge), so that delta tracking meets emission where the
// density is 0, about once per voxel length.
// records: S from a compact medium's records (medium/compact_attributes.h), as the render reads it,
// instead of from the medium's SGGX grids.
openvdb::FloatGrid::Ptr buildMajorantGrid(const Medium& medium, Interpolation interpolation,
                                          const openvdb::Vec3SGrid* emission = nullptr,
                                          const CompactAttributes* records = nullptr);

}  // namespace vdbappear
