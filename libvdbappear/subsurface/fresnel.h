#pragma once
// Fresnel terms of a smooth dielectric boundary, for the dipole BSSRDF (§2.3, translucent-caching
// seed). eta is the relative index of refraction n_inside / n_outside (1.3 for Jensen et al. 2001's
// materials; 1 for an index-matched boundary, which neither reflects nor refracts).

namespace vdbappear {

// Unpolarised Fresnel reflectance of light arriving from outside at cos_theta (> 0) to the normal.
// 1 past the critical angle (eta < 1).
double fresnelReflectance(double cos_theta, double eta);
inline double fresnelTransmittance(double cos_theta, double eta) { return 1 - fresnelReflectance(cos_theta, eta); }

// The diffuse Fresnel reflectance F_dr(eta) of the dipole's boundary condition: the reflectance of
// the boundary, seen from inside, to light arriving with a cosine-weighted (diffuse) distribution,
// 2 int_0^1 F_r(mu, 1/eta) mu dmu, integrated numerically. The seed quotes the rational fit
// -1.440/eta^2 + 0.710/eta + 0.668 + 0.0636 eta (§2.3); it agrees within 4e-4 for eta in [1.2, 1.5]
// but leaves 1.6e-3 at eta = 1, where an index-matched boundary reflects nothing (tested).
// diffuseFresnelReflectance(1 / eta) is the outside one: of light arriving diffusely from outside.
double diffuseFresnelReflectance(double eta);
inline double diffuseFresnelTransmittance(double eta) { return 1 - diffuseFresnelReflectance(eta); }

}  // namespace vdbappear
