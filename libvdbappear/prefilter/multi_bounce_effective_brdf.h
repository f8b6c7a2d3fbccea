#pragma once
// The multi-bounce effective BRDF of Eq. (4.15)-(4.17) in the displacement chapter
// (shared/papers/002_6a636dc24396287c.txt, §4.5.1): the reflectance of a patch with the light's
// interreflections inside its micro-geometry, the average over the patch of the path integral
//   r(x1, wi, wo) = int h(x1 ... xk) dmu,  h = V(xk, wi) prod_j f(xj, w_j->j+1, w_j->j-1) <n(xj), w_j->j+1>,
// weighted by the visible projected area A_G(p, wo) as in Eq. (4.6). Restricted to one vertex it is
// the single-bounce effective BRDF (prefilter/effective_brdf.h), on the same base positions.

#include "libvdbappear/prefilter/effective_brdf.h"
#include "libvdbappear/surface/microfacet_brdf.h"

#include <functional>
#include <vector>

namespace vdbappear {

// How light scatters at the points of a micro-geometry, directions in the base frame, wi toward the
// light and wo toward the viewer: f (without the cosine) and a sampled wi with the weight
// f <n, wi> / pdf, n the point's normal. What a path of Eq. (4.15) needs.
struct PatchScattering {
  std::function<Rgb(const MicroGeometry::Point& x, const Vec3& wi, const Vec3& wo)> eval;
  std::function<BrdfSample(const MicroGeometry::Point& x, const Vec3& wo, double u_lobe, const Point2& u)> sample;
};

// The same microfacet BRDF everywhere, in the frame of each micro-normal (f_orig).
PatchScattering microfacetScattering(const MicrofacetBrdf& f);

struct MultiBounceSettings {
  int samples_per_side = 50;  // stratified base positions, one path each: 2500 paths (§4.7.1)
  int max_vertices = 32;      // k of Eq. (4.15) at most; longer paths are dropped (a bias, tested small)
  std::uint64_t seed = 1;
};

// Over the count x count cells from cell (i0, j0): paths start at base positions p (jittered, as
// effectiveBrdf()), continue by sampling f and meet the light wi by a visibility test at every
// vertex, the next-event form of Eq. (4.16) for a directional light.
EffectiveBrdf multiBounceEffectiveBrdf(const MicroGeometry& geometry, int i0, int j0, int count,
                                       const PatchScattering& f, const Vec3& wi, const Vec3& wo,
                                       const MultiBounceSettings& settings);
// The same for many light directions at once, from the same positions and paths: a path's
// directions do not depend on wi, and each vertex meets every wi by a visibility test of its own.
// out[k] for wis[k], each equal to multiBounceEffectiveBrdf() of wis[k] alone (up to rounding).
std::vector<EffectiveBrdf> multiBounceEffectiveBrdfs(const MicroGeometry& geometry, int i0, int j0, int count,
                                                     const PatchScattering& f, const std::vector<Vec3>& wis,
                                                     const Vec3& wo, const MultiBounceSettings& settings);
inline EffectiveBrdf multiBounceEffectiveBrdf(const MicroGeometry& geometry, int i0, int j0, int count,
                                              const MicrofacetBrdf& f, const Vec3& wi, const Vec3& wo,
                                              const MultiBounceSettings& settings) {
  return multiBounceEffectiveBrdf(geometry, i0, j0, count, microfacetScattering(f), wi, wo, settings);
}

}  // namespace vdbappear
