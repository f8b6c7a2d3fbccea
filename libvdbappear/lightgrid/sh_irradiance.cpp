#include "libvdbappear/lightgrid/sh_irradiance.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/legendre.h"
#include "libvdbappear/math/spherical_harmonics.h"
#include "libvdbappear/medium/scattering_function.h"

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

std::vector<Vec3> shBandSums(const std::vector<Vec3>& coeffs, int lmax, const Vec3& u) {
  const std::vector<double> Y = evalSphericalHarmonics(lmax, u);
  std::vector<Vec3> bands(lmax + 1, Vec3::Zero());
  for (int l = 0; l <= lmax; ++l)
    for (int m = -l; m <= l; ++m) bands[l] += Y[shIndex(l, m)] * coeffs[shIndex(l, m)];
  return bands;
}

Vec3 shIrradiance(const std::vector<Vec3>& coeffs, const std::vector<double>& A, const Vec3& normal) {
  const std::vector<Vec3> bands = shBandSums(coeffs, int(A.size()) - 1, normal);
  Vec3 E = Vec3::Zero();
  for (std::size_t l = 0; l < bands.size(); ++l) E += A[l] * bands[l];
  return E;
}

std::optional<Rgb> shSingleScattering(const ScatteringFunction& f, const std::vector<Vec3>& coeffs, int lmax, const Vec3& wi) {
  for (int j = 0; j < f.lobeCount(); ++j)
    if (!f.lobe(j).hasClosedFormMoments()) return std::nullopt;
  const std::vector<Vec3> bands = shBandSums(coeffs, lmax, -wi);
  Rgb L = Rgb::Zero();
  for (int j = 0; j < f.lobeCount(); ++j) {
    Vec3 lobe = Vec3::Zero();
    for (int l = 0; l <= lmax; ++l) lobe += f.lobe(j).legendreMoment(l) * bands[l];
    L += f.weight(j) * lobe.array();
  }
  return L;
}

}  // namespace vdbappear
