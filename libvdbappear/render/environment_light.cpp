#include "libvdbappear/render/environment_light.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/sampling.h"
#include "libvdbappear/math/spherical_harmonics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {

Vec3 EnvironmentLight::directionOf(const Point2& uv) {
  const double phi = kPi * (1 - 2 * uv.x());
  const double elevation = kPi * (0.5 - uv.y());
  return {std::cos(elevation) * std::cos(phi), std::cos(elevation) * std::sin(phi), std::sin(elevation)};
}

Point2 EnvironmentLight::latLongOf(const Vec3& w) {
  const double phi = std::atan2(w.y(), w.x());
  const double elevation = std::atan2(w.z(), std::hypot(w.x(), w.y()));
  double u = (kPi - phi) / (2 * kPi);
  if (u >= 1) u -= 1;
  return {std::clamp(u, 0.0, 1.0 - 1e-16), std::clamp(0.5 - elevation / kPi, 0.0, 1.0 - 1e-16)};
}

std::unique_ptr<EnvironmentLight> EnvironmentLight::constant(const Rgb& radiance) {
  std::unique_ptr<EnvironmentLight> light(new EnvironmentLight());
  light->constant_ = radiance;
  return light;
}

void EnvironmentLight::buildDistribution(const std::vector<double>& weights, int width, int height) {
  std::vector<double> f(weights.size());
  for (int v = 0; v < height; ++v) {
    const double cos_elevation = std::cos(kPi * (0.5 - (v + 0.5) / height));
    for (int u = 0; u < width; ++u) f[std::size_t(v) * width + u] = weights[std::size_t(v) * width + u] * cos_elevation;
  }
  distribution_ = PiecewiseConstant2D(f, width, height);
}

void EnvironmentLight::measurePeakToMean(const std::vector<double>& weights, int width, int height) {
  double sum = 0, solid_angle = 0, peak = 0;
  for (int v = 0; v < height; ++v) {
    const double cos_elevation = std::cos(kPi * (0.5 - (v + 0.5) / height));
    for (int u = 0; u < width; ++u) {
      const double w = weights[std::size_t(v) * width + u];
      sum += w * cos_elevation;
      solid_angle += cos_elevation;
      peak = std::max(peak, w);
    }
  }
  peak_to_mean_ = sum > 0 ? peak / (sum / solid_angle) : 1.0;
}

std::unique_ptr<EnvironmentLight> EnvironmentLight::fromImage(int width, int height, std::vector<float> rgb,
                                                              double scale) {
  if (width < 1 || height < 1 || rgb.size() != std::size_t(width) * height * 3)
    throw std::invalid_argument("environment map: size mismatch");
  std::unique_ptr<EnvironmentLight> light(new EnvironmentLight());
  light->kind_ = Kind::kImage;
  light->width_ = width;
  light->height_ = height;
  light->scale_ = scale;
  std::vector<double> weights(std::size_t(width) * height);
  for (std::size_t i = 0; i < weights.size(); ++i) {
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(rgb[3 * i + c])) throw std::invalid_argument("environment map: NaN or infinite pixel");
    weights[i] = (std::abs(rgb[3 * i]) + std::abs(rgb[3 * i + 1]) + std::abs(rgb[3 * i + 2])) / 3;
  }
  light->rgb_ = std::move(rgb);
  light->measurePeakToMean(weights, width, height);
  light->buildDistribution(weights, width, height);
  return light;
}

std::unique_ptr<EnvironmentLight> EnvironmentLight::sphericalHarmonic(int l, int m, double scale) {
  if (l < 0 || std::abs(m) > l) throw std::invalid_argument("SH light: need l >= 0 and -l <= m <= l");
  std::unique_ptr<EnvironmentLight> light(new EnvironmentLight());
  light->kind_ = Kind::kSphericalHarmonic;
  light->l_ = l;
  light->m_ = m;
  light->scale_ = scale;
  const int width = 128, height = 64;
  std::vector<double> weights(std::size_t(width) * height);
  double max_weight = 0;
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const Vec3 w = directionOf(Point2((u + 0.5) / width, (v + 0.5) / height));
      weights[std::size_t(v) * width + u] = std::abs(vdbappear::sphericalHarmonic(l, m, w));
      max_weight = std::max(max_weight, weights[std::size_t(v) * width + u]);
    }
  light->measurePeakToMean(weights, width, height);
  for (double& weight : weights) weight += 0.05 * max_weight;
  light->buildDistribution(weights, width, height);
  return light;
}

Rgb EnvironmentLight::radiance(const Vec3& w) const {
  switch (kind_) {
    case Kind::kConstant: return constant_;
    case Kind::kSphericalHarmonic: return Rgb::Constant(scale_ * vdbappear::sphericalHarmonic(l_, m_, w));
    case Kind::kImage: {
      const Point2 uv = latLongOf(w);
      const int x = std::min(int(uv.x() * width_), width_ - 1), y = std::min(int(uv.y() * height_), height_ - 1);
      const float* px = &rgb_[(std::size_t(y) * width_ + x) * 3];
      return scale_ * Rgb(px[0], px[1], px[2]);
    }
  }
  return Rgb::Zero();
}

LightSample EnvironmentLight::sample(const Vec3& p, const Point2& u) const {
  if (kind_ == Kind::kConstant) {
    const Vec3 wi = sampleUniformSphere(u);
    return {wi, kInfinity, constant_, uniformSpherePdf(), false};
  }
  double pdf_uv = 0;
  const Point2 uv = distribution_.sample(u, &pdf_uv);
  const Vec3 wi = directionOf(uv);
  const double pdf_w = pdf(p, wi);
  if (!(pdf_w > 0)) return {};
  return {wi, kInfinity, radiance(wi), pdf_w, false};
}

double EnvironmentLight::pdf(const Vec3&, const Vec3& wi) const {
  if (kind_ == Kind::kConstant) return uniformSpherePdf();
  const double cos_elevation = std::hypot(wi.x(), wi.y());
  if (!(cos_elevation > 0)) return 0;
  return distribution_.pdf(latLongOf(wi)) / (2 * kPi * kPi * cos_elevation);
}

}  // namespace vdbappear
