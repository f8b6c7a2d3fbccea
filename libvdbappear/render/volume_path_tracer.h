#pragma once
// Unbiased volumetric path tracing (pbrt-v4 §14.2 without spectral MIS, since extinction is grey):
// free flights by delta tracking over the hierarchical majorant, real collisions scatter with the
// voxel's scaled phase function (weight f_s / pdf, which carries the albedo), next-event estimation
// of every light with ratio-tracked shadow rays, and multiple importance sampling (power heuristic) between light
// sampling and phase or BRDF sampling. Surfaces are diffuse; area lights are hit as surfaces;
// translucent objects give the dipole's light and reflect specularly (subsurface/).

#include "libvdbappear/math/random_stream.h"
#include "libvdbappear/render/ray.h"
#include "libvdbappear/render/render_scene.h"

#include <string>
#include <vector>

namespace vdbappear {

// Which estimator reaches non-delta lights: both combined by MIS, light sampling only, or
// phase/BRDF sampling only; kAuto (the default) is MIS except for smooth lights (a constant sky, low
// SH bands: Light::isSmooth), which phase/BRDF sampling alone reaches. All four converge to the same
// image (tested); delta lights are always reached by light sampling.
enum class LightStrategy { kAuto, kMis, kLightOnly, kPhaseOnly };
LightStrategy parseLightStrategy(const std::string& name);  // "auto" | "mis" | "light" | "phase"
const char* lightStrategyName(LightStrategy strategy);

struct PathSettings {
  int max_depth = -1;        // scattering events (medium and surface) per path; -1: unlimited
  int roulette_depth = 4;    // Russian roulette on the throughput after this many events (16, 8, 4,
                             // 2 and 1 measured on the coloured twill: 2 to 8 are best, 16 is 14% slower)
  LightStrategy strategy = LightStrategy::kAuto;
};

struct PathSample {
  Rgb L = Rgb::Zero();
  int first_cluster = -1;    // cluster id of the medium voxel where the camera ray first scatters
  bool camera_ray_collided = false;  // the camera ray had a real collision in the medium
  int scattering_events = 0;
};

class PathGradients;

class VolumePathTracer {
 public:
  VolumePathTracer(const RenderScene& scene, const PathSettings& settings);
  // lookup: this thread's MediumLookup (null when the scene has no medium). gradients: when given,
  // also the derivatives of the path's radiance with respect to the lobe-weight scales, from the
  // same path (render/path_gradients.h; not with an SH light grid).
  PathSample trace(Ray ray, RandomStream& rng, MediumLookup* lookup, PathGradients* gradients = nullptr) const;

 private:
  struct Vertex;
  Rgb sampleDirect(const Vertex& vertex, bool from_grid, RandomStream& rng, MediumLookup* lookup, const Rgb& beta,
                   PathGradients* gradients) const;
  Rgb shGridDirect(const Vertex& vertex, RandomStream& rng, MediumLookup* lookup) const;
  double transmittance(const Vec3& p, const Vec3& w, double distance, int level, RandomStream& rng,
                       MediumLookup* lookup) const;
  // unweighted: a camera ray or one leaving a specular reflection, which light sampling never reaches.
  Rgb escapedRadiance(const Ray& ray, double prev_pdf, bool unweighted) const;
  bool survivesRoulette(int depth, RandomStream& rng, Rgb* beta, PathGradients* gradients) const;
  // Whether next-event estimation samples the light (delta lights always), and the weight of a
  // light it samples when a phase- or BRDF-sampled direction of density phase_pdf reaches it
  // instead (a light it does not sample has weight 1 there).
  bool samplesLight(const Light& light) const;
  double phaseSampledWeight(double phase_pdf, double light_pdf) const;

  const RenderScene& scene_;
  PathSettings settings_;
  bool emits_ = false;  // the medium has an emission grid
  std::vector<double> clamped_cosine_;  // A_l of the SH grid's bands (lightgrid/sh_irradiance.h)
};

}  // namespace vdbappear
