#include "libvdbappear/subsurface/cache_generation.h"

#include "libvdbappear/subsurface/translucent_object.h"

#include <algorithm>
#include <limits>

namespace vdbappear {

double cacheRadius(const SubsurfaceEstimate& e, const RgbDipole& dipole, const SubsurfaceSettings& settings) {
  const double length = dipole.shortestDiffusionLength();
  const double R = settings.disk_radius * length;
  double radius = std::numeric_limits<double>::infinity();
  for (int c = 0; c < 3; ++c) {
    const double slope = e.V[c] * dipole.channel[c].splitDiskSlope(R);  // |dS/du| of the split disk
    if (slope > 0) radius = std::min(radius, settings.cache_error * e.S[c] / slope);
  }
  return std::clamp(radius, settings.min_cache_radius * length, settings.max_cache_radius * length);
}

CachePass generateCaches(const TranslucentObject& object, const std::vector<VisiblePoint>& points,
                         const SubsurfaceSettings& settings, bool one_pass) {
  // Caches are made at visible points only: their box is the octree's root.
  Vec3 lo = points.empty() ? Vec3::Zero() : points[0].p, hi = lo;
  for (const VisiblePoint& v : points) {
    lo = lo.cwiseMin(v.p);
    hi = hi.cwiseMax(v.p);
  }
  CachePass pass;
  pass.cache = std::make_shared<IlluminanceCache>(lo, hi, settings.min_normal_cos);
  for (const VisiblePoint& v : points) {
    if (pass.cache->anyValid(v.p, v.normal, v.reach)) {
      if (one_pass) pass.one_pass.push_back(pass.cache->interpolate(v.p, v.normal, v.reach)->S);
      continue;
    }
    const SubsurfaceEstimate e = object.estimate(v.p);
    pass.cache->insert({v.p, v.normal, e.S, e.gradS, e.V, cacheRadius(e, object.dipole(), settings)});
    if (v.direct) pass.generated_pixels.push_back(v.pixel);
    if (one_pass) pass.one_pass.push_back(e.S);
  }
  return pass;
}

}  // namespace vdbappear
