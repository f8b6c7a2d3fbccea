#pragma once
// The downsampled displacement map h_low of the displacement chapter, §4.4.1
// (shared/papers/002_6a636dc24396287c.txt): the coarse heights whose bilinear patches have the
// average slopes of the original micro-surface, by least squares on
//   L(h_low) = sum_uv |s~_uv - s~*_uv|^2 + w sum |Delta h_low|^2        (Eq. 4.10)
// with s~_uv from the patch's corners (Eq. 4.9) and s~*_uv the original's mean slope (Eq. 4.1).

#include "libvdbappear/surface/height_field.h"

namespace vdbappear {

struct HeightDownsampleSettings {
  int factor = 8;                  // coarse cell side in fine cells; divides both cell counts
  double smoothness_weight = 0.01;  // w of Eq. (4.10)
};

// The chapter leaves Delta's scale open. Here Delta h at an interior coarse vertex is the 5-point
// stencil in grid steps divided by the coarse cell size (the change of slope across one cell), so
// both terms of Eq. (4.10) are slopes and w means the same at every scale (docs/displacement.md §2).
// Slopes and Delta leave the mean height free: h_low takes the original's mean height.
// Throws std::invalid_argument when the factor does not divide the cell counts or w < 0.
HeightField downsampleHeights(const HeightField& fine, const HeightDownsampleSettings& settings);

// The point-sampled coarse map, h(u, v) = h_orig(u F, v F): the baseline that slope preservation
// is measured against.
HeightField decimateHeights(const HeightField& fine, int factor);

// The RMS over the coarse cells of |s~_uv(coarse) - s~*_uv(fine)|: how well a coarse map keeps the
// original's meso-scale slopes.
double slopeErrorRms(const HeightField& fine, const HeightField& coarse);

}  // namespace vdbappear
