#pragma once
// The isotropic base micro-BRDF f of the displacement chapter (shared/papers/002_6a636dc24396287c.txt,
// §4.3): a Lambertian term plus a microfacet specular term with Schlick's Fresnel,
//   f(wo, wi) = diffuse / pi + F(<wo, h>) D(h) G2(wo, wi) / (4 cos theta_o cos theta_i),
// h = (wo + wi) / |wo + wi|, in the local frame of the surface (n = +z), both directions pointing away.

#include "libvdbappear/math/rgb.h"
#include "libvdbappear/surface/microfacet_distribution.h"

namespace vdbappear {

struct BrdfSample {
  Vec3 wi = Vec3::Zero();
  Rgb weight = Rgb::Zero();  // f(wo, wi) cos theta_i / pdf; zero when the sample left the hemisphere
  double pdf = 0;
};

class MicrofacetBrdf {
 public:
  // specular: F0, the reflectance at normal incidence; diffuse: the Lambertian albedo. Both in [0, 1].
  MicrofacetBrdf(const MicrofacetDistribution& distribution, const Rgb& specular, const Rgb& diffuse);

  const MicrofacetDistribution& distribution() const { return distribution_; }
  const Rgb& specular() const { return specular_; }
  const Rgb& diffuse() const { return diffuse_; }

  Rgb eval(const Vec3& wo, const Vec3& wi) const;
  // One lobe is chosen with the probability specularProbability(wo.z), then wi from it: the specular
  // lobe reflects wo about distribution().sampleNormal(wo), the diffuse lobe is cosine-weighted.
  BrdfSample sample(const Vec3& wo, double u_lobe, const Point2& u) const;
  // sample()'s direction alone (wo.z > 0), without its pdf and weight: for a mixture of lobes
  // (surface/multi_lobe_brdf.h), whose pdf and weight are the mixture's.
  Vec3 sampleDirection(const Vec3& wo, double u_lobe, const Point2& u) const;
  double pdf(const Vec3& wo, const Vec3& wi) const;  // the mixture's solid-angle density of wi
  // The specular lobe's share of the draws for a view cos theta_o from the normal: about its albedo
  // there, Schlick's Fresnel (the mean over the channels) times G1 (its draws reflect wo near the
  // mirror direction), against the diffuse albedo,
  //   s / (s + diffuse),  s = F(cos theta_o) G1(wo),
  // so that a grazing view, which Fresnel makes mostly specular, draws the specular lobe more
  // (F0 / (F0 + diffuse) at normal incidence; docs/displacement.md §3).
  double specularProbability(double cos_theta_o) const;

 private:
  MicrofacetDistribution distribution_;
  Rgb specular_, diffuse_;
};

// Schlick's approximation, F0 + (1 - F0)(1 - cos)^5.
Rgb schlickFresnel(const Rgb& f0, double cos_theta);

}  // namespace vdbappear
