#include "libvdbappear/surface/sphere_shell.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/surface/height_field_mesh.h"

#include <algorithm>
#include <cmath>

namespace vdbappear {

SphereShell SphereShell::ofTiles(const Vec3& centre, double size, int tiles_x, int tiles_y) {
  return {centre, size * tiles_x / (2 * kPi), tiles_x, tiles_y};
}

namespace {

struct Angles {
  double sin_theta, cos_theta, sin_phi, cos_phi;  // theta from the north pole, phi the longitude
};

Angles anglesOf(const SphereShell& shell, double u, double v) {
  const double theta = kPi * (1 - v / shell.tiles_y), phi = 2 * kPi * u / shell.tiles_x;
  return {std::sin(theta), std::cos(theta), std::sin(phi), std::cos(phi)};
}

}  // namespace

Vec3 SphereShell::normal(double u, double v) const {
  const Angles a = anglesOf(*this, u, v);
  return {a.sin_theta * a.cos_phi, a.sin_theta * a.sin_phi, a.cos_theta};
}

Frame SphereShell::frame(double u, double v) const {
  const Angles a = anglesOf(*this, u, v);
  const Vec3 east(-a.sin_phi, a.cos_phi, 0);
  const Vec3 north(-a.cos_theta * a.cos_phi, -a.cos_theta * a.sin_phi, a.sin_theta);
  return {east, north, Vec3(a.sin_theta * a.cos_phi, a.sin_theta * a.sin_phi, a.cos_theta)};
}

TileStretch SphereShell::stretch(double v) const {
  const double sin_theta = anglesOf(*this, 0, v).sin_theta;  // cos latitude
  return TileStretch::diagonal(std::max(sin_theta, 1e-6), double(tiles_x) / (2 * tiles_y));
}

Point2 SphereShell::tileCoordinates(const Vec3& p) const {
  const Vec3 d = (p - centre).normalized();
  double phi = std::atan2(d.y(), d.x());
  if (phi < 0) phi += 2 * kPi;
  const double theta = std::acos(std::clamp(d.z(), -1.0, 1.0));
  return {phi / (2 * kPi) * tiles_x, (1 - theta / kPi) * tiles_y};
}

RigidMotion SphereShell::turn(int a) const {
  const double phi = 2 * kPi * a / tiles_x;
  Mat3 rotation;
  rotation << std::cos(phi), -std::sin(phi), 0, std::sin(phi), std::cos(phi), 0, 0, 0, 1;
  return {rotation, centre - rotation * centre};
}

std::vector<Triangle> shellTileTriangles(const HeightField& field, const SphereShell& shell, double height_scale,
                                         int a, int b) {
  std::vector<Triangle> triangles;
  triangles.reserve(std::size_t(2) * field.cellsX() * field.cellsY());
  for (int j = 0; j < field.cellsY(); ++j)
    for (int i = 0; i < field.cellsX(); ++i)
      for (Triangle t : cellTriangles(field, i, j)) {
        for (Vec3& p : t) p = shell.point(a + p.x() / field.cellsX(), b + p.y() / field.cellsY(), height_scale * p.z());
        triangles.push_back(t);
      }
  return triangles;
}

std::vector<Triangle> shellTriangles(const HeightField& field, const SphereShell& shell, double height_scale) {
  std::vector<Triangle> triangles;
  triangles.reserve(std::size_t(2) * field.cellsX() * field.cellsY() * shell.tiles_x * shell.tiles_y);
  for (int b = 0; b < shell.tiles_y; ++b)
    for (int a = 0; a < shell.tiles_x; ++a) {
      const std::vector<Triangle> tile = shellTileTriangles(field, shell, height_scale, a, b);
      triangles.insert(triangles.end(), tile.begin(), tile.end());
    }
  return triangles;
}

}  // namespace vdbappear
