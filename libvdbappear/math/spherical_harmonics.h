#pragma once
// Real spherical harmonics, Eq. (2.16)-(2.17) of the dissertation (Wu 2020):
//   Y_lm = sqrt(2) K_lm sin(|m| phi) P_l^|m|(cos theta)   m < 0
//        = K_l0 P_l^0(cos theta)                          m = 0
//        = sqrt(2) K_lm cos(m phi) P_l^m(cos theta)       m > 0
// with w = (sin theta cos phi, sin theta sin phi, cos theta) and
// K_lm = sqrt((2l+1)/(4 pi) (l-|m|)!/(l+|m|)!).
//
// Sign convention: P_l^m includes the Condon-Shortley phase (-1)^m, as in Sloan's "Stupid SH
// Tricks" and pbrt-v2, so Y_1,-1 = -sqrt(3/(4 pi)) y, Y_1,0 = sqrt(3/(4 pi)) z,
// Y_1,1 = -sqrt(3/(4 pi)) x. The basis is orthonormal over the sphere.
// Coefficients are ordered i = l (l + 1) + m.

#include "libvdbappear/math/vector.h"

#include <vector>

namespace vdbappear {

inline constexpr int shIndex(int l, int m) { return l * (l + 1) + m; }
inline constexpr int shCount(int lmax) { return (lmax + 1) * (lmax + 1); }

// All Y_lm(w) for l <= lmax, in index order; w a unit vector.
std::vector<double> evalSphericalHarmonics(int lmax, const Vec3& w);
// One basis function.
double sphericalHarmonic(int l, int m, const Vec3& w);

}  // namespace vdbappear
