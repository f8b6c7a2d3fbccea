#pragma once
// Isotropic microfacet normal distributions with Smith's shadowing-masking, in the local frame of
// the macro-surface (n = +z): the base micro-BRDFs f_orig of the displacement chapter
// (shared/papers/002_6a636dc24396287c.txt, §4.3-4.4). Walter et al. 2007 for D and Smith's Lambda,
// Heitz 2014 ("Understanding the Masking-Shadowing Function") for G1 and the height-correlated G2,
// Heitz 2018 ("Sampling the GGX Distribution of Visible Normals") for GGX's sampling.
// Evaluation and sampling sit side by side; each sampler returns its own pdf.

#include "libvdbappear/math/vector.h"

#include <string>

namespace vdbappear {

enum class MicrofacetKind { Beckmann, GGX };

MicrofacetKind parseMicrofacetKind(const std::string& name);  // "beckmann" or "ggx"; throws otherwise
const char* microfacetKindName(MicrofacetKind kind);

class MicrofacetDistribution {
 public:
  // alpha: the roughness (the RMS slope for Beckmann); alpha > 0 and finite, else std::invalid_argument.
  MicrofacetDistribution(MicrofacetKind kind, double alpha);

  MicrofacetKind kind() const { return kind_; }
  double alpha() const { return alpha_; }

  // D(m), normalised as int D(m) cos theta_m dm = 1 (the projected-area condition, Eq. 4.3).
  // GGX: alpha^2 / (pi (1 + cos^2 theta_m (alpha^2 - 1))^2);
  // Beckmann: exp(-tan^2 theta_m / alpha^2) / (pi alpha^2 cos^4 theta_m). Zero below the horizon.
  double D(const Vec3& m) const;

  // Smith's Lambda(w): GGX (-1 + sqrt(1 + alpha^2 tan^2 theta)) / 2; Beckmann, with
  // a = 1 / (alpha tan theta), (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi)).
  double Lambda(const Vec3& w) const;
  // Masking of one direction, G1(w) = 1 / (1 + Lambda(w)) for w above the horizon, else 0.
  double G1(const Vec3& w) const;
  // Height-correlated shadowing-masking, G2(wo, wi) = 1 / (1 + Lambda(wo) + Lambda(wi)).
  double G2(const Vec3& wo, const Vec3& wi) const;

  // A micro-normal m for the view direction wo (wo.z > 0). GGX draws the visible normals,
  // pdf D_wo(m) = G1(wo) <wo, m> D(m) / cos theta_o; Beckmann draws D(m) cos theta_m.
  Vec3 sampleNormal(const Vec3& wo, const Point2& u) const;
  double normalPdf(const Vec3& wo, const Vec3& m) const;

 private:
  MicrofacetKind kind_;
  double alpha_;
};

}  // namespace vdbappear
