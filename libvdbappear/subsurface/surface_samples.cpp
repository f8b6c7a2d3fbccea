#include "libvdbappear/subsurface/surface_samples.h"

#include <Eigen/Geometry>

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace vdbappear {

namespace {

constexpr std::size_t kMostPoints = 20'000'000;

void split(const Triangle& t, double max_edge2, std::vector<SurfacePoint>* out) {
  int longest = 0;
  double longest2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double e2 = (t[(k + 1) % 3] - t[k]).squaredNorm();
    if (e2 > longest2) {
      longest2 = e2;
      longest = k;
    }
  }
  if (longest2 <= max_edge2) {
    const Vec3 cross = (t[1] - t[0]).cross(t[2] - t[0]);
    const double norm = cross.norm();
    if (norm > 0) out->push_back({(t[0] + t[1] + t[2]) / 3, cross / norm, 0.5 * norm, t});
    if (out->size() > kMostPoints)
      throw std::invalid_argument("more than 20 M irradiance samples: the sample spacing is too small for this mesh");
    return;
  }
  const Vec3& a = t[longest];
  const Vec3& b = t[(longest + 1) % 3];
  const Vec3& c = t[(longest + 2) % 3];
  const Vec3 m = 0.5 * (a + b);
  split({a, m, c}, max_edge2, out);
  split({m, b, c}, max_edge2, out);
}

}  // namespace

std::vector<SurfacePoint> surfacePoints(const std::vector<Triangle>& triangles, double max_edge) {
  if (!(max_edge > 0)) throw std::invalid_argument("surfacePoints: the longest edge must be > 0");
  double expected = 0;  // halving to max_edge makes about 2 (longest / max_edge)^2 pieces of a face
  for (const Triangle& t : triangles) {
    const double longest2 = std::max({(t[1] - t[0]).squaredNorm(), (t[2] - t[1]).squaredNorm(), (t[0] - t[2]).squaredNorm()});
    expected += std::max(1.0, 2 * longest2 / (max_edge * max_edge));
  }
  if (expected > double(kMostPoints))
    throw std::invalid_argument(fmt::format("about {:.3g} irradiance samples, more than 20 M: the sample spacing is too "
                                            "small for this mesh", expected));
  std::vector<SurfacePoint> points;
  points.reserve(triangles.size());
  for (const Triangle& t : triangles) split(t, max_edge * max_edge, &points);
  return points;
}

}  // namespace vdbappear
