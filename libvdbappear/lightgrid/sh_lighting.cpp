#include "libvdbappear/lightgrid/sh_lighting.h"

#include "libvdbappear/lightgrid/polygon_sh.h"
#include "libvdbappear/lightgrid/zonal_factorisation.h"
#include "libvdbappear/math/spherical_harmonics.h"

#include <cmath>

namespace vdbappear {

ShLighting shLighting(const std::vector<PolygonLight>& lights, const Vec3& x, const ZonalFactorisation& zh) {
  const int count = shCount(zh.lmax());
  ShLighting sum(count);
  for (const PolygonLight& light : lights) {
    const std::vector<Vec3> facing = verticesFacing(light, x);
    if (facing.empty()) continue;
    const PolygonSh sh = polygonSh(facing, x, zh);
    for (int i = 0; i < count; ++i) {
      sum.coeffs[i] += sh.coeffs[i] * light.radiance;
      sum.gradients[i] += light.radiance * sh.gradients[i].transpose();
    }
  }
  return sum;
}

Vec3 dominantDirection(const std::vector<Vec3>& coeffs) {
  if (coeffs.size() < 4) return Vec3::Zero();
  const Vec3 d(-coeffs[shIndex(1, 1)].mean(), -coeffs[shIndex(1, -1)].mean(), coeffs[shIndex(1, 0)].mean());
  const double norm = d.norm();
  return norm > 1e-9 * std::abs(coeffs[0].mean()) && norm > 0 ? Vec3(d / norm) : Vec3(Vec3::Zero());
}

Vec3 incidentRadiance(const std::vector<Vec3>& coeffs, int lmax, const Vec3& towards_light) {
  const std::vector<double> Y = evalSphericalHarmonics(lmax, towards_light);
  Vec3 L = Vec3::Zero();
  for (int i = 0; i < shCount(lmax); ++i) L += Y[i] * coeffs[i];
  return L;
}

}  // namespace vdbappear
