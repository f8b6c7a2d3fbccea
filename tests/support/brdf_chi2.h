#pragma once
// The chi-square test of a BRDF's sampler (support/chi2_test.h) whose draws take a number for the
// choice of lobe besides the two that bin the direction: that number follows the golden ratio's
// sequence, equidistributed and unrelated to the other two; a draw of pdf 0 counts as absorbed.

#include "libvdbappear/surface/microfacet_brdf.h"

#include "support/chi2_test.h"

#include <cmath>
#include <functional>

namespace vdbappear::test {

using BrdfSampler = std::function<BrdfSample(double u_lobe, const Point2& u)>;

inline Chi2Result chi2TestBrdfSampling(const BrdfSampler& sample, const SphereFunction& pdf, const Chi2Options& options) {
  double u_lobe = 0;
  return chi2TestDirections(
      [&](const Point2& u) {
        u_lobe = std::fmod(u_lobe + 0.6180339887498949, 1.0);
        const BrdfSample s = sample(u_lobe, u);
        return s.pdf > 0 ? s.wi : Vec3(0, 0, 0);
      },
      pdf, options);
}

}  // namespace vdbappear::test
