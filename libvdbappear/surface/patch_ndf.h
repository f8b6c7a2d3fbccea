#pragma once
// The patch NDF of Eq. (4.2) in the displacement chapter (shared/papers/002_6a636dc24396287c.txt,
// §4.3, §4.4.2): D(w) = int_P delta(w - w_m(p)) / <w_m(p), w_g> k_P(p) dp over the micro-normals
// w_m of the original height field within a coarse patch P, fitted by six vMF lobes (Eq. 4.4,
// §4.7.1) to give the spatially varying multi-lobe BRDF f'_low (Eq. 4.11).

#include "libvdbappear/surface/height_field.h"
#include "libvdbappear/surface/vmf_ndf.h"

#include <vector>

namespace vdbappear {

// The micro-normals of the count x count fine cells from cell (i0, j0), at points_per_side^2
// cell-centred points of each bilinear cell: n = (-dh/dx, -dh/dy, 1) / |...|. Each stands for the
// same base area, so they are draws of p ~ k_P (a box kernel) and their density is D(w) cos theta.
std::vector<Vec3> patchMicroNormals(const HeightField& field, int i0, int j0, int count, int points_per_side);

// D of Eq. (4.2) as a vMF mixture: EM weighted by 1 / cos theta_m fits D's shape, and the
// amplitudes carry D's mass, int D dw = E_p[1 / cos theta_m], so that the projected area
// int D cos theta dw is 1 (Eq. 4.3) up to the fit's error.
VmfMixture fitPatchNdf(const std::vector<Vec3>& micro_normals, const VmfFitSettings& settings);

}  // namespace vdbappear
