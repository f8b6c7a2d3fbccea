#pragma once
// Unshadowed SH lighting convolved with zonal kernels, by the Funk-Hecke theorem: a kernel k(u . w)
// with Legendre coefficients k_l = 2 pi int_{-1}^{1} k(t) P_l(t) dt turns L(w) = sum L_lm Y_lm(w)
// into sum_l k_l B_l(u), B_l(u) = sum_m L_lm Y_lm(u).
// - Diffuse irradiance: the clamped cosine max(0, n . w) about n, so E(n) = sum_l A_l B_l(n) with
//   A_l = 2 pi int_0^1 mu P_l(mu) d mu (Ramamoorthi and Hanrahan 2001: A_0 = pi, A_1 = 2 pi / 3,
//   A_2 = pi / 4, A_l = 0 for odd l > 1).
// - Single scattering in a medium: a phase function p(mu), mu = -wi . w, about u = -wi, with its
//   Legendre moments f_l (similarity paper, Eq. 8: g^l for HG).

#include "libvdbappear/math/rgb.h"
#include "libvdbappear/math/vector.h"

#include <optional>
#include <vector>

namespace vdbappear {

class ScatteringFunction;

// B_0(u) .. B_lmax(u) of RGB coefficients indexed l (l + 1) + m.
std::vector<Vec3> shBandSums(const std::vector<Vec3>& coeffs, int lmax, const Vec3& u);

std::vector<double> clampedCosineCoefficients(int lmax);  // A_0 .. A_lmax

// E(n) per channel for RGB coefficients indexed l (l + 1) + m; the second form takes the A_l.
Vec3 shIrradiance(const std::vector<Vec3>& coeffs, int lmax, const Vec3& normal);
Vec3 shIrradiance(const std::vector<Vec3>& coeffs, const std::vector<double>& A, const Vec3& normal);

// The single-scattered radiance toward wi, integral of f_s(wi, w) L(w) dw over the sphere:
// sum_j W_j sum_l f_jl B_l(-wi) when every lobe has closed-form Legendre moments (isotropic, HG);
// nullopt otherwise (SGGX lobes, tables), where the caller estimates it by sampling.
std::optional<Rgb> shSingleScattering(const ScatteringFunction& f, const std::vector<Vec3>& coeffs, int lmax, const Vec3& wi);

}  // namespace vdbappear
