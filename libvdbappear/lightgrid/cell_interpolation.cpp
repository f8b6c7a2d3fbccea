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

CellWeights cellWeights(CellInterpolation method, const Vec3& p, const Vec3& size) {
  const auto interpolate = [&](const CellCorners& c) {
    switch (method) {
      case CellInterpolation::kHermite: return tricubicHermite(p, size, c);
      case CellInterpolation::kTrilinear: return trilinear(p, size, c);
      case CellInterpolation::kTaylor: return taylorInverseDistance(p, size, c);
    }
    return 0.0;
  };
  // The interpolant of unit data at each of the 32 inputs (linearity).
  CellWeights w;
  CellCorners unit;
  for (int i = 0; i < 8; ++i) {
    unit.f[i] = 0;
    unit.grad[i] = Vec3::Zero();
  }
  for (int i = 0; i < 8; ++i) {
    unit.f[i] = 1;
    w.value[i] = interpolate(unit);
    unit.f[i] = 0;
    for (int axis = 0; axis < 3; ++axis) {
      unit.grad[i][axis] = 1;
      w.gradient[i][axis] = interpolate(unit);
      unit.grad[i][axis] = 0;
    }
  }
  return w;
}

}  // namespace vdbappear
