#include "libvdbappear/subsurface/translucent_object.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/subsurface/fresnel.h"

namespace vdbappear {

TranslucentObject::TranslucentObject(const TranslucentMaterial& material, std::vector<IrradianceSample> samples,
                                     const SubsurfaceSettings& settings)
    : material_(material), dipole_(material), octree_(std::move(samples)),
      F_dt_outside_(diffuseFresnelTransmittance(1 / material.eta)) {
  hierarchy_.max_solid_angle = settings.max_solid_angle;
  hierarchy_.disk_radius = settings.disk_radius * dipole_.shortestDiffusionLength();
}

Rgb TranslucentObject::illuminance(const Vec3& p, const Vec3& n, double reach) const {
  if (!cache_) return estimate(p).S;
  if (const std::optional<SubsurfaceEstimate> cached = cache_->interpolate(p, n, reach)) return cached->S;
  uncached_lookups_.fetch_add(1, std::memory_order_relaxed);
  return estimate(p).S;
}

Rgb TranslucentObject::radiance(const Vec3& p, const Vec3& n, double cos_theta, double reach) const {
  return illuminance(p, n, reach) * (fresnelTransmittance(cos_theta, material_.eta) / (F_dt_outside_ * kPi));
}

double TranslucentObject::specularReflectance(double cos_theta) const {
  return material_.eta == 1 ? 0.0 : fresnelReflectance(cos_theta, material_.eta);
}

}  // namespace vdbappear
