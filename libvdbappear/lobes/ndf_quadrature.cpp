#include "libvdbappear/lobes/ndf_quadrature.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/sggx.h"

#include <algorithm>
#include <cmath>

namespace vdbappear {

const std::vector<Vec3>& ndfQuadraturePoints() {
  static const std::vector<Vec3> points = [] {
    std::vector<Vec3> p(kNdfQuadraturePoints);
    const double golden_angle = kPi * (3 - std::sqrt(5.0));
    for (int k = 0; k < kNdfQuadraturePoints; ++k) {
      const double z = (k + 0.5) / kNdfQuadraturePoints, r = std::sqrt(std::max(0.0, 1 - z * z));
      p[k] = Vec3(r * std::cos(golden_angle * k), r * std::sin(golden_angle * k), z);
    }
    return p;
  }();
  return points;
}

NdfSamples sampleNdf(const Mat3& S) {
  const Sggx sggx(S);
  const std::vector<Vec3>& points = ndfQuadraturePoints();
  NdfSamples D(points.size());
  for (std::size_t q = 0; q < points.size(); ++q) D[q] = sggx.D(points[q]);
  return D;
}

double sphereL2DistanceSquared(const NdfSamples& a, const NdfSamples& b) {
  double sum = 0;
  for (std::size_t q = 0; q < a.size(); ++q) sum += (a[q] - b[q]) * (a[q] - b[q]);
  return 2 * (2 * kPi / double(a.size())) * sum;  // both hemispheres
}

}  // namespace vdbappear
