#include "libvdbappear/surface/microfacet_brdf.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/frame.h"
#include "libvdbappear/math/sampling.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {

Rgb schlickFresnel(const Rgb& f0, double cos_theta) {
  const double c = 1 - std::clamp(cos_theta, 0.0, 1.0);
  return f0 + (1 - f0) * (c * c * c * c * c);
}

namespace {

bool isReflectance(const Rgb& c) { return c.allFinite() && (c >= 0).all() && (c <= 1).all(); }

}  // namespace

MicrofacetBrdf::MicrofacetBrdf(const MicrofacetDistribution& distribution, const Rgb& specular, const Rgb& diffuse)
    : distribution_(distribution), specular_(specular), diffuse_(diffuse) {
  if (!isReflectance(specular) || !isReflectance(diffuse))
    throw std::invalid_argument("BRDF reflectances must lie in [0, 1]");
}

double MicrofacetBrdf::specularProbability(double cos_theta_o) const {
  const double cos_o = std::clamp(cos_theta_o, 0.0, 1.0);
  const Vec3 wo(std::sqrt(1 - cos_o * cos_o), 0, cos_o);  // G1 is isotropic
  const double s = average(schlickFresnel(specular_, cos_o)) * distribution_.G1(wo), d = average(diffuse_);
  return s + d > 0 ? s / (s + d) : 1;
}

Rgb MicrofacetBrdf::eval(const Vec3& wo, const Vec3& wi) const {
  if (wo.z() <= 0 || wi.z() <= 0) return Rgb::Zero();
  Rgb f = diffuse_ / kPi;
  const Vec3 h = (wo + wi).normalized();
  const double g2 = distribution_.G2(wo, wi);
  if (g2 > 0) f += schlickFresnel(specular_, wo.dot(h)) * (distribution_.D(h) * g2 / (4 * wo.z() * wi.z()));
  return f;
}

double MicrofacetBrdf::pdf(const Vec3& wo, const Vec3& wi) const {
  if (wo.z() <= 0 || wi.z() <= 0) return 0;
  const Vec3 h = (wo + wi).normalized();
  // The reflection Jacobian |d wi / d h| = 4 <wo, h> (Walter et al. 2007, Eq. 14).
  const double specular = distribution_.normalPdf(wo, h) / (4 * wo.dot(h));
  const double p_specular = specularProbability(wo.z());
  return p_specular * specular + (1 - p_specular) * cosineHemispherePdf(wi.z());
}

Vec3 MicrofacetBrdf::sampleDirection(const Vec3& wo, double u_lobe, const Point2& u) const {
  return u_lobe < specularProbability(wo.z()) ? reflect(wo, distribution_.sampleNormal(wo, u)) : sampleCosineHemisphere(u);
}

BrdfSample MicrofacetBrdf::sample(const Vec3& wo, double u_lobe, const Point2& u) const {
  BrdfSample s;
  if (wo.z() <= 0) return s;
  s.wi = sampleDirection(wo, u_lobe, u);
  if (s.wi.z() <= 0) return s;
  s.pdf = pdf(wo, s.wi);
  if (s.pdf > 0) s.weight = eval(wo, s.wi) * (s.wi.z() / s.pdf);
  return s;
}

}  // namespace vdbappear
