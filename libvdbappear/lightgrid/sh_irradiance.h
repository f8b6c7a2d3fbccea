#pragma once
// Diffuse (unshadowed) irradiance from SH lighting, by the Funk-Hecke theorem: the clamped cosine
// max(0, n . w) is zonal about n, so E(n) = sum_l A_l sum_m L_lm Y_lm(n) with
// A_l = 2 pi int_0^1 mu P_l(mu) d mu (Ramamoorthi and Hanrahan 2001: A_0 = pi, A_1 = 2 pi / 3,
// A_2 = pi / 4, A_l = 0 for odd l > 1).

#include "libvdbappear/math/vector.h"

#include <vector>

namespace vdbappear {

std::vector<double> clampedCosineCoefficients(int lmax);  // A_0 .. A_lmax

// E(n) per channel for RGB coefficients indexed l (l + 1) + m; the second form takes the A_l.
Vec3 shIrradiance(const std::vector<Vec3>& coeffs, int lmax, const Vec3& normal);
Vec3 shIrradiance(const std::vector<Vec3>& coeffs, const std::vector<double>& A, const Vec3& normal);

}  // namespace vdbappear
