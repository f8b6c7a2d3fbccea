#include "libvdbappear/subsurface/dipole.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/subsurface/fresnel.h"

#include <algorithm>
#include <cmath>

namespace vdbappear {

DipoleProfile::DipoleProfile(double sigma_s, double sigma_a, double g, double eta) {
  const double sigma_s_reduced = sigma_s * (1 - g);
  const double sigma_t_reduced = sigma_a + sigma_s_reduced;
  alpha_prime_ = sigma_s_reduced / sigma_t_reduced;
  sigma_tr_ = std::sqrt(3 * sigma_a * sigma_t_reduced);
  const double F_dr = diffuseFresnelReflectance(eta);
  A_ = (1 + F_dr) / (1 - F_dr);
  z_r_ = 1 / sigma_t_reduced;
  z_v_ = z_r_ * (1 + 4 * A_ / 3);
}

double DipoleProfile::Rd(double r) const {
  const double s_r = std::sqrt(r * r + z_r_ * z_r_), s_v = std::sqrt(r * r + z_v_ * z_v_);
  const auto source = [&](double z, double s) { return z * (1 + sigma_tr_ * s) * std::exp(-sigma_tr_ * s) / (s * s * s); };
  return alpha_prime_ / (4 * kPi) * (source(z_r_, s_r) + source(z_v_, s_v));
}

Vec3 DipoleProfile::gradRs(const Vec3& x) const {
  const double r2 = x.squaredNorm();
  const auto slope = [&](double z) {  // -(1/|x|) d/d|x| of one source's term
    const double s = std::sqrt(r2 + z * z);
    return z * std::exp(-sigma_tr_ * s) / (s * s * s * s) * (sigma_tr_ * sigma_tr_ * s + 3 * sigma_tr_ + 3 / s);
  };
  return -alpha_prime_ / (4 * kPi) * (slope(z_r_) + slope(z_v_)) * x;
}

double DipoleProfile::totalDiffuseReflectance() const {
  const double root = std::sqrt(3 * (1 - alpha_prime_));
  return alpha_prime_ / 2 * (1 + std::exp(-4.0 / 3.0 * A_ * root)) * std::exp(-root);
}

double DipoleProfile::splitDiskSlope(double R) const {
  const double R_r = std::sqrt(R * R + z_r_ * z_r_), R_v = std::sqrt(R * R + z_v_ * z_v_);
  const double bracket = std::exp(-sigma_tr_ * z_r_) - z_r_ / R_r * std::exp(-sigma_tr_ * R_r) +
                         std::exp(-sigma_tr_ * z_v_) - z_v_ / R_v * std::exp(-sigma_tr_ * R_v);
  return 2 * alpha_prime_ / (kPi * R) * bracket;
}

namespace {

DipoleProfile channelOf(const TranslucentMaterial& m, int c) {
  return DipoleProfile(m.sigmaS()[c], m.sigmaA()[c], m.g, m.eta);
}

}  // namespace

RgbDipole::RgbDipole(const TranslucentMaterial& material)
    : channel{channelOf(material, 0), channelOf(material, 1), channelOf(material, 2)} {}

double RgbDipole::shortestDiffusionLength() const {
  double longest_sigma_tr = 0, longest_z_r = 0;
  for (const DipoleProfile& p : channel) {
    longest_sigma_tr = std::max(longest_sigma_tr, p.sigmaTr());
    longest_z_r = std::max(longest_z_r, p.zr());
  }
  // A lossless interior (albedo 1) has sigma_tr = 0 in every channel: fall back on ten mean free paths.
  return longest_sigma_tr > 0 ? 1 / longest_sigma_tr : 10 * longest_z_r;
}

}  // namespace vdbappear
