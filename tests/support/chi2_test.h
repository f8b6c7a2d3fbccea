#pragma once
// Pearson's chi-square test of a direction sampler against its pdf (after Mitsuba 3's
// ChiSquareTest): directions are binned in (cos theta, phi) about a frame, expected counts come
// from integrating the pdf over each bin, bins expecting fewer than 5 samples are pooled.

#include "sphere_quadrature.h"

#include <cstdint>
#include <string>

namespace vdbappear::test {

struct Chi2Options {
  SphereGrid bins{Frame::fromNormal(Vec3(0, 0, 1)), 20, 40};
  int cells_per_bin = 2;            // each bin integrated as cells_per_bin^2 adaptive cells
  std::uint64_t sample_count = 1'000'000;
  std::uint64_t seed = 1;
  double significance = 0.01;       // before the Sidak correction for the number of tests
  int test_count = 1;               // tests in the suite, for the Sidak correction
  // A sampler that may fail (a BRDF's reflection below the horizon) returns a non-unit vector; its
  // pdf then integrates to 1 - P(failure). With absorbed_samples, the failed fraction must match
  // 1 - the pdf's integral to within five standard errors; without, no sample may fail.
  bool absorbed_samples = false;
};

struct Chi2Result {
  bool passed = false;
  double p_value = 0;
  double statistic = 0;
  int degrees_of_freedom = 0;
  double pdf_integral = 0;          // integral of the pdf over the sphere: should be 1
  double invalid_fraction = 0;      // samples that were not unit vectors
  std::string summary;              // for failure messages
};

using DirectionSampler = std::function<Vec3(const Point2& u)>;

Chi2Result chi2TestDirections(const DirectionSampler& sample, const SphereFunction& pdf, const Chi2Options& options);

}  // namespace vdbappear::test
