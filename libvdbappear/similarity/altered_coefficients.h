#pragma once
// Per-voxel altered coefficients of the similarity relations (sigma_a* = sigma_a,
// sigma_s* = alpha sigma_s, Algorithm 1 line 2) for the project's media, where the extinction
// (density) is one number and the albedo has three channels. Light header.
//
// Colour. One density and one phase function serve all three channels, so the relations can hold
// exactly for one albedo only: the reference albedo a_ref. The voxel gets
//   density* = density r,  r = 1 - a_ref (1 - alpha)   (sigma_t* of the reference channel),
//   albedo*_c = 1 - (1 - a_c) / r                      (sigma_a* = sigma_a in every channel),
// so absorption is kept exactly in every channel and sigma_s* = alpha sigma_s holds for a_c = a_ref
// (a grey albedo: exactly). Channel c then scatters with alpha_c = 1 - (a_ref / a_c)(1 - alpha)
// instead of alpha, and its order-n reduced attenuation (Eq. 11) is off by
//   density (1 - f_n)(a_c - a_ref)(1 - alpha) / alpha.
// a_ref is chosen to minimise the largest relative error of the order-1 term over the channels,
// max_c |a_c - a_ref| / (1 - a_c f_1) (a channel with a high albedo weighs more: its sigma_tr,1 is
// small), subject to a_ref (1 - alpha) <= min_c a_c: a channel with a_c < a_ref (1 - alpha) would
// need negative scattering (it then gets albedo 0 and absorption stays exact).

#include "libvdbappear/math/rgb.h"

namespace vdbappear {

struct AlteredCoefficients {
  double density = 0;
  Rgb albedo;
  // max_c |sigma_tr,1*(c) - sigma_tr,1(c)| / sigma_tr,1(c): 0 for a grey albedo.
  double reduced_attenuation_error = 0;
};

// The a_ref above, for an albedo, the original phase function's mean cosine f_1 and alpha.
double referenceAlbedo(const Rgb& albedo, double f1, double alpha);

AlteredCoefficients alterCoefficients(double density, const Rgb& albedo, double alpha, double f1);

}  // namespace vdbappear
