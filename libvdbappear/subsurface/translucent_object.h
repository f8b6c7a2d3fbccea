#pragma once
// A translucent object as the renderer sees it (docs/subsurface.md): a closed mesh whose light
// leaves by the dipole, L = F_t(eta, w) / F_dt(eta) S(p) / pi (§2.3 of the translucent-caching
// seed), with S from the hierarchical integration of pass 1's irradiance samples, and a smooth
// dielectric boundary that reflects F_r(eta, w) specularly.

#include "libvdbappear/subsurface/dipole.h"
#include "libvdbappear/subsurface/irradiance_octree.h"
#include "libvdbappear/subsurface/translucent_material.h"

#include <vector>

namespace vdbappear {

// Lengths are in units of the shortest diffusion length 1 / sigma_tr (RgbDipole).
struct SubsurfaceSettings {
  double sample_spacing = 0.5;   // longest edge of an irradiance sample's face
  double max_solid_angle = 0.1;  // m of the hierarchy (HierarchySettings)
  double disk_radius = 1;        // R of the split-disk model
  int light_samples = 64;        // per irradiance sample and light, for lights that are not delta
};

class TranslucentObject {
 public:
  TranslucentObject(const TranslucentMaterial& material, std::vector<IrradianceSample> samples,
                    const SubsurfaceSettings& settings);

  // S, grad S and V at p (hierarchical integration, uncached).
  SubsurfaceEstimate estimate(const Vec3& p) const { return octree_.evaluate(p, dipole_, hierarchy_); }
  // Radiance leaving the surface at p toward w, cos_theta = n . w > 0.
  Rgb radiance(const Vec3& p, double cos_theta) const;
  double specularReflectance(double cos_theta) const;

  const TranslucentMaterial& material() const { return material_; }
  const RgbDipole& dipole() const { return dipole_; }
  const IrradianceOctree& octree() const { return octree_; }

 private:
  TranslucentMaterial material_;
  RgbDipole dipole_;
  HierarchySettings hierarchy_;
  IrradianceOctree octree_;
  double F_dt_;
};

}  // namespace vdbappear
