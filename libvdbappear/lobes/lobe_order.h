#pragma once
// Lobe ordering (§6.2, Eq. 13 of the downsampling paper): the voxels of one cluster share weight
// factors per lobe index, so each voxel's lobes are permuted to match the shapes of a reference
// voxel's lobes. Light header.

#include "libvdbappear/lobes/ndf_quadrature.h"

#include <vector>

namespace vdbappear {

// The most lobes a voxel may have: the brute-force search tries up to kMaxOrderedLobes! orders.
inline constexpr int kMaxOrderedLobes = 5;

// Eq. (13): slot[j], the reference lobe that the voxel's lobe j takes, minimising
//   sum_j integral (D_reference[slot[j]] - D_lobes[j])^2 dm
// over every injective assignment (brute force). The voxel may have fewer lobes than the reference
// (then they take a subset of its slots) but not more. Ties: the first order in lexicographic order
// of the slots, so the identity wins among equals.
std::vector<int> matchLobeSlots(const std::vector<NdfSamples>& reference, const std::vector<NdfSamples>& lobes);

}  // namespace vdbappear
