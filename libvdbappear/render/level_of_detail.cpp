#include "libvdbappear/render/level_of_detail.h"

#include "libvdbappear/math/random_stream.h"

#include <algorithm>
#include <cmath>

namespace vdbappear {

LevelBlend blendForFootprint(const std::vector<double>& factors, double footprint_cells) {
  const int last = int(factors.size()) - 1;
  if (last <= 0 || !(footprint_cells > factors.front())) return {0, 0, 0};
  if (footprint_cells >= factors.back()) return {last, last, 0};
  int k = 0;
  while (footprint_cells >= factors[std::size_t(k) + 1]) ++k;
  const double w = std::log(footprint_cells / factors[std::size_t(k)]) /
                   std::log(factors[std::size_t(k) + 1] / factors[std::size_t(k)]);
  return {k, k + 1, w};
}

std::optional<Footprint> footprintOn(const MipmapFootprint& mipmap, const Ray& ray) {
  const double cos_theta = std::abs(ray.d.z());
  if (!(cos_theta > 1e-12)) return std::nullopt;
  const double t = (mipmap.origin.z() - ray.o.z()) / ray.d.z();
  if (!(t > 0)) return std::nullopt;
  const Vec3 p = ray(t);
  const double x = p.x() - mipmap.origin.x(), y = p.y() - mipmap.origin.y();
  if (x < 0 || y < 0 || x > mipmap.width_x || y > mipmap.width_y) return std::nullopt;
  // The pixel's solid angle spread^2 covers t^2 spread^2 / cos(theta) of the plane.
  const double width = t * ray.spread / std::sqrt(cos_theta);
  return Footprint{t, width / mipmap.cell};
}

int pathLevel(const std::vector<MipmapFootprint>& mipmaps, const Ray& ray, RandomStream& rng) {
  if (mipmaps.empty() || !(ray.spread > 0)) return 0;
  const MipmapFootprint* nearest = nullptr;
  Footprint at;
  for (const MipmapFootprint& mipmap : mipmaps) {
    const std::optional<Footprint> f = footprintOn(mipmap, ray);
    if (f && (!nearest || f->t < at.t)) nearest = &mipmap, at = *f;
  }
  if (!nearest) {
    std::size_t coarsest = 0;
    for (const MipmapFootprint& mipmap : mipmaps) coarsest = std::max(coarsest, mipmap.factors.size());
    return int(coarsest) - 1;
  }
  const LevelBlend blend = blendForFootprint(nearest->factors, at.cells);
  if (blend.lower == blend.upper || !(blend.weight > 0)) return blend.lower;
  return rng.uniform() < blend.weight ? blend.upper : blend.lower;
}

}  // namespace vdbappear
