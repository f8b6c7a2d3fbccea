#include "libvdbappear/lightgrid/polygon_light.h"

#include <fmt/format.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vdbappear {

namespace {

Vec3 newellVector(const std::vector<Vec3>& p) {  // twice the vector area
  Vec3 n = Vec3::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) n += p[i].cross(p[(i + 1) % p.size()]);
  return n;
}

}  // namespace

Vec3 PolygonLight::normal() const { return newellVector(vertices).normalized(); }

double PolygonLight::area() const { return 0.5 * newellVector(vertices).norm(); }

void validatePolygonLight(const PolygonLight& light, const std::string& what) {
  const auto fail = [&](const std::string& why) { throw std::invalid_argument(fmt::format("{}: {}", what, why)); };
  const std::vector<Vec3>& p = light.vertices;
  if (p.size() < 3) fail(fmt::format("a polygon needs at least 3 vertices, got {}", p.size()));
  double extent = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p[i].allFinite()) fail(fmt::format("vertex {} is not finite", i));
    extent = std::max(extent, (p[i] - p[0]).norm());
  }
  for (std::size_t i = 0; i < p.size(); ++i)
    if ((p[i] - p[(i + 1) % p.size()]).norm() <= 1e-9 * extent) fail(fmt::format("vertices {} and {} coincide", i, (i + 1) % p.size()));
  if (light.area() <= 1e-12 * extent * extent) fail("the polygon has zero area");
  const Vec3 n = light.normal();
  for (std::size_t i = 0; i < p.size(); ++i)
    if (std::abs(n.dot(p[i] - p[0])) > 1e-6 * extent) fail(fmt::format("vertex {} is off the polygon's plane", i));
  if (!light.radiance.allFinite() || (light.radiance.array() < 0).any()) fail("radiance must be finite and >= 0");
}

std::vector<Vec3> verticesFacing(const PolygonLight& light, const Vec3& x) {
  const double side = light.normal().dot(x - light.vertices[0]);  // > 0: x is on the emitting side
  // In the light's plane (to rounding: a grid node placed on a light would get gradients of 1e16),
  // x sees the polygon edge-on: no light.
  const double extent = (light.vertices[1] - light.vertices[0]).norm() + (x - light.vertices[0]).norm();
  if (std::abs(side) <= 1e-12 * extent || (side < 0 && !light.two_sided)) return {};
  std::vector<Vec3> p = light.vertices;
  if (side > 0) std::reverse(p.begin(), p.end());
  return p;
}

}  // namespace vdbappear
