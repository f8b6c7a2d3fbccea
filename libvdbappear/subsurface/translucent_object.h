#pragma once
// A translucent object as the renderer sees it (docs/subsurface.md): a closed mesh whose light
// leaves by the dipole, L = F_t(eta, w) / (1 - F_dr(1/eta)) S(p) / pi, so that its exitance is S
// (§2.3 of the translucent-caching seed divides by F_dt(eta) instead, docs/subsurface.md §5), with S
// interpolated from pass 2's caches (pass 3, Eq. 3.9) or, where none is valid or no
// cache was made, from the hierarchical integration of pass 1's irradiance samples; and a smooth
// dielectric boundary that reflects F_r(eta, w) specularly.

#include "libvdbappear/subsurface/dipole.h"
#include "libvdbappear/subsurface/illuminance_cache.h"
#include "libvdbappear/subsurface/irradiance_octree.h"
#include "libvdbappear/subsurface/translucent_material.h"

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

namespace vdbappear {

// Lengths are in units of the shortest diffusion length 1 / sigma_tr (RgbDipole).
struct SubsurfaceSettings {
  double sample_spacing = 0.5;   // longest edge of an irradiance sample's face
  double max_solid_angle = 0.1;  // m of the hierarchy (HierarchySettings)
  double disk_radius = 1;        // R of the split-disk model
  int light_samples = 64;        // per irradiance sample and light, for lights that are not delta
  // The cache (pass 2): the seed's error bound a, relative to S here (cacheRadius); 0: no cache.
  double cache_error = 0.03;
  double min_cache_radius = 0.1;  // clamps of the validity radius r_k
  double max_cache_radius = 2;
  double min_normal_cos = 0.9;    // a cache serves points whose normal is within 26 degrees of its own
};

class TranslucentObject {
 public:
  TranslucentObject(const TranslucentMaterial& material, std::vector<IrradianceSample> samples,
                    const SubsurfaceSettings& settings);

  // S, grad S and V at p (hierarchical integration, uncached).
  SubsurfaceEstimate estimate(const Vec3& p) const { return octree_.evaluate(p, dipole_, hierarchy_); }
  // S at p with outward normal n: from the cache where one is valid (within reach times its
  // radius: IlluminanceCache, cacheReach), else by estimate (counted).
  Rgb illuminance(const Vec3& p, const Vec3& n, double reach = 1) const;
  // Radiance leaving the surface at p (outward normal n) toward w, cos_theta = n . w > 0; its
  // cosine-weighted integral over the outside hemisphere is S (tested).
  Rgb radiance(const Vec3& p, const Vec3& n, double cos_theta, double reach = 1) const;
  double specularReflectance(double cos_theta) const;

  // Pass 2's caches; before any render (the object is read-only while rendering).
  void setCache(std::shared_ptr<const IlluminanceCache> cache) { cache_ = std::move(cache); }
  const IlluminanceCache* cache() const { return cache_.get(); }
  // Shading points that found no valid cache and were integrated instead, since construction.
  std::uint64_t uncachedLookups() const { return uncached_lookups_.load(std::memory_order_relaxed); }
  // Pass 1's time (irradiance samples), as measured by whoever ran it.
  void setPass1Seconds(double seconds) { pass1_seconds_ = seconds; }
  double pass1Seconds() const { return pass1_seconds_; }

  const TranslucentMaterial& material() const { return material_; }
  const RgbDipole& dipole() const { return dipole_; }
  const IrradianceOctree& octree() const { return octree_; }

 private:
  TranslucentMaterial material_;
  RgbDipole dipole_;
  HierarchySettings hierarchy_;
  IrradianceOctree octree_;
  double F_dt_outside_;  // 1 - F_dr(1/eta): int F_t(eta, w) cos dw / pi over the outside hemisphere
  std::shared_ptr<const IlluminanceCache> cache_;
  mutable std::atomic<std::uint64_t> uncached_lookups_{0};
  double pass1_seconds_ = 0;
};

}  // namespace vdbappear
