#include "libvdbappear/render/area_light.h"

#include "libvdbappear/math/sampling.h"

#include <Eigen/Geometry>

#include <stdexcept>

namespace vdbappear {

AreaLight::AreaLight(std::vector<Triangle> triangles, const Rgb& radiance, bool two_sided)
    : triangles_(std::move(triangles)), radiance_(radiance), two_sided_(two_sided) {
  std::vector<double> areas;
  for (const Triangle& t : triangles_) {
    const Vec3 cross = (t[1] - t[0]).cross(t[2] - t[0]);
    areas.push_back(cross.norm() / 2);
    normals_.push_back(cross.normalized());
    area_ += areas.back();
  }
  if (triangles_.empty() || !(area_ > 0)) throw std::invalid_argument("area light: no triangle with area");
  by_area_ = PiecewiseConstant1D(areas);
}

std::vector<Triangle> AreaLight::fanTriangulate(const std::vector<Vec3>& vertices) {
  if (vertices.size() < 3) throw std::invalid_argument("area light: a polygon needs 3 or more vertices");
  std::vector<Triangle> triangles;
  for (std::size_t i = 1; i + 1 < vertices.size(); ++i) triangles.push_back({vertices[0], vertices[i], vertices[i + 1]});
  return triangles;
}

Rgb AreaLight::emitted(const Vec3& n, const Vec3& w_out) const {
  return two_sided_ || n.dot(w_out) > 0 ? radiance_ : Rgb::Zero();
}

LightSample AreaLight::sample(const Vec3& p, const Point2& u) const {
  double pdf_pick = 0;
  int index = 0;
  const double u_remapped = by_area_.sample(u.x(), &pdf_pick, &index) * by_area_.size() - index;  // reuse u.x
  const Triangle& t = triangles_[index];
  const Point2 b = sampleUniformTriangle(Point2(std::clamp(u_remapped, 0.0, 1.0 - 1e-16), u.y()));
  const Vec3 y = b.x() * t[0] + b.y() * t[1] + (1 - b.x() - b.y()) * t[2];
  const Vec3 to_light = y - p;
  const double r = to_light.norm();
  if (!(r > 0)) return {};
  const Vec3 wi = to_light / r;
  const double pdf_w = pdf(p, y, normals_[index]);
  if (!(pdf_w > 0) || !std::isfinite(pdf_w)) return {};
  return {wi, r, emitted(normals_[index], -wi), pdf_w, false};
}

double AreaLight::pdf(const Vec3& p, const Vec3& y, const Vec3& n) const {
  const Vec3 to_light = y - p;
  const double r2 = to_light.squaredNorm();
  const double cos_light = std::abs(n.dot(to_light)) / std::sqrt(r2);
  return cos_light > 0 ? r2 / (area_ * cos_light) : 0;
}

}  // namespace vdbappear
