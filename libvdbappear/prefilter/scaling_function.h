#pragma once
// The scaling function R of Eq. (4.12) in the displacement chapter (shared/papers/002_6a636dc24396287c.txt,
// §4.4.3) at one coarse patch and one pair of directions: the original's effective BRDF over the
// prefiltered model's (h_low with f'_low), so that f_low = R f'_low (Eq. 4.13) gives the patch the
// original's aggregate reflectance under single bounces. Footnote 2's epsilon keeps the ratio finite.

#include "libvdbappear/prefilter/effective_brdf.h"

namespace vdbappear {

struct PatchPair {
  const MicroGeometry& original;  // h_orig
  const MicroGeometry& low;       // h_low: one coarse cell per `factor` x `factor` fine cells
  int factor;
};

// R at coarse cell (u, v), per channel: f_eff(G_orig, f_orig) / (f_eff(G_low, f'_low) + epsilon).
Rgb scalingFactor(const PatchPair& patches, int u, int v, const PatchBrdf& f_orig, const PatchBrdf& f_low,
                  const Vec3& wi, const Vec3& wo, const EffectiveBrdfSettings& settings, double epsilon = 1e-6);

}  // namespace vdbappear
