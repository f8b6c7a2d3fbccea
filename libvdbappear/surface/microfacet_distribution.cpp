#include "libvdbappear/surface/microfacet_distribution.h"

#include "libvdbappear/math/constants.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {

MicrofacetKind parseMicrofacetKind(const std::string& name) {
  if (name == "beckmann") return MicrofacetKind::Beckmann;
  if (name == "ggx") return MicrofacetKind::GGX;
  throw std::invalid_argument("unknown microfacet distribution '" + name + "' (beckmann or ggx)");
}

const char* microfacetKindName(MicrofacetKind kind) { return kind == MicrofacetKind::GGX ? "ggx" : "beckmann"; }

MicrofacetDistribution::MicrofacetDistribution(MicrofacetKind kind, double alpha) : kind_(kind), alpha_(alpha) {
  if (!(alpha > 0) || !std::isfinite(alpha))
    throw std::invalid_argument("microfacet roughness must be positive and finite, got " + std::to_string(alpha));
}

double MicrofacetDistribution::D(const Vec3& m) const {
  const double cos2 = m.z() * m.z();
  if (m.z() <= 0) return 0;
  const double a2 = alpha_ * alpha_;
  if (kind_ == MicrofacetKind::GGX) {
    const double denom = 1 + cos2 * (a2 - 1);
    return a2 / (kPi * denom * denom);
  }
  const double tan2 = std::max(0.0, 1 - cos2) / cos2;
  return std::exp(-tan2 / a2) / (kPi * a2 * cos2 * cos2);
}

double MicrofacetDistribution::Lambda(const Vec3& w) const {
  const double cos2 = w.z() * w.z();
  const double sin2 = std::max(0.0, 1 - cos2);
  if (sin2 == 0) return 0;
  if (kind_ == MicrofacetKind::GGX) return (-1 + std::sqrt(1 + alpha_ * alpha_ * sin2 / cos2)) / 2;
  const double a = std::abs(w.z()) / (alpha_ * std::sqrt(sin2));
  return (std::erf(a) - 1) / 2 + std::exp(-a * a) / (2 * a * std::sqrt(kPi));
}

double MicrofacetDistribution::G1(const Vec3& w) const { return w.z() > 0 ? 1 / (1 + Lambda(w)) : 0; }

double MicrofacetDistribution::G2(const Vec3& wo, const Vec3& wi) const {
  if (wo.z() <= 0 || wi.z() <= 0) return 0;
  return 1 / (1 + Lambda(wo) + Lambda(wi));
}

namespace {

// Heitz 2018, Listing 1: the visible normals of GGX as a hemisphere's projection, stretched.
Vec3 sampleGgxVisibleNormal(const Vec3& wo, double alpha, const Point2& u) {
  const Vec3 vh = Vec3(alpha * wo.x(), alpha * wo.y(), wo.z()).normalized();
  const double lensq = vh.x() * vh.x() + vh.y() * vh.y();
  const Vec3 t1 = lensq > 0 ? Vec3(-vh.y(), vh.x(), 0) / std::sqrt(lensq) : Vec3(1, 0, 0);
  const Vec3 t2 = vh.cross(t1);
  const double r = std::sqrt(u.x()), phi = 2 * kPi * u.y();
  const double p1 = r * std::cos(phi);
  const double s = 0.5 * (1 + vh.z());
  const double p2 = (1 - s) * std::sqrt(std::max(0.0, 1 - p1 * p1)) + s * r * std::sin(phi);
  const Vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1 - p1 * p1 - p2 * p2)) * vh;
  return Vec3(alpha * nh.x(), alpha * nh.y(), std::max(1e-12, nh.z())).normalized();
}

// Beckmann's D(m) cos theta_m by inversion: tan^2 theta_m = -alpha^2 log(1 - u1), phi = 2 pi u2.
Vec3 sampleBeckmannNormal(double alpha, const Point2& u) {
  const double tan2 = -alpha * alpha * std::log1p(-u.x());
  const double cos_theta = 1 / std::sqrt(1 + tan2);
  const double sin_theta = std::sqrt(std::max(0.0, 1 - cos_theta * cos_theta));
  const double phi = 2 * kPi * u.y();
  return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

}  // namespace

Vec3 MicrofacetDistribution::sampleNormal(const Vec3& wo, const Point2& u) const {
  return kind_ == MicrofacetKind::GGX ? sampleGgxVisibleNormal(wo, alpha_, u) : sampleBeckmannNormal(alpha_, u);
}

double MicrofacetDistribution::normalPdf(const Vec3& wo, const Vec3& m) const {
  if (kind_ == MicrofacetKind::Beckmann) return D(m) * std::max(0.0, m.z());
  if (wo.z() <= 0) return 0;
  return G1(wo) * std::max(0.0, wo.dot(m)) * D(m) / wo.z();
}

}  // namespace vdbappear
