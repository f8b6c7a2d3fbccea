#include "libvdbappear/prefilter/multi_bounce_effective_brdf.h"

#include "libvdbappear/math/frame.h"
#include "libvdbappear/math/random_stream.h"

#include <stdexcept>

namespace vdbappear {
namespace {

// r(x1, wi, wo) of Eq. (4.16) by one path from x1 seen along wo: at each vertex x_j the light's
// term V(x_j, wi) f(x_j, wi, w_j->j-1) <n, wi>, times the throughput of the vertices before it.
Rgb pathReflectance(const MicroGeometry& geometry, MicroGeometry::Point x, const MicrofacetBrdf& f, const Vec3& wi,
                    const Vec3& wo, int max_vertices, RandomStream& rng) {
  Rgb r = Rgb::Zero(), throughput = Rgb::Ones();
  Vec3 toward_previous = wo;  // w_1->0 := wo
  for (int k = 1; k <= max_vertices; ++k) {
    const Frame frame = Frame::fromNormal(x.normal);
    const Vec3 wo_local = frame.toLocal(toward_previous);
    if (wo_local.z() <= 0) break;  // reached from below its plane: a grazing leak
    const double cos_i = x.normal.dot(wi);
    if (cos_i > 0 && geometry.unoccluded(x, wi)) r += throughput * f.eval(wo_local, frame.toLocal(wi)) * cos_i;
    if (k == max_vertices) break;
    const double u_lobe = rng.uniform();
    const BrdfSample s = f.sample(wo_local, u_lobe, rng.uniform2());
    if (s.pdf <= 0 || (s.weight <= 0).all()) break;
    const Vec3 w_next = frame.toWorld(s.wi);
    const std::optional<MicroGeometry::Point> next = geometry.trace(x, w_next);
    if (!next) break;  // the path leaves the micro-geometry: only the light's direction counts
    throughput *= s.weight;
    toward_previous = -w_next;
    x = *next;
  }
  return r;
}

}  // namespace

EffectiveBrdf multiBounceEffectiveBrdf(const MicroGeometry& geometry, int i0, int j0, int count,
                                       const MicrofacetBrdf& f, const Vec3& wi, const Vec3& wo,
                                       const MultiBounceSettings& settings) {
  const HeightField& field = geometry.field();
  if (count < 1 || i0 < 0 || j0 < 0 || i0 + count > field.cellsX() || j0 + count > field.cellsY() ||
      settings.samples_per_side < 1 || settings.max_vertices < 1)
    throw std::invalid_argument("multiBounceEffectiveBrdf: the patch leaves the height field, or no samples");
  // The base positions draw from effectiveBrdf()'s stream in its order, so that one vertex gives
  // its estimate; each path draws from its own stream.
  RandomStream positions(settings.seed, {i0, j0, count});
  const int n = settings.samples_per_side;
  Rgb numerator = Rgb::Zero();
  double area = 0;
  for (int b = 0; b < n; ++b)
    for (int a = 0; a < n; ++a) {
      const Point2 jitter = positions.uniform2();
      const MicroGeometry::Point p =
          geometry.at(i0 + count * (a + jitter.x()) / n, j0 + count * (b + jitter.y()) / n);
      // A_G(p, wo) of Eq. (4.7), as in effectiveBrdf().
      const double cos_o = p.normal.dot(wo);
      if (cos_o <= 0 || !geometry.unoccluded(p, wo)) continue;
      const double A = cos_o / p.normal.z();
      area += A;
      RandomStream path(settings.seed, {i0, j0, count, a, b, 1});
      numerator += pathReflectance(geometry, p, f, wi, wo, settings.max_vertices, path) * A;
    }
  EffectiveBrdf result;
  result.visible_area = area / (double(n) * n);
  if (area > 0) result.value = numerator / area;
  return result;
}

}  // namespace vdbappear
