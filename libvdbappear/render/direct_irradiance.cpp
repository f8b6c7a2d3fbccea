#include "libvdbappear/render/direct_irradiance.h"

#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/render/render_scene.h"
#include "libvdbappear/subsurface/fresnel.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

namespace vdbappear {

namespace {

constexpr std::int64_t kPassOneStream = 0x5055;  // keys pass 1's random streams apart from the paths'

Rgb irradianceAt(const SurfacePoint& point, double eta, const RenderScene& scene, int light_samples, RandomStream& rng,
                 MediumLookup* lookup) {
  const double eps = scene.ray_epsilon;
  const Vec3 origin = point.p + eps * point.normal;
  Rgb E = Rgb::Zero();
  for (const auto& light : scene.lights) {
    const int n = light->isDelta() ? 1 : light_samples;
    for (int k = 0; k < n; ++k) {
      const LightSample ls = light->sample(origin, rng.uniform2());
      const double cos_theta = point.normal.dot(ls.wi);
      if (!(ls.pdf > 0) || cos_theta <= 0 || (ls.Li == 0).all()) continue;
      if (scene.surfaces && scene.surfaces->occluded(origin, ls.wi, eps, ls.distance * (1 - 1e-6) - eps)) continue;
      const double T = lookup ? lookup->transmittance(origin, ls.wi, ls.distance, rng) : 1.0;
      E += ls.Li * (T * cos_theta * fresnelTransmittance(cos_theta, eta) / (ls.pdf * n));
    }
  }
  return E;
}

}  // namespace

std::vector<IrradianceSample> directIrradiance(const std::vector<SurfacePoint>& points, double eta,
                                               const RenderScene& scene, int light_samples, std::uint64_t seed) {
  std::vector<IrradianceSample> samples(points.size());
  tbb::enumerable_thread_specific<std::unique_ptr<MediumLookup>> lookups;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 256), [&](const auto& range) {
    std::unique_ptr<MediumLookup>& lookup = lookups.local();
    if (scene.medium && !lookup) lookup = scene.medium->lookup();
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      RandomStream rng(seed, {kPassOneStream, std::int64_t(i)});
      samples[i] = {points[i].p, points[i].area, irradianceAt(points[i], eta, scene, light_samples, rng, lookup.get()),
                    points[i].face};
    }
  });
  return samples;
}

}  // namespace vdbappear
