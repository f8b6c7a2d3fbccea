#include "libvdbappear/render/level_of_detail.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/render/surface_scene.h"
#include "libvdbappear/surface/mesh_shell.h"
#include "libvdbappear/surface/sphere_shell.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

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

BaseIntersector sphereBase(const SphereShell& shell, int cells_x, int cells_y) {
  return [shell, cells_x, cells_y](const Ray& ray) -> std::optional<BaseHit> {
    // |o + t d - c|^2 = r^2, the nearest t > 0.
    const Vec3 oc = ray.o - shell.centre;
    const double a = ray.d.squaredNorm(), b = oc.dot(ray.d), c = oc.squaredNorm() - shell.radius * shell.radius;
    const double discriminant = b * b - a * c;
    if (!(discriminant >= 0) || !(a > 0)) return std::nullopt;
    double t = (-b - std::sqrt(discriminant)) / a;
    if (!(t > 0)) t = (-b + std::sqrt(discriminant)) / a;
    if (!(t > 0)) return std::nullopt;
    const Vec3 n = (ray(t) - shell.centre).normalized();
    const double cos_latitude = std::max(1e-6, std::sqrt(std::max(0.0, 1 - n.z() * n.z())));
    const double along_x = 2 * kPi * shell.radius * cos_latitude / (shell.tiles_x * cells_x);
    const double along_y = kPi * shell.radius / (shell.tiles_y * cells_y);
    return BaseHit{t, std::abs(n.dot(ray.d)) / std::sqrt(a), std::sqrt(along_x * along_y)};
  };
}

BaseIntersector meshBase(const MeshShell& shell, int cells_x, int cells_y) {
  auto scene = std::make_shared<SurfaceScene>();
  std::vector<Triangle> triangles;
  auto cell = std::make_shared<std::vector<double>>();  // per base triangle
  const double mean_cell = shell.meanTileWidth() / std::sqrt(double(cells_x) * cells_y);
  for (const UvTriangle& t : shell.base()) {
    triangles.push_back({t.position[0], t.position[1], t.position[2]});
    const double area = 0.5 * (t.position[1] - t.position[0]).cross(t.position[2] - t.position[0]).norm();
    const Point2 d1 = t.uv[1] - t.uv[0], d2 = t.uv[2] - t.uv[0];
    const double cells = 0.5 * std::abs(d1.x() * d2.y() - d2.x() * d1.y()) * shell.tilesX() * shell.tilesY() *
                         double(cells_x) * cells_y;  // the original's cells over the triangle
    cell->push_back(cells > 0 && area > 0 ? std::sqrt(area / cells) : mean_cell);
  }
  scene->addDiffuse(triangles, Rgb::Zero());
  scene->commit();
  return [scene, cell](const Ray& ray) -> std::optional<BaseHit> {
    const std::optional<SurfaceHit> hit = scene->intersect(ray.o, ray.d, 0, std::numeric_limits<double>::infinity());
    if (!hit) return std::nullopt;
    return BaseHit{hit->t, std::abs(hit->normal.dot(ray.d)) / ray.d.norm(), (*cell)[hit->primitive]};
  };
}

namespace {

// The pixel's solid angle spread^2 covers t spread across the view by t spread / cos(theta) along it
// (to first order), `cell` wide cells of the original.
Footprint footprintAt(double t, double spread, double cos_theta, double cell) {
  const double across = t * spread / cell;
  return Footprint{t, across, across / std::sqrt(cos_theta)};
}

}  // namespace

std::optional<Footprint> footprintOn(const MipmapFootprint& mipmap, const Ray& ray) {
  if (mipmap.curved) {  // theta to the curved base's normal where the ray meets it, its cells stretched there
    const std::optional<BaseHit> hit = mipmap.curved(ray);
    if (!hit || !(hit->cos_theta > 1e-12) || !(hit->cell > 0)) return std::nullopt;
    return footprintAt(hit->t, ray.spread, hit->cos_theta, hit->cell);
  }
  const double cos_theta = std::abs(ray.d.z());
  if (!(cos_theta > 1e-12)) return std::nullopt;
  const double t = (mipmap.origin.z() - ray.o.z()) / ray.d.z();
  if (!(t > 0)) return std::nullopt;
  const Vec3 p = ray(t);
  const double x = p.x() - mipmap.origin.x(), y = p.y() - mipmap.origin.y();
  if (x < 0 || y < 0 || x > mipmap.width_x || y > mipmap.width_y) return std::nullopt;
  return footprintAt(t, ray.spread, cos_theta, mipmap.cell);
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
  const LevelBlend blend = blendForFootprint(nearest->factors, at.cells(nearest->levels_by));
  if (blend.lower == blend.upper || !(blend.weight > 0)) return blend.lower;
  return rng.uniform() < blend.weight ? blend.upper : blend.lower;
}

}  // namespace vdbappear
