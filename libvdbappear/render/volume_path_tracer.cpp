#include "libvdbappear/render/volume_path_tracer.h"

#include "libvdbappear/math/constants.h"
#include "libvdbappear/math/frame.h"
#include "libvdbappear/prefilter/prefiltered_brdf.h"
#include "libvdbappear/math/sampling.h"
#include "libvdbappear/lightgrid/sh_irradiance.h"
#include "libvdbappear/lightgrid/sh_grid_lookup.h"
#include "libvdbappear/lightgrid/sh_lighting.h"
#include "libvdbappear/render/area_light.h"
#include "libvdbappear/render/path_gradients.h"
#include "libvdbappear/subsurface/translucent_object.h"

#include <stdexcept>

namespace vdbappear {

LightStrategy parseLightStrategy(const std::string& name) {
  if (name == "auto") return LightStrategy::kAuto;
  if (name == "mis") return LightStrategy::kMis;
  if (name == "light") return LightStrategy::kLightOnly;
  if (name == "phase") return LightStrategy::kPhaseOnly;
  throw std::invalid_argument("light strategy '" + name + "': expected auto, mis, light or phase");
}

const char* lightStrategyName(LightStrategy strategy) {
  switch (strategy) {
    case LightStrategy::kAuto: return "auto";
    case LightStrategy::kMis: return "mis";
    case LightStrategy::kLightOnly: return "light";
    case LightStrategy::kPhaseOnly: return "phase";
  }
  return "?";
}

VolumePathTracer::VolumePathTracer(const RenderScene& scene, const PathSettings& settings)
    : scene_(scene), settings_(settings), emits_(scene.medium && scene.medium->emits()) {
  if (scene_.sh_lights) clamped_cosine_ = clampedCosineCoefficients(scene_.sh_lights->lmax());
}

// A scattering vertex: in the medium (scattering function) or on a surface, diffuse or glossy
// (a microfacet BRDF in the frame of the geometric normal, surface/microfacet_brdf.h).
struct VolumePathTracer::Vertex {
  Vec3 p;
  Vec3 wi;  // back along the incoming ray
  bool on_surface = false;
  ScatteringFunction medium;
  Vec3 normal;  // surfaces: facing wi
  Rgb albedo;
  const MicrofacetBrdf* brdf = nullptr;  // glossy surfaces
  Frame frame;                           // glossy surfaces: about normal
  // Prefiltered displacement maps: the SVBRDF, in the map's base frame (world, z up), at base
  // position map_x; the cosine is the coarse surface's (docs/displacement.md §8).
  const PrefilteredBrdf* prefiltered = nullptr;
  Point2 map_x;
  Frame map_frame;  // the map's base frame at p (world axes on a plane, the tangent frame on a shell)
  TileStretch map_stretch;  // how the surface lays the tile out there (surface/tile_stretch.h)
  int level = 0;  // the path's level of detail (render/level_of_detail.h)

  bool camera_view = false;  // reached by the camera ray, or by its mirror reflections

  bool lambertian() const { return on_surface && !brdf && !prefiltered; }
  // A direction below a prefiltered map's base horizon, which a curved base shows beyond its
  // terminator and at its silhouette (prefilter/prefiltered_brdf.h).
  bool belowBaseHorizon(const Vec3& w) const { return on_surface && prefiltered && map_frame.n.dot(w) < 0; }
  // Whether the prefiltered map's light reaches where the path came from: light that leaves below
  // the base horizon is shown to the camera only. R_ir's denominator ended the model's paths
  // between coarse cells there, and S_ir restores the original's interreflection over what they
  // carry, so a path that met the map from below its horizon after a bounce would count it twice.
  // For the same reason a path that leaves the map below its horizon sees lights only (trace()).
  bool reflectsBack() const { return camera_view || !belowBaseHorizon(wi); }
  Rgb eval(const Vec3& wo) const {
    if (!on_surface) return medium.eval(wi, wo);
    const double cos_o = std::max(0.0, normal.dot(wo));
    if (brdf) return brdf->eval(frame.toLocal(wi), frame.toLocal(wo)) * cos_o;  // f cos
    if (prefiltered)
      return cos_o > 0 ? Rgb(prefiltered->eval(map_x, map_frame.toLocal(wo), map_frame.toLocal(wi), map_stretch, map_frame.toLocal(normal)) * cos_o) : Rgb(Rgb::Zero());
    return albedo * (cos_o / kPi);  // Lambertian f cos
  }
  // eval, and in a medium each lobe's term W_j f_j in per_lobe (for gradient images).
  Rgb eval(const Vec3& wo, Rgb* per_lobe) const { return on_surface ? eval(wo) : medium.evalLobes(wi, wo, per_lobe); }
  const ScatteringFunction* scattering() const { return on_surface ? nullptr : &medium; }
  double pdf(const Vec3& wo) const {
    if (!on_surface) return medium.pdf(wi, wo);
    if (prefiltered) return prefiltered->pdf(map_x, map_frame.toLocal(wi), map_frame.toLocal(wo));
    return brdf ? brdf->pdf(frame.toLocal(wi), frame.toLocal(wo)) : cosineHemispherePdf(normal.dot(wo));
  }
  // per_lobe (media): each lobe's term W_j f_j at the sampled direction (for gradient images).
  ScatterSample sample(RandomStream& rng, Rgb* per_lobe = nullptr) const {
    const double u_lobe = rng.uniform();
    const Point2 u = rng.uniform2();
    if (!on_surface) return medium.sample(wi, u_lobe, u, per_lobe);
    if (brdf) {
      const BrdfSample s = brdf->sample(frame.toLocal(wi), u_lobe, u);
      return {frame.toWorld(s.wi), s.pdf, s.weight};
    }
    if (prefiltered) {  // f'_low's sampling; its weight f_low |cos theta_i| / pdf moved to the coarse surface's cosine
      const BrdfSample s = prefiltered->sample(map_x, map_frame.toLocal(wi), u_lobe, u, map_stretch, map_frame.toLocal(normal));
      const Vec3 wo = map_frame.toWorld(s.wi);
      if (!(s.pdf > 0)) return {wo, 0, Rgb::Zero()};
      return {wo, s.pdf, s.weight * (std::max(0.0, normal.dot(wo)) / std::abs(s.wi.z()))};
    }
    const Vec3 wo = Frame::fromNormal(normal).toWorld(sampleCosineHemisphere(u));
    const double pdf = cosineHemispherePdf(normal.dot(wo));
    return {wo, pdf, pdf > 0 ? albedo : Rgb(Rgb::Zero())};
  }
  Vec3 origin() const { return p; }
};

double VolumePathTracer::transmittance(const Vec3& p, const Vec3& w, double distance, int level, RandomStream& rng,
                                       MediumLookup* lookup) const {
  const double eps = scene_.ray_epsilon;
  if (scene_.surfaces && scene_.surfaces->occluded(p, w, eps, distance * (1 - 1e-6) - eps, level)) return 0;
  return lookup ? lookup->transmittance(p, w, distance, rng) : 1.0;
}

// Smooth lights under kAuto (Light::isSmooth): phase sampling (or the BRDF's cosine sampling) has
// a pdf proportional to f, so its weight f L / pdf is the albedo times L wherever the light is
// unshadowed, bounded by the light's peak, while light sampling weighs each direction by f / pdf_L.
// Leaving such lights to phase sampling saves a shadow ray per vertex and lowers the variance per
// path besides (measured in docs/rendering.md §7).
bool VolumePathTracer::samplesLight(const Light& light) const {
  if (light.isDelta()) return true;
  switch (settings_.strategy) {
    case LightStrategy::kPhaseOnly: return false;
    case LightStrategy::kAuto: return !light.isSmooth();
    default: return true;
  }
}

double VolumePathTracer::phaseSampledWeight(double phase_pdf, double light_pdf) const {
  if (settings_.strategy == LightStrategy::kLightOnly) return 0;
  return powerHeuristic(phase_pdf, light_pdf);
}

// Next-event estimation: one sample of every light (one shadow ray each), each MIS-weighted against
// the vertex's own sampling. Sampling every light rather than picking one removes the variance of
// the pick: on the SGGX twill under a sun and a sky it cut the time to equal noise 1.46x
// (scripts/bench_render.py). Scenes of many lights would want a pick again.
// With gradients, each light's term also enters the derivatives (path_gradients.h); beta is the
// throughput that reached the vertex.
Rgb VolumePathTracer::sampleDirect(const Vertex& vertex, bool from_grid, RandomStream& rng, MediumLookup* lookup,
                                   const Rgb& beta, PathGradients* gradients) const {
  Rgb L = from_grid ? shGridDirect(vertex, rng, lookup) : Rgb(Rgb::Zero());
  std::array<Rgb, ScatteringFunction::kMaxLobes> per_lobe;
  for (const auto& light : scene_.lights) {
    const Point2 u = rng.uniform2();  // drawn for every light, so streams stay aligned
    if (!samplesLight(*light)) continue;
    if (from_grid && light->isArea()) continue;  // the grid stands for the area lights
    const LightSample ls = light->sample(vertex.p, u);
    if (!(ls.pdf > 0) || (ls.Li == 0).all()) continue;
    const Rgb f = gradients ? vertex.eval(ls.wi, per_lobe.data()) : vertex.eval(ls.wi);
    if ((f == 0).all()) continue;
    const double T = transmittance(vertex.origin(), ls.wi, ls.distance, vertex.level, rng, lookup);
    if (!(T > 0)) continue;
    double weight = 1;
    if (!ls.is_delta && settings_.strategy != LightStrategy::kLightOnly) weight = powerHeuristic(ls.pdf, vertex.pdf(ls.wi));
    const Rgb light_weight = ls.Li * (T * weight / ls.pdf);
    L += f * light_weight;
    if (gradients) gradients->addLightThroughVertex(vertex.scattering(), per_lobe.data(), beta, f, light_weight);
  }
  return L;
}

// The area lights' direct light from the SH grid (dissertation ch. 5), by Funk-Hecke where it has
// a closed form, so with no variance: on a diffuse surface albedo E(n) / pi; in a medium of
// isotropic and HG lobes sum_j W_j sum_l g_j^l B_l(-wi). Otherwise (SGGX, tables, glossy and
// prefiltered surfaces) one direction sampled from the scattering function or BRDF, weight f / pdf
// times the SH radiance. With sh_shadows, times
// the medium's transmittance toward the grid's dominant direction, or along the sampled direction
// where there is one (surfaces do not shadow the grid's light).
Rgb VolumePathTracer::shGridDirect(const Vertex& vertex, RandomStream& rng, MediumLookup* lookup) const {
  const ShGridLookup& grid = *scene_.sh_lights;
  const std::vector<Vec3> coeffs = grid.interpolate(vertex.p, scene_.sh_interpolation);
  Rgb L;
  Vec3 shadow_direction = Vec3::Zero();
  if (vertex.lambertian()) {
    L = vertex.albedo * shIrradiance(coeffs, clamped_cosine_, vertex.normal).array() / kPi;
  } else if (const std::optional<Rgb> closed_form =
                 vertex.on_surface ? std::nullopt : shSingleScattering(vertex.medium, coeffs, grid.lmax(), vertex.wi)) {
    L = *closed_form;  // media only: a glossy surface's vertex holds no scattering function
  } else {
    const ScatterSample s = vertex.sample(rng);
    if (!(s.pdf > 0)) return Rgb::Zero();
    L = s.weight * incidentRadiance(coeffs, grid.lmax(), s.wo).array();
    shadow_direction = s.wo;
  }
  if (!scene_.sh_shadows || !lookup || (L == 0).all()) return L;
  if (shadow_direction.isZero()) shadow_direction = dominantDirection(coeffs);
  return shadow_direction.isZero() ? L : Rgb(L * lookup->transmittance(vertex.origin(), shadow_direction, kInfinity, rng));
}

// Radiance of the environment lights along a ray that left the scene.
Rgb VolumePathTracer::escapedRadiance(const Ray& ray, double prev_pdf, bool unweighted) const {
  Rgb L = Rgb::Zero();
  for (const auto& light : scene_.lights) {
    if (!light->isEnvironment()) continue;
    const Rgb Le = light->radiance(ray.d);
    // A light that next-event estimation leaves alone is reached here alone: weight 1, no pdf needed.
    if (unweighted || !samplesLight(*light)) L += Le;
    else L += Le * phaseSampledWeight(prev_pdf, light->pdf(ray.o, ray.d));
  }
  return L;
}

PathSample VolumePathTracer::trace(Ray ray, RandomStream& rng, MediumLookup* lookup, PathGradients* gradients) const {
  PathSample result;
  if (gradients) gradients->startPath();
  Rgb beta = Rgb::Ones();
  double prev_pdf = 0;  // solid-angle pdf of the direction sampled at the previous vertex
  bool prev_from_grid = false;  // the previous vertex's area light came from the SH grid
  const int max_depth = settings_.max_depth < 0 ? std::numeric_limits<int>::max() : settings_.max_depth;
  const double eps = scene_.ray_epsilon;
  bool prev_specular = false;  // the previous vertex reflected specularly: what the ray reaches is not MIS-weighted
  double mirror_reflectance = 1;  // of the camera ray's mirror reflections so far; 0 once a path scatters otherwise
  // The path left a prefiltered map below its base horizon: only a light, not a surface or a
  // medium, is seen along it (Vertex::reflectsBack says why); a medium's own emission counts as a
  // light (the map's tables hold none of it).
  bool lights_only = false;
  Vertex vertex;  // one per path, refilled at each collision (its scattering function is 1.6 kB)
  vertex.level = pathLevel(scene_.mipmaps, ray, rng);
  for (int depth = 0;; ++depth) {
    const bool camera_ray = depth == 0;
    const bool unweighted = camera_ray || prev_specular;
    std::optional<SurfaceHit> hit;
    if (scene_.surfaces) hit = scene_.surfaces->intersect(ray.o, ray.d, camera_ray ? 0.0 : eps, kInfinity, vertex.level);
    const double t_surface = hit ? hit->t : kInfinity;
    std::optional<double> t_medium;
    if (lookup) {
      // The medium's own light along the ray up to the collision (docs/medium.md §3b): no light
      // samples it, so it is scored here, unweighted, along every ray the path traces.
      Rgb emitted = Rgb::Zero();
      t_medium = lookup->sampleCollision(ray.o, ray.d, t_surface, rng, emits_ ? &emitted : nullptr);
      if (emits_ && (emitted > 0).any()) {
        result.L += beta * emitted;
        if (gradients) gradients->addLight(emitted);
      }
    }

    vertex.wi = -ray.d;
    vertex.on_surface = false;
    if (lights_only && (t_medium || (hit && hit->light < 0))) break;
    if (t_medium) {
      vertex.p = ray(*t_medium);
      if (camera_ray) {
        result.first_cluster = lookup->cluster(vertex.p);
        result.camera_ray_collided = true;
      }
      lookup->scattering(vertex.p, &vertex.medium);
      if (scene_.lobe_scales) scene_.lobe_scales->apply(vertex.medium);
    } else if (hit && hit->light >= 0) {
      const auto& light = static_cast<const AreaLight&>(*scene_.lights[hit->light]);
      const Rgb Le = light.emitted(hit->normal, -ray.d);
      if (prev_from_grid) break;  // its direct light came from the SH grid
      const Rgb Le_weighted = unweighted || !samplesLight(light)
                                  ? Le
                                  : Rgb(Le * phaseSampledWeight(prev_pdf, light.pdf(ray.o, ray(hit->t), hit->normal)));
      result.L += beta * Le_weighted;
      if (gradients) gradients->addLight(Le_weighted);
      break;
    } else if (hit && hit->translucent >= 0) {
      // A translucent object: the dipole's light leaves it (scored like a light's, though
      // next-event estimation never samples it), and its boundary reflects specularly.
      const TranslucentObject& object = *scene_.translucent[std::size_t(hit->translucent)];
      const double cos_theta = hit->normal.dot(-ray.d);
      if (cos_theta <= 0) break;  // reached from inside: the interior is the dipole's
      const double reach = mirror_reflectance > 0 ? cacheReach(mirror_reflectance) : 1.0;
      const Rgb Lo = object.radiance(ray(hit->t), hit->normal, cos_theta, reach);
      result.L += beta * Lo;
      if (gradients) gradients->addLight(Lo);
      const double F = object.specularReflectance(cos_theta);
      if (depth >= max_depth || !(F > 0)) break;
      ++result.scattering_events;
      beta *= F;
      mirror_reflectance *= F;
      if (gradients) gradients->scaleThroughput(F);
      ray = {ray(hit->t) + eps * hit->normal, ray.d - 2 * ray.d.dot(hit->normal) * hit->normal};
      prev_specular = true;
      prev_from_grid = false;
      if (!survivesRoulette(depth, rng, &beta, gradients)) break;
      continue;
    } else if (hit) {
      vertex.on_surface = true;
      vertex.normal = hit->normal.dot(ray.d) < 0 ? hit->normal : Vec3(-hit->normal);
      vertex.p = ray(hit->t) + eps * vertex.normal;
      vertex.albedo = hit->albedo;
      vertex.brdf = hit->brdf >= 0 ? &scene_.brdfs[std::size_t(hit->brdf)] : nullptr;
      if (vertex.brdf) vertex.frame = Frame::fromNormal(vertex.normal);
      vertex.prefiltered = nullptr;
      if (hit->prefiltered >= 0) {
        const PrefilteredPlacement& placement = scene_.prefiltered[std::size_t(hit->prefiltered)];
        vertex.prefiltered = placement.brdf.get();
        const PrefilteredPlacement::MapPoint at = placement.mapPoint(vertex.p, *hit);
        vertex.map_x = at.position;
        vertex.map_frame = at.frame;
        vertex.map_stretch = at.stretch;
        vertex.camera_view = mirror_reflectance > 0;
        if (!vertex.reflectsBack()) break;  // no light leaves toward a path from below the horizon
      }
    } else {
      const Rgb escaped = escapedRadiance(ray, prev_pdf, unweighted);
      result.L += beta * escaped;
      if (gradients) gradients->addLight(escaped);
      break;
    }

    if (depth >= max_depth) break;
    ++result.scattering_events;
    // The grid stands for the area lights inside its box; outside it they are sampled as usual.
    prev_from_grid = scene_.sh_lights && scene_.sh_lights->contains(vertex.p);
    result.L += beta * sampleDirect(vertex, prev_from_grid, rng, lookup, beta, gradients);
    std::array<Rgb, ScatteringFunction::kMaxLobes> per_lobe;
    const ScatterSample s = vertex.sample(rng, gradients ? per_lobe.data() : nullptr);
    if (!(s.pdf > 0) || (s.weight <= 0).all()) break;
    if (gradients) gradients->scatter(vertex.scattering(), per_lobe.data(), beta, s.weight, s.pdf);
    beta *= s.weight;
    prev_pdf = s.pdf;
    prev_specular = false;
    lights_only = vertex.belowBaseHorizon(s.wo);
    mirror_reflectance = 0;
    ray = {vertex.p, s.wo};
    if (!survivesRoulette(depth, rng, &beta, gradients)) break;
  }
  return result;
}

// Russian roulette on the throughput after settings_.roulette_depth events, unbiased.
bool VolumePathTracer::survivesRoulette(int depth, RandomStream& rng, Rgb* beta, PathGradients* gradients) const {
  if (depth + 1 < settings_.roulette_depth) return true;
  const double q = std::min(1.0, beta->maxCoeff());
  if (rng.uniform() >= q) return false;
  *beta /= q;
  if (gradients) gradients->scaleThroughput(1 / q);
  return true;
}

}  // namespace vdbappear
