#include "libvdbappear/prefilter/multi_bounce_effective_brdf.h"

#include "libvdbappear/math/frame.h"
#include "libvdbappear/math/random_stream.h"

#include <stdexcept>

namespace vdbappear {
namespace {

// r(x1, wi, wo) of Eq. (4.16) by one path from x1 seen along wo: at each vertex x_j the light's
// term V(x_j, wi) f(x_j, wi, w_j->j-1) <n, wi>, times the throughput of the vertices before it.
Rgb pathReflectance(const MicroGeometry& geometry, MicroGeometry::Point x, const PatchScattering& f, const Vec3& wi,
                    const Vec3& wo, int max_vertices, RandomStream& rng) {
  Rgb r = Rgb::Zero(), throughput = Rgb::Ones();
  Vec3 toward_previous = wo;  // w_1->0 := wo
  for (int k = 1; k <= max_vertices; ++k) {
    if (x.normal.dot(toward_previous) <= 0) break;  // reached from below its plane: a grazing leak
    const double cos_i = x.normal.dot(wi);
    if (cos_i > 0 && geometry.unoccluded(x, wi)) r += throughput * f.eval(x, wi, toward_previous) * cos_i;
    if (k == max_vertices) break;
    const double u_lobe = rng.uniform();
    const BrdfSample s = f.sample(x, toward_previous, u_lobe, rng.uniform2());
    if (s.pdf <= 0 || (s.weight <= 0).all()) break;
    const std::optional<MicroGeometry::Point> next = geometry.trace(x, s.wi);
    if (!next) break;  // the path leaves the micro-geometry: only the light's direction counts
    throughput *= s.weight;
    toward_previous = -s.wi;
    x = *next;
  }
  return r;
}

}  // namespace

PatchScattering microfacetScattering(const MicrofacetBrdf& f) {
  PatchScattering s;
  s.eval = [patch = microfacetPatchBrdf(f)](const MicroGeometry::Point& x, const Vec3& wi, const Vec3& wo) {
    return patch(x.x, x.normal, wi, wo);
  };
  s.sample = [f](const MicroGeometry::Point& x, const Vec3& wo, double u_lobe, const Point2& u) {
    const Frame frame = Frame::fromNormal(x.normal);
    BrdfSample sample = f.sample(frame.toLocal(wo), u_lobe, u);  // weight f cos / pdf in the normal's frame
    sample.wi = frame.toWorld(sample.wi);
    return sample;
  };
  return s;
}

EffectiveBrdf multiBounceEffectiveBrdf(const MicroGeometry& geometry, int i0, int j0, int count,
                                       const PatchScattering& f, const Vec3& wi, const Vec3& wo,
                                       const MultiBounceSettings& settings) {
  if (settings.max_vertices < 1) throw std::invalid_argument("multiBounceEffectiveBrdf: no vertices");
  // The base positions of effectiveBrdf(), so that one vertex gives its estimate; each path draws
  // from its own stream.
  EffectiveBrdfSettings positions;
  positions.samples_per_side = settings.samples_per_side;
  positions.seed = settings.seed;
  return visibleAreaAverage(geometry, i0, j0, count, wo, positions, [&](const MicroGeometry::Point& p, int a, int b) {
    RandomStream path(settings.seed, {i0, j0, count, a, b, 1});
    return pathReflectance(geometry, p, f, wi, wo, settings.max_vertices, path);
  });
}

}  // namespace vdbappear
