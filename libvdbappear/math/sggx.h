#pragma once
// The SGGX microflake distribution and its specular microflake phase function:
// Heitz, Dupuy, Crassin, Dachsbacher 2015, "The SGGX Microflake Distribution" (SIGGRAPH),
// as used by Eq. (3)-(5) of the downsampling paper (Zhao et al. 2016).
//
// Conventions (as in Mitsuba 3 and pbrt-v4): wi and wo are unit vectors that both point away
// from the scattering point; wi points back toward where the path came from. Microflakes are
// two-sided mirrors: D(m) = D(-m).

#include "libvdbappear/math/vector.h"

#include <cmath>

namespace vdbappear {

// A direction sampled from a phase function. weight = f / pdf.
struct PhaseSample {
  Vec3 wo;
  double pdf = 0;
  double weight = 0;
};

// S from the medium's channels: diag = (Sxx, Syy, Szz), offdiag = (Sxy, Sxz, Syz).
Mat3 sggxMatrix(const Vec3& diag, const Vec3& offdiag);
// The inverse of sggxMatrix: the channels of a symmetric S.
inline Vec3 sggxDiagonal(const Mat3& S) { return {S(0, 0), S(1, 1), S(2, 2)}; }
inline Vec3 sggxOffDiagonal(const Mat3& S) { return {S(0, 1), S(0, 2), S(1, 2)}; }

// Is sggxMatrix(diag, offdiag) positive definite? Sylvester's criterion on the leading principal
// minors, in double precision, without tolerance; false for non-finite entries.
inline bool isPositiveDefinite(const Vec3& diag, const Vec3& offdiag) {
  const double xx = diag.x(), yy = diag.y(), zz = diag.z(), xy = offdiag.x(), xz = offdiag.y(), yz = offdiag.z();
  const double minor2 = xx * yy - xy * xy;
  const double det = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
  const bool finite = std::isfinite(xx + yy + zz + xy + xz + yz);
  return finite && xx > 0 && minor2 > 0 && det > 0;  // false for NaN too
}

class Sggx {
 public:
  Sggx() : S_(Mat3::Identity()), S_inverse_(Mat3::Identity()), sqrt_det_S_(1) {}  // isotropic flakes
  // S must be symmetric positive definite (check with isPositiveDefinite).
  explicit Sggx(const Mat3& S);
  // S from the medium's channels, as sggxMatrix(diag, offdiag).
  Sggx(const Vec3& diag, const Vec3& offdiag);

  // Fiber-like flakes around a fiber with tangent t (normalised here): the flake normals lie mostly in the
  // plane orthogonal to t. S = (I - t t^T) + roughness^2 t t^T (Heitz et al. 2015, §4).
  // The eigenvector with the smallest eigenvalue (roughness^2) is the tangent.
  static Mat3 fiberMatrix(const Vec3& t, double roughness);
  static Sggx fromFiberTangent(const Vec3& t, double roughness) { return Sggx(fiberMatrix(t, roughness)); }

  // Surface-like flakes with normal n (normalised here): S = n n^T + roughness^2 (I - n n^T).
  static Mat3 surfaceMatrix(const Vec3& n, double roughness);
  static Sggx fromSurfaceNormal(const Vec3& n, double roughness) { return Sggx(surfaceMatrix(n, roughness)); }

  const Mat3& S() const { return S_; }

  // Projected area of the flakes toward w: sigma(w) = sqrt(w^T S w) = integral of D(m) <w,m>+ dm.
  // Extinction toward w is rho * sigma(w).
  double sigma(const Vec3& w) const;

  // Eq. (4), downsampling paper: D(m) = 1 / (pi sqrt|S| (m^T S^-1 m)^2).
  double D(const Vec3& m) const;

  // Distribution of visible normals: D_wi(m) = <wi,m>+ D(m) / sigma(wi).
  double visibleNormalPdf(const Vec3& wi, const Vec3& m) const;

  // Samples m from D_wi (Heitz et al. 2015, Appendix: "sampling the VNDF"). u in [0,1)^2.
  Vec3 sampleVisibleNormal(const Vec3& wi, const Point2& u) const;

  // Specular microflake phase function, f(wi -> wo) = D(wh) / (4 sigma(wi)), wh = (wi+wo)/|wi+wo|.
  // It integrates to 1 over wo; note f(wi->wo) sigma(wi) = f(wo->wi) sigma(wo).
  double phase(const Vec3& wi, const Vec3& wo) const;

  // Samples wo by reflecting wi about a visible normal; pdf = phase(wi, wo), so weight = 1
  // (0 in the measure-zero case of a normal at grazing incidence, where pdf = 0).
  PhaseSample samplePhase(const Vec3& wi, const Point2& u) const;

 private:
  // sampleVisibleNormal, also giving sigma(wi), which samplePhase's pdf needs.
  Vec3 sampleVisibleNormal(const Vec3& wi, const Point2& u, double* sigma_wi) const;

  Mat3 S_;
  Mat3 S_inverse_;
  double sqrt_det_S_;
};

}  // namespace vdbappear
