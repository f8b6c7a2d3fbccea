#pragma once
// A uniformly emitting polygonal light: triangles (a quad is two) of one radiance L. One-sided by
// default: it emits toward the side of its counter-clockwise normal n = (v1 - v0) x (v2 - v0);
// two-sided lights emit L on both sides. Sampled uniformly by area (pbrt-v4 §12.3.2), the density
// converted to solid angle: pdf(wi) = r^2 / (A |cos theta_light|).

#include "libvdbappear/math/piecewise_constant.h"
#include "libvdbappear/math/triangle.h"
#include "libvdbappear/render/light.h"

#include <array>
#include <vector>

namespace vdbappear {

class AreaLight final : public Light {
 public:
  AreaLight(std::vector<Triangle> triangles, const Rgb& radiance, bool two_sided);
  // A polygon given by its vertices in counter-clockwise order, fan-triangulated (convex polygons).
  static std::vector<Triangle> fanTriangulate(const std::vector<Vec3>& vertices);

  bool isDelta() const override { return false; }
  bool isArea() const override { return true; }
  LightSample sample(const Vec3& p, const Point2& u) const override;
  // Density of sample(p) over solid angle at light point y with unit normal n. Light's pdf(p, wi)
  // stays visible beside it (0: an area light's density needs the point the direction hits).
  using Light::pdf;
  double pdf(const Vec3& p, const Vec3& y, const Vec3& n) const;
  // Radiance leaving the light toward w_out (a unit vector from the surface) at a point with unit normal n.
  Rgb emitted(const Vec3& n, const Vec3& w_out) const;

  const std::vector<Triangle>& triangles() const { return triangles_; }
  double area() const { return area_; }

 private:
  std::vector<Triangle> triangles_;
  std::vector<Vec3> normals_;
  PiecewiseConstant1D by_area_;
  double area_ = 0;
  Rgb radiance_;
  bool two_sided_;
};

}  // namespace vdbappear
