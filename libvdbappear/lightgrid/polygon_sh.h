#pragma once
// Analytic SH coefficients and SH gradients of a uniform polygonal light of unit radiance seen
// from a point x (dissertation ch. 5, Algorithms 2 and 3):
//   L_lm(x) = integral over the projected polygon Q(x) of Y_lm(w) dw            Eq. (5.4)
//   grad L_lm(x)                                                                Eq. (5.7)
// Both through the ZH factorisation (Eq. 5.3, 5.5, 5.29) and per-edge integrals of Legendre
// polynomials (Eq. 5.23-5.28, 5.30-5.32).

#include "libvdbappear/math/vector.h"

#include <vector>

namespace vdbappear {

class ZonalFactorisation;

// The edge integrals of one arc w(t) = w_i cos t + lambda_i sin t, t in [0, T], for
// h(t) = c_x cos t + c_y sin t and l = 0..lmax (Algorithm 3):
//   B_l = int P_l(h) dt, C_l = int h P_l(h) dt, E_l = int h'(t) P_l(h) dt.
struct EdgeIntegrals {
  std::vector<double> B, C, E;
};
EdgeIntegrals edgeIntegrals(double c_x, double c_y, double T, int lmax);

struct PolygonSh {
  std::vector<double> coeffs;    // L_lm, index l (l + 1) + m
  std::vector<Vec3> gradients;   // grad L_lm, same index
};

// `polygon`: the light's vertices ordered as verticesFacing() returns them (face normal pointing
// away from x). Returns zeros when x lies in the polygon's plane.
PolygonSh polygonSh(const std::vector<Vec3>& polygon, const Vec3& x, const ZonalFactorisation& zh);

// Solid angle of the projected polygon (the base case of Eq. 5.32), as a sum of signed triangles
// of a fan (Van Oosterom and Strackee's formula, which is robust for thin triangles).
double projectedSolidAngle(const std::vector<Vec3>& directions);

}  // namespace vdbappear
