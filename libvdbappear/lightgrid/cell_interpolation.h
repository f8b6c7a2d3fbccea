#pragma once
// Interpolation inside one grid cell from the values f_i and gradients grad f_i at its eight
// corners, corner i = x + 2y + 4z (bit 0: +x, bit 1: +y, bit 2: +z). `p` is the point relative to
// corner 0, `size` the cell's extent (dissertation ch. 5, Section 5.6.2).

#include "libvdbappear/math/vector.h"

namespace vdbappear {

struct CellCorners {
  double f[8];
  Vec3 grad[8];
};

enum class CellInterpolation { kHermite, kTrilinear, kTaylor };

// All three interpolants are linear in the corner data, so one point's interpolant is a set of
// weights, q = sum_i value[i] f_i + gradient[i] . grad f_i, computed once (in closed form) and
// applied to every SH coefficient and colour channel.
struct CellWeights {
  double value[8];
  Vec3 gradient[8];

  double apply(const CellCorners& c) const;
};
CellWeights cellWeights(CellInterpolation method, const Vec3& p, const Vec3& size);

// Eq. (5.33)-(5.35), Algorithm 4 HERMITE1D: the cubic with q(x_L) = f_L, q(x_R) = f_R,
// q'(x_L) = f'_L, q'(x_R) = f'_R.
double hermite1d(double x, double x_L, double f_L, double df_L, double x_R, double f_R, double df_R);

// Algorithm 4: cubic Hermite along x, then y, then z; the gradients of the intermediate points are
// interpolated linearly.
double tricubicHermite(const Vec3& p, const Vec3& size, const CellCorners& c);

// Trilinear interpolation of the values (the gradients are not used).
double trilinear(const Vec3& p, const Vec3& size, const CellCorners& c);

// Annen et al. 2004, as the dissertation describes it: the first-order Taylor expansion from each
// corner, f_i + grad f_i . (p - x_i), blended by inverse-distance weights 1 / |p - x_i|^2 (Shepard).
double taylorInverseDistance(const Vec3& p, const Vec3& size, const CellCorners& c);

}  // namespace vdbappear
