#include "libvdbappear/lightgrid/cell_interpolation.h"

namespace vdbappear {

namespace {

Vec3 cornerOffset(int i, const Vec3& size) {
  return Vec3(i & 1 ? size.x() : 0.0, i & 2 ? size.y() : 0.0, i & 4 ? size.z() : 0.0);
}

}  // namespace

double hermite1d(double x, double x_L, double f_L, double df_L, double x_R, double f_R, double df_R) {
  const double dx = x_R - x_L, s = (f_R - f_L) / dx;
  const double a = f_L, b = df_L, c = (s - df_L) / dx, d = (df_L + df_R - 2 * s) / (dx * dx);  // Eq. (5.35)
  const double t = x - x_L;
  return a + b * t + c * t * t + d * t * t * (x - x_R);  // Eq. (5.33)
}

double tricubicHermite(const Vec3& p, const Vec3& size, const CellCorners& c) {
  const double tx = p.x() / size.x(), ty = p.y() / size.y();
  double g[4];
  Vec3 grad_g[4];
  for (int i = 0; i < 4; ++i) {  // along x (Algorithm 4, lines 4-7)
    g[i] = hermite1d(p.x(), 0, c.f[2 * i], c.grad[2 * i].x(), size.x(), c.f[2 * i + 1], c.grad[2 * i + 1].x());
    grad_g[i] = (1 - tx) * c.grad[2 * i] + tx * c.grad[2 * i + 1];
  }
  double h[2];
  Vec3 grad_h[2];
  for (int i = 0; i < 2; ++i) {  // along y (lines 8-11)
    h[i] = hermite1d(p.y(), 0, g[2 * i], grad_g[2 * i].y(), size.y(), g[2 * i + 1], grad_g[2 * i + 1].y());
    grad_h[i] = (1 - ty) * grad_g[2 * i] + ty * grad_g[2 * i + 1];
  }
  return hermite1d(p.z(), 0, h[0], grad_h[0].z(), size.z(), h[1], grad_h[1].z());  // along z (line 12)
}

double trilinear(const Vec3& p, const Vec3& size, const CellCorners& c) {
  const Vec3 t = p.cwiseQuotient(size);
  double sum = 0;
  for (int i = 0; i < 8; ++i)
    sum += (i & 1 ? t.x() : 1 - t.x()) * (i & 2 ? t.y() : 1 - t.y()) * (i & 4 ? t.z() : 1 - t.z()) * c.f[i];
  return sum;
}

double taylorInverseDistance(const Vec3& p, const Vec3& size, const CellCorners& c) {
  double sum = 0, weights = 0;
  for (int i = 0; i < 8; ++i) {
    const Vec3 d = p - cornerOffset(i, size);
    const double d2 = d.squaredNorm();
    if (d2 == 0) return c.f[i];
    const double w = 1 / d2;
    sum += w * (c.f[i] + c.grad[i].dot(d));
    weights += w;
  }
  return sum / weights;
}

double CellWeights::apply(const CellCorners& c) const {
  double q = 0;
  for (int i = 0; i < 8; ++i) q += value[i] * c.f[i] + gradient[i].dot(c.grad[i]);
  return q;
}

namespace {

// Cubic Hermite basis on t in [0, 1] (Eq. 5.33-5.35 rewritten): q = H0 f_L + H1 f_R + h (D0 f'_L + D1 f'_R).
struct HermiteBasis {
  double H[2], D[2], L[2];  // value weights, derivative weights (times the cell size), linear weights
  explicit HermiteBasis(double t, double size) {
    const double t2 = t * t, t3 = t2 * t;
    H[0] = 2 * t3 - 3 * t2 + 1;
    H[1] = -2 * t3 + 3 * t2;
    D[0] = size * (t3 - 2 * t2 + t);
    D[1] = size * (t3 - t2);
    L[0] = 1 - t;
    L[1] = t;
  }
};

}  // namespace

// Closed forms of the three interpolants' weights. Algorithm 4 is cubic Hermite along x, then y,
// then z, with the gradients of the intermediate points interpolated linearly, so corner (bx, by, bz)
// weighs its value by H(bx) H(by) H(bz), its x-derivative by D(bx) H(by) H(bz), its y-derivative by
// L(bx) D(by) H(bz) and its z-derivative by L(bx) L(by) D(bz).
CellWeights cellWeights(CellInterpolation method, const Vec3& p, const Vec3& size) {
  CellWeights w;
  if (method == CellInterpolation::kTaylor) {
    double total = 0;
    for (int i = 0; i < 8; ++i) {
      const Vec3 d = p - cornerOffset(i, size);
      const double d2 = d.squaredNorm();
      if (d2 == 0) {  // at a corner: its value
        for (int k = 0; k < 8; ++k) {
          w.value[k] = k == i ? 1 : 0;
          w.gradient[k] = Vec3::Zero();
        }
        return w;
      }
      w.value[i] = 1 / d2;
      w.gradient[i] = d / d2;
      total += 1 / d2;
    }
    for (int i = 0; i < 8; ++i) {
      w.value[i] /= total;
      w.gradient[i] /= total;
    }
    return w;
  }
  const HermiteBasis x(p.x() / size.x(), size.x()), y(p.y() / size.y(), size.y()), z(p.z() / size.z(), size.z());
  for (int i = 0; i < 8; ++i) {
    const int bx = i & 1, by = i >> 1 & 1, bz = i >> 2 & 1;
    if (method == CellInterpolation::kTrilinear) {
      w.value[i] = x.L[bx] * y.L[by] * z.L[bz];
      w.gradient[i] = Vec3::Zero();
    } else {
      w.value[i] = x.H[bx] * y.H[by] * z.H[bz];
      w.gradient[i] = Vec3(x.D[bx] * y.H[by] * z.H[bz], x.L[bx] * y.D[by] * z.H[bz], x.L[bx] * y.L[by] * z.D[bz]);
    }
  }
  return w;
}

}  // namespace vdbappear
