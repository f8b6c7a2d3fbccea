#include "libvdbappear/math/spherical_harmonics.h"

#include "libvdbappear/math/constants.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {

namespace {

// K_lm of Eq. (2.17) for m >= 0.
double shNormalisation(int l, int m) {
  double ratio = 1;  // (l-m)! / (l+m)!
  for (int k = l - m + 1; k <= l + m; ++k) ratio /= k;
  return std::sqrt((2 * l + 1) / (4 * kPi) * ratio);
}

}  // namespace

std::vector<double> evalSphericalHarmonics(int lmax, const Vec3& w) {
  if (lmax < 0) throw std::invalid_argument("spherical harmonics: lmax must be >= 0");
  std::vector<double> Y(shCount(lmax), 0.0);
  const double z = std::clamp(w.z(), -1.0, 1.0);
  const double sin_theta = std::sqrt(std::max(0.0, 1 - z * z));
  const double phi = std::atan2(w.y(), w.x());
  // Associated Legendre polynomials with the Condon-Shortley phase, column by column in m:
  // P_m^m = (-1)^m (2m-1)!! sin^m, P_{m+1}^m = (2m+1) z P_m^m,
  // (l-m) P_l^m = (2l-1) z P_{l-1}^m - (l+m-1) P_{l-2}^m.
  double P_mm = 1;
  for (int m = 0; m <= lmax; ++m) {
    if (m > 0) P_mm *= -(2 * m - 1) * sin_theta;
    double P_prev = 0, P = P_mm;
    const double c = std::cos(m * phi), s = std::sin(m * phi);
    for (int l = m; l <= lmax; ++l) {
      if (l == m + 1) {
        P_prev = P;
        P = (2 * m + 1) * z * P_mm;
      } else if (l > m + 1) {
        const double next = ((2 * l - 1) * z * P - (l + m - 1) * P_prev) / (l - m);
        P_prev = P;
        P = next;
      }
      const double K = shNormalisation(l, m);
      if (m == 0) {
        Y[shIndex(l, 0)] = K * P;
      } else {
        Y[shIndex(l, m)] = std::sqrt(2.0) * K * c * P;
        Y[shIndex(l, -m)] = std::sqrt(2.0) * K * s * P;
      }
    }
  }
  return Y;
}

double sphericalHarmonic(int l, int m, const Vec3& w) {
  if (l < 0 || m < -l || m > l) throw std::invalid_argument("spherical harmonics: need l >= 0 and |m| <= l");
  return evalSphericalHarmonics(l, w)[shIndex(l, m)];
}

}  // namespace vdbappear
