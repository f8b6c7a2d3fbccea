#include "libvdbappear/prefilter/multi_bounce_effective_brdf.h"

#include "libvdbappear/math/frame.h"
#include "libvdbappear/math/random_stream.h"

#include <algorithm>
#include <stdexcept>

namespace vdbappear {
namespace {

// r(x1, wi, wo) of Eq. (4.16) by one path from x1 seen along wo, for every wi of `wis` at once
// (r[k]): at each vertex x_j the light's term V(x_j, wi) f(x_j, wi, w_j->j-1) <n, wi>, times the
// throughput of the vertices before it. The path's directions do not depend on wi.
void pathReflectances(const MicroGeometry& geometry, MicroGeometry::Point x, const PatchScattering& f, const Vec3* wis,
                      std::size_t n, const Vec3& wo, int max_vertices, RandomStream& rng, Rgb* r) {
  std::fill(r, r + n, Rgb::Zero());
  Rgb throughput = Rgb::Ones();
  Vec3 toward_previous = wo;  // w_1->0 := wo
  for (int k = 1; k <= max_vertices; ++k) {
    if (x.normal.dot(toward_previous) <= 0) break;  // reached from below its plane: a grazing leak
    for (std::size_t w = 0; w < n; ++w) {
      const double cos_i = x.normal.dot(wis[w]);
      if (cos_i > 0 && geometry.unoccluded(x, wis[w])) r[w] += throughput * f.eval(x, wis[w], toward_previous) * cos_i;
    }
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
}

// The base positions of effectiveBrdf(), so that one vertex gives its estimate; each path draws from
// its own stream, keyed by its position (not by wi).
EffectiveBrdfSettings positionsOf(const MultiBounceSettings& settings) {
  if (settings.max_vertices < 1) throw std::invalid_argument("multiBounceEffectiveBrdf: no vertices");
  EffectiveBrdfSettings positions;
  positions.samples_per_side = settings.samples_per_side;
  positions.seed = settings.seed;
  return positions;
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
  return visibleAreaAverage(geometry, i0, j0, count, wo, positionsOf(settings), [&](const MicroGeometry::Point& p, int a, int b) {
    RandomStream path(settings.seed, {i0, j0, count, a, b, 1});
    Rgb r;
    pathReflectances(geometry, p, f, &wi, 1, wo, settings.max_vertices, path, &r);
    return r;
  });
}

std::vector<EffectiveBrdf> multiBounceEffectiveBrdfs(const MicroGeometry& geometry, int i0, int j0, int count,
                                                     const PatchScattering& f, const std::vector<Vec3>& wis,
                                                     const Vec3& wo, const MultiBounceSettings& settings) {
  return visibleAreaAverages(geometry, i0, j0, count, wo, positionsOf(settings), wis.size(),
                             [&](const MicroGeometry::Point& p, int a, int b, Rgb* r) {
                               RandomStream path(settings.seed, {i0, j0, count, a, b, 1});
                               pathReflectances(geometry, p, f, wis.data(), wis.size(), wo, settings.max_vertices, path, r);
                             });
}

}  // namespace vdbappear
