#pragma once
// A translucent object's homogeneous interior, given the project's way (docs/subsurface.md §1):
// extinction sigma_t per world unit (grey or per channel), single-scattering albedo, HG asymmetry g,
// and the relative index of refraction eta of its boundary.

#include "libvdbappear/math/rgb.h"

#include <string>

namespace vdbappear {

struct TranslucentMaterial {
  Rgb sigma_t = Rgb::Constant(100);  // extinction, 1 / world unit
  Rgb albedo = Rgb::Constant(0.99);  // sigma_s / sigma_t
  double g = 0;                      // HG asymmetry of the interior's phase function
  double eta = 1.3;                  // n_inside / n_outside

  Rgb sigmaS() const { return albedo * sigma_t; }
  Rgb sigmaA() const { return (1 - albedo) * sigma_t; }
};

// Throws std::invalid_argument "WHERE: what is wrong" for a negative or non-finite sigma_t, an
// albedo outside [0, 1], |g| >= 1 or eta outside (0, 10], and for an interior that neither absorbs nor
// scatters in some channel (sigma_t' = 0: the dipole has no length scale there).
void validateTranslucentMaterial(const TranslucentMaterial& material, const std::string& where);

}  // namespace vdbappear
