#pragma once
// The dipole diffusion profile of Jensen et al. 2001 as the translucent-caching seed writes it
// (shared/papers/004_9ab77ac845cb3af3.txt, §2.3 and §3.1-3.3), one colour channel at a time.
// Names follow the seed: reduced albedo alpha', effective transport coefficient sigma_tr, the real
// and virtual sources' depths z_r and z_v.

#include "libvdbappear/math/rgb.h"
#include "libvdbappear/math/vector.h"
#include "libvdbappear/subsurface/translucent_material.h"

#include <array>

namespace vdbappear {

class DipoleProfile {
 public:
  // sigma_s' = sigma_s (1 - g), sigma_t' = sigma_a + sigma_s', alpha' = sigma_s' / sigma_t',
  // sigma_tr = sqrt(3 sigma_a sigma_t'), z_r = 1 / sigma_t', z_v = z_r (1 + 4A/3),
  // A = (1 + F_dr) / (1 - F_dr) (§2.3).
  DipoleProfile(double sigma_s, double sigma_a, double g, double eta);

  // R_d(r), Eq. (3.2): radiant exitance at distance r from a unit incident flux.
  double Rd(double r) const;
  // R_s(x) = R_d(|x|), Eq. (3.3): the profile as a 3-D radial function of the offset x.
  double Rs(const Vec3& x) const { return Rd(x.norm()); }
  // grad R_s(x) = -x sum_{k in r,v} z_k e^{-sigma_tr s_k} (sigma_tr^2 s_k + 3 sigma_tr + 3 / s_k) / s_k^4
  // times alpha' / (4 pi), s_k = sqrt(|x|^2 + z_k^2). The seed's Eq. (3.8) prints it without the
  // minus sign; R_s falls with |x|, and the central-difference test settles it.
  Vec3 gradRs(const Vec3& x) const;
  // The closed form of the total diffuse reflectance, 2 pi int_0^inf R_d(r) r dr =
  // alpha'/2 (1 + e^{-4/3 A sqrt(3(1 - alpha'))}) e^{-sqrt(3(1 - alpha'))} (Jensen et al. 2001).
  double totalDiffuseReflectance() const;
  // The split-disk model's bound on |dS/du| per unit standard deviation V of the irradiance within
  // a disk of radius R (§3.3, the factor of Eq. 3.10):
  // 2 alpha' / (pi R) (e^{-sigma_tr z_r} - z_r/R_r e^{-sigma_tr R_r} + e^{-sigma_tr z_v} - z_v/R_v e^{-sigma_tr R_v}).
  double splitDiskSlope(double R) const;

  double alphaPrime() const { return alpha_prime_; }
  double sigmaTr() const { return sigma_tr_; }
  double zr() const { return z_r_; }
  double zv() const { return z_v_; }

 private:
  double alpha_prime_, sigma_tr_, z_r_, z_v_, A_;
};

// One profile per channel; colour stays per channel throughout (docs/subsurface.md §3).
struct RgbDipole {
  std::array<DipoleProfile, 3> channel;

  explicit RgbDipole(const TranslucentMaterial& material);
  Rgb Rd(double r) const { return {channel[0].Rd(r), channel[1].Rd(r), channel[2].Rd(r)}; }
  // 1 / sigma_tr of the channel that diffuses least far: the length unit of the sampling, the
  // hierarchy and the cache's radii (ten mean free paths for a lossless interior).
  double shortestDiffusionLength() const;
};

}  // namespace vdbappear
