#pragma once
// Normal distributions as mixtures of von Mises-Fisher lobes, Eq. (4.4) of the displacement chapter
// (shared/papers/002_6a636dc24396287c.txt, after Han et al. 2007): D(w) = sum_i alpha_i
// gamma(w; kappa_i, mu_i), gamma(w; kappa, mu) = kappa / (4 pi sinh kappa) exp(kappa (w . mu)).
// The fit is weighted EM on directions (Banerjee et al. 2005) seeded by k-means.

#include "libvdbappear/math/vector.h"

#include <cstdint>
#include <vector>

namespace vdbappear {

// gamma(w; kappa, mu), evaluated as kappa / (2 pi (1 - e^{-2 kappa})) e^{kappa (w . mu - 1)} so that
// large kappa does not overflow; kappa -> 0 gives 1 / (4 pi).
double vmf(const Vec3& w, double kappa, const Vec3& mu);
// A direction drawn from gamma (Wood 1994): w = 1 + log(u1 + (1 - u1) e^{-2 kappa}) / kappa about mu.
Vec3 sampleVmf(double kappa, const Vec3& mu, const Point2& u);

struct VmfLobe {
  double amplitude = 0;  // alpha_i
  double kappa = 0;      // bandwidth
  Vec3 mu = Vec3(0, 0, 1);
};

struct VmfMixture {
  std::vector<VmfLobe> lobes;
  double operator()(const Vec3& w) const;  // sum_i alpha_i gamma(w; kappa_i, mu_i)
};

struct VmfFitSettings {
  int lobes = 6;               // six per patch NDF, as in §4.7.1
  int max_iterations = 200;    // EM iterations; stops earlier when the log-likelihood settles
  double max_kappa = 1e5;      // a patch whose normals coincide gets this bandwidth
  std::uint64_t seed = 1;      // the k-means seeding's stream
};

// The mixture of at most settings.lobes lobes that maximises sum_n w_n log sum_i pi_i gamma(d_n),
// amplitudes pi_i summing to 1 (a density on the sphere). Fewer lobes when there are fewer distinct
// directions. Throws std::invalid_argument on empty input or non-positive weights.
VmfMixture fitVmfMixture(const std::vector<Vec3>& directions, const std::vector<double>& weights,
                         const VmfFitSettings& settings);

}  // namespace vdbappear
