#include "libvdbappear/lightgrid/sh_irradiance.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/legendre.h"
#include "libvdbappear/math/spherical_harmonics.h"

#include <boost/math/quadrature/gauss.hpp>

namespace vdbappear {

std::vector<double> clampedCosineCoefficients(int lmax) {
  // mu P_l(mu) has degree l + 1: 12-point Gauss-Legendre is exact up to degree 23 (l <= 22).
  using Rule = boost::math::quadrature::gauss<double, 12>;
  std::vector<double> A(lmax + 1);
  for (int l = 0; l <= lmax; ++l) A[l] = 2 * kPi * Rule::integrate([l](double mu) { return mu * legendrePolynomials(l, mu)[l]; }, 0.0, 1.0);
  return A;
}

Vec3 shIrradiance(const std::vector<Vec3>& coeffs, int lmax, const Vec3& normal) {
  return shIrradiance(coeffs, clampedCosineCoefficients(lmax), normal);
}

Vec3 shIrradiance(const std::vector<Vec3>& coeffs, const std::vector<double>& A, const Vec3& normal) {
  const int lmax = int(A.size()) - 1;
  const std::vector<double> Y = evalSphericalHarmonics(lmax, normal);
  Vec3 E = Vec3::Zero();
  for (int l = 0; l <= lmax; ++l)
    for (int m = -l; m <= l; ++m) E += A[l] * Y[shIndex(l, m)] * coeffs[shIndex(l, m)];
  return E;
}

}  // namespace vdbappear
