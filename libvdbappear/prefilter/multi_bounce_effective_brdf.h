#pragma once
// The multi-bounce effective BRDF of Eq. (4.15)-(4.17) in the displacement chapter
// (shared/papers/002_6a636dc24396287c.txt, §4.5.1): the reflectance of a patch with the light's
// interreflections inside its micro-geometry, the average over the patch of the path integral
//   r(x1, wi, wo) = int h(x1 ... xk) dmu,  h = V(xk, wi) prod_j f(xj, w_j->j+1, w_j->j-1) <n(xj), w_j->j+1>,
// weighted by the visible projected area A_G(p, wo) as in Eq. (4.6). Restricted to one vertex it is
// the single-bounce effective BRDF (prefilter/effective_brdf.h), on the same base positions.

#include "libvdbappear/prefilter/effective_brdf.h"
#include "libvdbappear/surface/microfacet_brdf.h"

namespace vdbappear {

struct MultiBounceSettings {
  int samples_per_side = 50;  // stratified base positions, one path each: 2500 paths (§4.7.1)
  int max_vertices = 32;      // k of Eq. (4.15) at most; longer paths are dropped (a bias, tested small)
  std::uint64_t seed = 1;
};

// Over the count x count cells from cell (i0, j0), with the micro-BRDF f in every micro-normal's
// frame: paths start at base positions p (jittered, as effectiveBrdf()), continue by sampling f
// (its sample() and weight f cos / pdf) and meet the light wi by a visibility test at every
// vertex, the next-event form of Eq. (4.16) for a directional light.
EffectiveBrdf multiBounceEffectiveBrdf(const MicroGeometry& geometry, int i0, int j0, int count,
                                       const MicrofacetBrdf& f, const Vec3& wi, const Vec3& wo,
                                       const MultiBounceSettings& settings);

}  // namespace vdbappear
