#pragma once
// The multi-lobe BRDF of Eq. (4.5) in the displacement chapter (shared/papers/002_6a636dc24396287c.txt,
// after Han et al. 2007), the initial prefiltered SVBRDF f'_low of Eq. (4.11) for one patch:
//   rho(wi, wo; D, f) = 1 / cos theta_i int f(R_w(wi), R_w(wo)) <w, wi> D(w) dw,
// the base BRDF f seen through micro-normals distributed as D, with no shadowing, masking or
// interreflection (which the scaling function restores, Eq. 4.12-4.13).
//
// Evaluated in closed form, as Han et al. convolve lobes: each vMF lobe (alpha_k, kappa_k, mu_k) of
// D is the base BRDF in the frame of mu_k with its roughness widened by the lobe's spread,
//   rho ~ 1 / cos theta_i sum_k alpha_k <mu_k, wi> f_k(R_mu_k(wi), R_mu_k(wo)),
//   f_k = f with alpha_k' = sqrt(alpha^2 + 2 / kappa_k) (slope variances add: a vMF of bandwidth
//   kappa spreads normals by 1 / kappa per axis, a Beckmann or GGX lobe by alpha^2 / 2),
// six microfacet evaluations per call, so that a renderer can afford it at every vertex. Exact for
// narrow lobes; the scaling function is computed against this same f'_low, so what it leaves out
// for wide lobes is part of what R corrects (docs/displacement.md §4).

#include "libvdbappear/math/frame.h"
#include "libvdbappear/surface/microfacet_brdf.h"
#include "libvdbappear/surface/tile_stretch.h"
#include "libvdbappear/surface/vmf_ndf.h"

#include <vector>

namespace vdbappear {

class MultiLobeBrdf {
 public:
  MultiLobeBrdf(const VmfMixture& ndf, const MicrofacetBrdf& base);

  // Eq. (4.5), wi (toward the light) and wo (toward the viewer) in the macro-surface's frame
  // (n = +z); zero below its horizon. 1 / cos theta_i is limited to 10 (beyond 84 degrees).
  Rgb eval(const Vec3& wi, const Vec3& wo) const;
  // wi drawn for a given wo: a lobe k with probability proportional to alpha_k among those facing
  // wo, then f_k's own sampling in mu_k's frame. weight = eval cos theta_i / pdf; zero (pdf 0) when wi falls below
  // the macro-surface or no lobe faces wo.
  BrdfSample sample(const Vec3& wo, double u_lobe, const Point2& u) const;
  double pdf(const Vec3& wo, const Vec3& wi) const;  // solid-angle density of sample()

  // The same pieces with no macro-surface horizon, for a base that curves below it
  // (prefilter/prefiltered_brdf.h): Eq. (4.5)'s integrand summed over the lobes,
  //   rho cos theta_i = sum_k alpha_k <mu_k, wi>+ f_k(R_mu_k(wi), R_mu_k(wo)),
  // the lobe choice and f_k's own sampling (wi anywhere f_k reaches), and that sampling's density.
  Rgb projected(const Vec3& wi, const Vec3& wo) const;
  // The same over a tile that the surface stretches (surface/tile_stretch.h), wi and wo the
  // surface's: each lobe's facets at <mu_k, vi> (vi = stretch.toMap(wi)) weighed by 1 / |A^-T mu_k|,
  // and f_k about the stretched axis A^-T mu_k at wi and wo. Equal to projected(wi, wo) when the
  // stretch is the identity.
  Rgb projected(const Vec3& wi, const Vec3& wo, const TileStretch& stretch) const;
  // Eq. (4.5) over a stretched tile as a prefiltered model shades it on a coarse facet of normal
  // `coarse_normal` (surface/tile_stretch.h; either side): the lobes' facets each weighed, the
  // coarse facet's weight |A^T n_c| divided out, and 1 / cos theta(vi) = |A^-1 wi| / cos theta_i,
  // limited where the surface's own wi grazes:
  //   projected(wi, wo, stretch) |A^-1 wi| / (limitedCosine(cos theta_i) |A^T n_c|).
  // No horizon cut (the caller's); eval() on the square tile, up to its cut.
  Rgb onStretchedTile(const Vec3& wi, const Vec3& wo, const TileStretch& stretch, const Vec3& coarse_normal) const;
  // The lobes as a viewer sees them: each lobe's term of projected(wi, wo, stretch) in proportion
  // to the area its facets show toward wo, alpha_k' <a_k, wo>+ (a_k its axis on the surface,
  // alpha_k' = alpha_k / |A^-T mu_k| its area there; mu_k and alpha_k on the square tile):
  //   V(wi, wo) = sum_k alpha_k' <a_k, wo>+ rho_k / sum_k alpha_k' <a_k, wo>+,
  //   rho_k = <mu_k, vi>+ f_k(wi, wo), lobe k's own reflectance,
  // microfacet theory's mean over the facets in view, masking aside; zero when no lobe faces wo.
  // Eq. (4.5) weighs the lobes by alpha_k alone; above the horizon S, measured against it, makes
  // up the difference, and below a curved base's horizon prefilter/prefiltered_brdf.h uses both.
  Rgb visibleMean(const Vec3& wi, const Vec3& wo, const TileStretch& stretch = {}) const;
  BrdfSample sampleLobes(const Vec3& wo, double u_lobe, const Point2& u) const;  // weight not filled
  double lobePdf(const Vec3& wo, const Vec3& wi) const;

  // cos theta_i as Eq. (4.5)'s division by it is limited in eval() (to 0.1, 84 degrees).
  static double limitedCosine(double cos_theta_i);
  // alpha' of a lobe of bandwidth kappa over a base roughness alpha (capped at 1).
  static double widenedRoughness(double alpha, double kappa);

 private:
  struct Lobe {
    Frame frame;  // about mu_k
    double amplitude;
    MicrofacetBrdf brdf;
  };
  // Lobe l on the surface that `stretch` lays the tile out as: its frame about a_k, |A^-T mu_k|
  // (alpha_k' = alpha_k / length; 1 on the square tile) and <mu_k, vi> (vi = stretch.toMap(wi)).
  struct OnSurface {
    Frame frame;
    double length;
    double cos_i;
  };
  static OnSurface onSurface(const Lobe& l, const Vec3& vi, const TileStretch& stretch);
  // The lobes' selection probabilities for wo; false when none faces it.
  bool lobeProbabilities(const Vec3& wo, double* probability) const;

  std::vector<Lobe> lobes_;
};

}  // namespace vdbappear
