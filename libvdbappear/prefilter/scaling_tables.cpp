#include "libvdbappear/prefilter/scaling_tables.h"

#include "libvdbappear/math/concentric_mapping.h"

#include <algorithm>
#include <cmath>

namespace vdbappear {
namespace {

// Linear interpolation between the centres of N bins over [0,1]: the two bins and the weight of the second.
struct AxisWeights {
  int i0, i1;
  double t;
};

AxisWeights axisWeights(double s, int N) {
  const double c = std::clamp(s * N - 0.5, 0.0, double(N - 1));
  const int i0 = std::min(int(c), std::max(0, N - 2));
  return {i0, std::min(i0 + 1, N - 1), c - i0};
}

// The same with nodes at the edges besides the N bin centres: node 0 at s = 0, node k at bin
// k - 1's centre (k - 0.5) / N, node N + 1 at s = 1.
AxisWeights edgeAxisWeights(double s, int N) {
  const double half = 0.5 / N;
  s = std::clamp(s, 0.0, 1.0);
  const double c = s < half ? s / half : s > 1 - half ? N + (s - (1 - half)) / half : s * N + 0.5;
  const int i0 = std::min(int(c), N);
  return {i0, i0 + 1, c - i0};
}

}  // namespace

Rgb SpatialScaling::operator()(const Point2& x) const {
  const AxisWeights a = axisWeights(x.x(), resolution), b = axisWeights(x.y(), resolution);
  const auto at = [&](int i, int j) { return values[std::size_t(i) + std::size_t(resolution) * j]; };
  return (1 - b.t) * ((1 - a.t) * at(a.i0, b.i0) + a.t * at(a.i1, b.i0)) +
         b.t * ((1 - a.t) * at(a.i0, b.i1) + a.t * at(a.i1, b.i1));
}

Point2 SpatialScaling::binCentre(int a, int b) const { return {(a + 0.5) / resolution, (b + 0.5) / resolution}; }

Rgb AngularScaling::read(const Vec3& wi, const Vec3& wo, Rgb* slope) const {
  const Point2 si = hemisphereToSquare(Vec3(wi.x(), wi.y(), std::max(0.0, wi.z())).normalized());
  const Point2 so = hemisphereToSquare(Vec3(wo.x(), wo.y(), std::max(0.0, wo.z())).normalized());
  const auto view_axis = [&](double s) {
    return view_horizon ? edgeAxisWeights(s, resolution) : axisWeights(s, resolution);
  };
  const AxisWeights axes[4] = {axisWeights(si.x(), resolution), axisWeights(si.y(), resolution), view_axis(so.x()),
                               view_axis(so.y())};
  Rgb sum = Rgb::Zero(), slope_sum = Rgb::Zero();
  for (int corner = 0; corner < 16; ++corner) {  // the 16 bin centres around (wi, wo)
    int i[4];
    double weight = 1;
    for (int k = 0; k < 4; ++k) {
      const bool upper = (corner >> k) & 1;
      i[k] = upper ? axes[k].i1 : axes[k].i0;
      weight *= upper ? axes[k].t : 1 - axes[k].t;
    }
    if (weight > 0) {
      const std::size_t k = index(i[0], i[1], i[2], i[3]);
      sum += weight * values[k];
      if (slope) slope_sum += weight * relief_slopes[k];
    }
  }
  if (slope) *slope = slope_sum;
  return sum;
}

Vec3 AngularScaling::binDirection(int a, int b) const {
  return squareToHemisphere({(a + 0.5) / resolution, (b + 0.5) / resolution});
}

Vec3 AngularScaling::viewNodeDirection(int oa, int ob) const {
  if (!view_horizon) return binDirection(oa, ob);
  const int N = resolution;
  const auto position = [N](int k) { return k == 0 ? 0.0 : k == N + 1 ? 1.0 : (k - 0.5) / N; };
  const Vec3 w = squareToHemisphere({position(oa), position(ob)});
  return onHorizon(oa, ob) ? Vec3(w.x(), w.y(), 0).normalized() : w;
}

}  // namespace vdbappear
