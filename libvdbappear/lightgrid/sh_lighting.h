#pragma once
// RGB spherical-harmonic lighting of many polygonal lights at one point: the lights' SH
// coefficients and gradients (polygon_sh.h) weighted by their radiance and summed (Algorithm 1,
// lines 4-8, dissertation ch. 5). Unshadowed: every light is seen whole.

#include "libvdbappear/lightgrid/polygon_light.h"
#include "libvdbappear/math/vector.h"

#include <vector>

namespace vdbappear {

class ZonalFactorisation;

struct ShLighting {
  std::vector<Vec3> coeffs;     // [l (l + 1) + m]: (r, g, b)
  std::vector<Mat3> gradients;  // [l (l + 1) + m]: row c is the gradient of channel c

  explicit ShLighting(int count = 0) : coeffs(count, Vec3::Zero()), gradients(count, Mat3::Zero()) {}
};

ShLighting shLighting(const std::vector<PolygonLight>& lights, const Vec3& x, const ZonalFactorisation& zh);

// Radiance arriving at x from the lights in direction w (pointing from x toward the light),
// reconstructed from the band-limited coefficients: L(x, w) = sum_i L_i Y_i(w).
Vec3 incidentRadiance(const std::vector<Vec3>& coeffs, int lmax, const Vec3& towards_light);

// The unit direction of the band-1 part of the radiance, integral of L(w) w dw averaged over the
// channels: with the Condon-Shortley basis (docs/sh_lightgrid.md §1) it is proportional to
// (-L_1,1, -L_1,-1, L_1,0). The zero vector when that part vanishes (lmax 0, or light from all
// sides alike).
Vec3 dominantDirection(const std::vector<Vec3>& coeffs);

}  // namespace vdbappear
