#include "libvdbappear/math/sggx.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/frame.h"

#include <Eigen/LU>

#include <cmath>

namespace vdbappear {

Sggx::Sggx(const Mat3& S) : Sggx(sggxDiagonal(S), sggxOffDiagonal(S)) {}

// S^-1 = adj(S) / |S| from the six cofactors of the symmetric S (S is SPD: |S| > 0).
Sggx::Sggx(const Vec3& diag, const Vec3& offdiag) {
  const double xx = diag.x(), yy = diag.y(), zz = diag.z(), xy = offdiag.x(), xz = offdiag.y(), yz = offdiag.z();
  S_ << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  const double c_xx = yy * zz - yz * yz, c_xy = xz * yz - xy * zz, c_xz = xy * yz - xz * yy;
  const double c_yy = xx * zz - xz * xz, c_yz = xy * xz - xx * yz, c_zz = xx * yy - xy * xy;
  const double det = xx * c_xx + xy * c_xy + xz * c_xz;
  const double inv_det = 1 / det;
  S_inverse_ << c_xx * inv_det, c_xy * inv_det, c_xz * inv_det,  //
      c_xy * inv_det, c_yy * inv_det, c_yz * inv_det,             //
      c_xz * inv_det, c_yz * inv_det, c_zz * inv_det;
  sqrt_det_S_ = std::sqrt(det);
}

Mat3 sggxMatrix(const Vec3& diag, const Vec3& offdiag) {
  Mat3 S;
  S << diag.x(), offdiag.x(), offdiag.y(),  //
      offdiag.x(), diag.y(), offdiag.z(),   //
      offdiag.y(), offdiag.z(), diag.z();
  return S;
}

Mat3 Sggx::fiberMatrix(const Vec3& tangent, double roughness) {
  const Vec3 t = tangent.normalized();
  const Mat3 ttT = t * t.transpose();
  return (Mat3::Identity() - ttT) + roughness * roughness * ttT;
}

Mat3 Sggx::surfaceMatrix(const Vec3& normal, double roughness) {
  const Vec3 n = normal.normalized();
  const Mat3 nnT = n * n.transpose();
  return nnT + roughness * roughness * (Mat3::Identity() - nnT);
}

double Sggx::sigma(const Vec3& w) const { return std::sqrt(std::max(0.0, w.dot(S_ * w))); }

double Sggx::D(const Vec3& m) const {
  const double q = m.dot(S_inverse_ * m);
  return 1.0 / (kPi * sqrt_det_S_ * q * q);
}

double Sggx::visibleNormalPdf(const Vec3& wi, const Vec3& m) const {
  const double cos_theta = wi.dot(m);
  if (cos_theta <= 0) return 0;
  return cos_theta * D(m) / sigma(wi);
}

Vec3 Sggx::sampleVisibleNormal(const Vec3& wi, const Point2& u) const {
  double sigma_wi;
  return sampleVisibleNormal(wi, u, &sigma_wi);
}

Vec3 Sggx::sampleVisibleNormal(const Vec3& wi, const Point2& u, double* sigma_wi) const {
  // A cosine-distributed point (u1, u2, u3) on the hemisphere around wi ...
  const double r = std::sqrt(u.x());
  const double phi = 2 * kPi * u.y();
  const double u1 = r * std::cos(phi), u2 = r * std::sin(phi);
  const double u3 = std::sqrt(std::max(0.0, 1 - u1 * u1 - u2 * u2));

  // ... mapped through the square root of S expressed in the frame (wk, wj, wi).
  const Frame frame = Frame::fromNormal(wi);
  const Vec3 &wk = frame.s, &wj = frame.t;
  const Vec3 S_wi = S_ * wi, S_wj = S_ * wj;
  const double S_jj = wj.dot(S_wj), S_ii = wi.dot(S_wi);
  const double S_kj = wk.dot(S_wj), S_ki = wk.dot(S_wi), S_ji = wj.dot(S_wi);
  *sigma_wi = std::sqrt(std::max(0.0, S_ii));
  const double sqrt_det_S_kji = sqrt_det_S_;  // the determinant does not depend on the frame
  const double inv_sqrt_S_ii = 1 / std::sqrt(S_ii);
  const double tmp = std::sqrt(std::max(1e-300, S_jj * S_ii - S_ji * S_ji));
  const Vec3 M_k(sqrt_det_S_kji / tmp, 0, 0);
  const Vec3 M_j(-inv_sqrt_S_ii * (S_ki * S_ji - S_kj * S_ii) / tmp, inv_sqrt_S_ii * tmp, 0);
  const Vec3 M_i(inv_sqrt_S_ii * S_ki, inv_sqrt_S_ii * S_ji, inv_sqrt_S_ii * S_ii);
  const Vec3 m_kji = (u1 * M_k + u2 * M_j + u3 * M_i).normalized();
  return frame.toWorld(m_kji);
}

double Sggx::phase(const Vec3& wi, const Vec3& wo) const {
  const Vec3 h = wi + wo;
  const double length = h.norm();
  if (length == 0) return 0;
  return D(h / length) / (4 * sigma(wi));
}

PhaseSample Sggx::samplePhase(const Vec3& wi, const Point2& u) const {
  double sigma_wi;
  const Vec3 m = sampleVisibleNormal(wi, u, &sigma_wi);
  const Vec3 wo = reflect(wi, m).normalized();
  // pdf = D_wi(m) / (4 |wi.m|) = D(m) / (4 sigma(wi)) = phase(wi, wo), with the half vector m
  // itself rather than (wi + wo) / |wi + wo| recomputed from wo (the same up to rounding).
  const double pdf = wi.dot(m) != 0 && sigma_wi > 0 ? D(m) / (4 * sigma_wi) : 0.0;
  return {wo, pdf, pdf > 0 ? 1.0 : 0.0};
}

}  // namespace vdbappear
